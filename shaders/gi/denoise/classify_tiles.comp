#version 460
#extension GL_GOOGLE_include_directive : require
// gi.denoise.classify_tiles: one workgroup per 16x16 tile marks whether any
// pixel of it has a surface. Every later denoiser pass skips the empty
// tiles (sky) after one fetch (REBLUR's tile classification). On the way
// it packs each pixel's surface into the denoiser's own image (viewZ bits;
// octahedral normal and roughness, shared/packing.glsl's
// packNormalRoughness; viewZ 0 where the pixel has no usable surface): the
// later passes' taps read depth, normal and roughness in one 8-byte load
// instead of the engine's two images.
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "shared/packing.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 0, binding = 3, r16f) writeonly uniform image2D gOut_Tiles;
layout(set = 0, binding = 4, rg32ui) writeonly uniform uimage2D gOut_Surface;

shared uint anySurface;

void main() {
  if (gl_LocalInvocationIndex == 0u) anySurface = 0u;
  barrier();
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (insideFull(pixel)) {
    float roughness;
    Surface x = gbufferSurfaceRoughness(pixel, roughness);
    if (x.viewZ > 0.0f) atomicOr(anySurface, 1u);
    imageStore(gOut_Surface, pixel,
               uvec4(floatBitsToUint(max(x.viewZ, 0.0f)), packNormalRoughness(x.normal, roughness), 0u, 0u));
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) imageStore(gOut_Tiles, ivec2(gl_WorkGroupID.xy), vec4(float(anySurface)));
}
