#version 460
#extension GL_GOOGLE_include_directive : require
// gi.denoise.blur: REBLUR's blur, the spatial kernel of
// gi/denoise/spatial_filter.glsl (shared with gi.denoise.post_blur, which
// runs it again at a smaller radius), for every signal of the dispatch
// from one load of the pixel's surface: over the history-fixed signal (in
// the signal's history image) at gi.denoise.blur_radius (scaled as
// blurRadius says) into the accumulation image, which post-blur reads.
#include "gi/gi_common.glsl"
#define DENOISE_READS_TILES
#include "gi/denoise/denoise_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

DENOISE_SLOT_IMAGES(readonly, gIn_Filtered, 20)
DENOISE_SLOT_IMAGES(readonly, gIn_Signal, 24)
DENOISE_SLOT_IMAGES(writeonly, gOut_Filtered, 28)
DENOISE_SLOT_LOAD(gIn_Filtered)
DENOISE_SLOT_LOAD(gIn_Signal)
DENOISE_SLOT_STORE(gOut_Filtered)

#include "gi/denoise/spatial_filter.glsl"

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  float roughness;
  Surface x = denoiseSurfaceRoughness(pixel, roughness);
  bool surface = !tileEmpty(pixel) && x.viewZ > 0.0f;
  for (uint slot = 0u; slot < gSignals.count; ++slot)
    gOut_FilteredStore(slot, pixel,
                       surface ? roundedToHalf(spatialFilter(slot, pixel, x, roughness, gIn_SignalAt(slot, pixel).w))
                               : vec4(0.0f));
}
