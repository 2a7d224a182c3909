#version 460
#extension GL_GOOGLE_include_directive : require
// gi.denoise.classify_tiles: one workgroup per 16x16 tile marks whether any
// pixel of it has a surface. Every later denoiser pass skips the empty
// tiles (sky) after one fetch (REBLUR's tile classification).
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 0, binding = 3, r16f) writeonly uniform image2D gOut_Tiles;

shared uint anySurface;

void main() {
  if (gl_LocalInvocationIndex == 0u) anySurface = 0u;
  barrier();
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (insideFull(pixel) && gbufferDepth(pixel) > 0.0f) atomicOr(anySurface, 1u);
  barrier();
  if (gl_LocalInvocationIndex == 0u) imageStore(gOut_Tiles, ivec2(gl_WorkGroupID.xy), vec4(float(anySurface)));
}
