#version 460
#extension GL_GOOGLE_include_directive : require
// gi.store_history: this frame's depth and normals, packed into 8 bytes a
// pixel, for the next frame: gathering reconstructs last frame's surfaces
// from them, and reprojection tests that a surface is the one it was. A
// pixel without a usable surface is stored as background, so the next frame
// finds no history there. Also this frame's depth alone, for the visibility
// marches (gi/screen_trace.glsl).
#include "gi/gi_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

#include "gi/gbuffer.glsl"

layout(set = 0, binding = 3, rg32ui) writeonly uniform uimage2D gOut_Surface;
layout(set = 0, binding = 4, r32f) writeonly uniform image2D gOut_MarchDepth;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  Surface surface = gbufferSurface(pixel);
  uint packedNormal = surface.viewZ > 0.0f ? packNormalOct32(surface.normal) : 0u;
  imageStore(gOut_Surface, pixel, uvec4(floatBitsToUint(surface.viewZ), packedNormal, 0u, 0u));
  // The depth alone (a surface whose normal is unusable still blocks rays).
  imageStore(gOut_MarchDepth, pixel, vec4(gbufferDepth(pixel), 0.0f, 0.0f, 0.0f));
}
