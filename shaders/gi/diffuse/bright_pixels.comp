#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.bright_pixels: the first step of the bright-pixel pyramid
// (the Jitter gi pass's diffuse ReSTIR): each 2x2 tile of the previous composited frame keeps its
// brightest pixel, as (brightness, pixel x, pixel y, 1), or 0 when the tile
// is all background. gi.diffuse.bright_pixels_reduce repeats the step until
// a handful of the frame's brightest pixels remain.
#include "gi/gi_common.glsl"
#include "gi/diffuse/diffuse_common.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4, rgba16f) readonly uniform image2D gPrev_Composite;
layout(set = 0, binding = 5, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 6, rgba32f) writeonly uniform image2D gOut_Brightest;

void main() {
  ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
  // The level covers the render size, which may be less than the image.
  if (!all(lessThan(tile, (ivec2(fullSize()) + 1) / 2))) return;
  vec4 best = vec4(0.0f);
  for (int i = 0; i < 4; ++i) {
    ivec2 pixel = tile * 2 + ivec2(i & 1, i >> 1);
    if (!insideFull(pixel)) continue;
    if (uintBitsToFloat(imageLoad(gPrev_Surface, pixel).x) <= 0.0f) continue;  // background: no surface sends light
    float brightness = targetBrightness(sanitizeRadiance(imageLoad(gPrev_Composite, pixel).xyz), gIn_DiffuseConstants.diffuse.targetFunction);
    if (brightness > best.x) best = vec4(brightness, vec2(pixel), 1.0f);
  }
  imageStore(gOut_Brightest, tile, best);
}
