#version 460
#extension GL_GOOGLE_include_directive : require
// gi.specular.validation: the branch's validation view, for --dump-stages
// only (never in a timed frame): each reservoir's confidence M and its
// sample's hit distance (world units; the environment counts as 10^4), so a
// user sees where reuse found history and how far reflections reach.
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 5, rgba32ui) readonly uniform uimage2D gIn_Reservoir1;
layout(set = 0, binding = 6, r32f) writeonly uniform image2D gOut_M;
layout(set = 0, binding = 7, r32f) writeonly uniform image2D gOut_HitDistance;

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideHalf(halfPixel)) return;
  Reservoir r = unpackReservoir(imageLoad(gIn_Reservoir0, halfPixel), imageLoad(gIn_Reservoir1, halfPixel));
  Surface x = gbufferSurface(reservoirSurfacePixel(halfPixel));
  float hitDistance = 0.0f;
  if (x.viewZ > 0.0f && reservoirHasSample(r))
    hitDistance = reservoirIsEnvironment(r) ? 1.0e4f : distance(r.position, x.position);
  imageStore(gOut_M, halfPixel, vec4(r.M));
  imageStore(gOut_HitDistance, halfPixel, vec4(hitDistance));
}
