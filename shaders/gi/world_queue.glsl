// The queue of pixels whose world rays a pass leaves to a pass of its own
// (gi.diffuse.gather -> gi.diffuse.world_candidates, gi.specular.trace ->
// gi.specular.world_trace): a storage buffer of uints, a count and then
// each half-resolution pixel as x | y << 16; the library clears the count
// each frame. The writer declares it as gOut_WorldQueue and defines
// WORLD_QUEUE_APPEND, the reader as gIn_WorldQueue and defines
// WORLD_QUEUE_READ, before including this.
#ifndef BOUNCE_GI_WORLD_QUEUE_GLSL
#define BOUNCE_GI_WORLD_QUEUE_GLSL

#ifdef WORLD_QUEUE_APPEND
#extension GL_KHR_shader_subgroup_ballot : require
// Appends halfPixel (one atomic per subgroup).
void enqueuePixel(ivec2 halfPixel) {
  uvec4 lanes = subgroupBallot(true);
  uint base = 0u;
  if (subgroupElect()) base = atomicAdd(gOut_WorldQueue.items[0], subgroupBallotBitCount(lanes));
  uint slot = subgroupBroadcastFirst(base) + subgroupBallotExclusiveBitCount(lanes);
  gOut_WorldQueue.items[1u + slot] = uint(halfPixel.x) | (uint(halfPixel.y) << 16);
}
#endif

#ifdef WORLD_QUEUE_READ
// The pixel of this invocation's queue entry, for a pass dispatched over
// the half-resolution size (invocation i takes entry i); false past the end.
bool queuedPixel(out ivec2 halfPixel) {
  halfPixel = ivec2(0);
  uint index = gl_GlobalInvocationID.y * uint(halfSize().x) + gl_GlobalInvocationID.x;
  if (gl_GlobalInvocationID.x >= uint(halfSize().x) || index >= gIn_WorldQueue.items[0]) return false;
  uint entry = gIn_WorldQueue.items[1u + index];
  halfPixel = ivec2(entry & 0xffffu, entry >> 16);
  return true;
}
#endif

#endif
