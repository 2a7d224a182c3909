#version 460
#extension GL_GOOGLE_include_directive : require
// gi.store_history: this frame's depth, normals and material ids (their low
// 8 bits; 0 where the engine gave none), packed into 8 bytes a pixel, for
// the next frame: gathering reconstructs last frame's surfaces from them,
// and reprojection tests that a surface is the one it was (the denoiser's
// temporal passes also read this frame's material id here). A
// pixel without a usable surface is stored as background, so the next frame
// finds no history there. Also this frame's depth alone, for the visibility
// marches (gi/screen_trace.glsl).
#include "gi/gi_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

#include "gi/gbuffer.glsl"

layout(set = 0, binding = 3, rg32ui) writeonly uniform uimage2D gOut_Surface;
layout(set = 0, binding = 4, r32f) writeonly uniform image2D gOut_MarchDepth;
// Any unsigned-integer format; read only where gIn_Frame says it was given.
layout(set = 0, binding = 5) uniform usampler2D gIn_MaterialId;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  Surface surface = gbufferSurface(pixel);
  uint material = gIn_Frame.frame.hasMaterialId != 0u ? texelFetch(gIn_MaterialId, pixel, 0).x : 0u;
  uint packedNormal = surface.viewZ > 0.0f ? packNormalMaterial(surface.normal, material) : 0u;
  imageStore(gOut_Surface, pixel, uvec4(floatBitsToUint(surface.viewZ), packedNormal, 0u, 0u));
  // The depth alone (a surface whose normal is unusable still blocks rays).
  imageStore(gOut_MarchDepth, pixel, vec4(gbufferDepth(pixel), 0.0f, 0.0f, 0.0f));
}
