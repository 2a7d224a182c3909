#version 460
#extension GL_GOOGLE_include_directive : require
// gi.denoise.SIGNAL.blur and gi.denoise.SIGNAL.post_blur (one shader, two
// passes, as REBLUR's): the spatial kernel of gi/denoise/spatial_filter.glsl.
// Blur runs over the history-fixed signal at gi.denoise.blur_radius (scaled
// as blurRadius says); post-blur over blur's output at
// post_blur_radius_scale of that, and its output is next frame's history
// for temporal accumulation and what temporal stabilisation reads.
#include "gi/gi_common.glsl"
#define DENOISE_READS_TILES
#include "gi/denoise/denoise_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 5, rgba16f) readonly uniform image2D gIn_Filtered;
layout(set = 0, binding = 6, rgba16f) readonly uniform image2D gIn_Signal;
layout(set = 0, binding = 7, rgba16f) writeonly uniform image2D gOut_Filtered;

#include "gi/denoise/spatial_filter.glsl"

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  imageStore(gOut_Filtered, pixel, roundedToHalf(spatialFilter(pixel)));
}
