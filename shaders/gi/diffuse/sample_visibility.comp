#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.sample_visibility: one any-hit ray through the scene bridge per
// half-resolution reservoir, from its own surface to its sample, after
// reuse (gi.diffuse.visibility hybrid, with a bridge that traces). A sample
// hidden from the reservoir's surface is dropped (W = 0; M stays: the
// candidates were seen), here and in the history the next frame starts
// from, as ReSTIR DI's visibility reuse does. The resolve then trusts this
// verdict where its own screen-space march cannot decide, so the world
// rays are one per reservoir instead of one per sample per full-resolution
// pixel (16 times fewer); a sample visible from the reservoir's surface but
// hidden from a pixel next to it, where the march cannot tell, leaks.
// The pass whose counters its world rays add to (gi/world_ray_count.glsl).
#define WORLD_RAY_PASS kWorldRayPassSampleVisibility
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 5, rgba32ui) uniform uimage2D gInOut_Reservoir1;

#include "gi/scene_bridge.glsl"
#include "gi/world_rays.glsl"

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideHalf(halfPixel) || !kSceneBridgeTraces) return;
  uvec4 first = imageLoad(gIn_Reservoir0, halfPixel);
  uvec4 second = imageLoad(gInOut_Reservoir1, halfPixel);
  Reservoir r = unpackReservoir(first, second);
  if (!reservoirHasSample(r)) return;
  Surface x = gbufferSurface(reservoirSurfacePixel(halfPixel));
  if (x.viewZ <= 0.0f) return;
  if (worldSeesSample(r, x, kWorldRaysSampleVisibility)) return;
  r.W = 0.0f;
  r.flags &= ~kReservoirHasSample;
  packReservoir(r, first, second);
  imageStore(gInOut_Reservoir1, halfPixel, second);
}
