#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.neighbour_visibility: the visibility tests gi.diffuse.spatial_reuse
// queued, one any-hit ray through the scene bridge per invocation: does the
// neighbour in the test's slot see the sample the pixel chose? A neighbour
// that does not has its M negated in the slot, for
// gi.diffuse.spatial_normalize. Dispatched over the half-resolution size;
// the queue can hold several tests per pixel, so each invocation takes
// every queueInvocations()-th entry from its own on (gi/world_queue.glsl).
// The pass whose counters its world rays add to (gi/world_ray_count.glsl).
#define WORLD_RAY_PASS kWorldRayPassNeighbourVisibility
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "gi/diffuse/diffuse_common.glsl"
#include "gi/diffuse/reuse_visibility.glsl"
#include "gi/diffuse/neighbour_tests.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 5, rgba32ui) readonly uniform uimage2D gIn_Reservoir1;
layout(set = 0, binding = 6, std430) buffer NeighbourTests { uvec2 items[]; } gInOut_NeighbourTests;
layout(set = 0, binding = 7, std430) readonly buffer WorldQueue { uint items[]; } gIn_WorldQueue;
#define WORLD_QUEUE_READ
#include "gi/world_queue.glsl"

void main() {
  // Each entry is taken by exactly one invocation (queueInvocation numbers
  // every invocation of the dispatch once and the stride is their count):
  // two turning one verdict would cancel (they once did, when invocations
  // past the half-resolution size shared numbers with others).
  if (!kSceneBridgeTraces || params.slotsPerPixel == 0u) return;
  uint count = queuedCount();
  for (uint index = queueInvocation(); index < count; index += queueInvocations()) {
    uint slot = queuedEntry(index);
    ivec2 halfPixel = ivec2(indexToPixel(slot / params.slotsPerPixel, uint(halfSize().x)));
    uvec2 test = gInOut_NeighbourTests.items[slot];
    ivec2 neighbourHalf = ivec2(test.x & 0xffffu, test.x >> 16);
    Reservoir chosen = unpackReservoir(imageLoad(gIn_Reservoir0, halfPixel), imageLoad(gIn_Reservoir1, halfPixel));
    Surface neighbour = gbufferSurface(reservoirSurfacePixel(neighbourHalf));
    if (!neighbourSeesSample(chosen, neighbour))
      gInOut_NeighbourTests.items[slot].y = floatBitsToUint(-uintBitsToFloat(test.y));
  }
}
