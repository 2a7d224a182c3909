// The queues of work a pass leaves to a pass of its own, so that the rays
// of one purpose are traced together (gi.diffuse.gather ->
// gi.diffuse.world_candidates, gi.specular.trace -> gi.specular.world_trace:
// half-resolution pixels, each as x | y << 16; gi.diffuse.spatial_reuse ->
// gi.diffuse.neighbour_visibility: slot indices). A storage buffer of
// uints: a count, then the entries; the library clears the count before
// the writer runs. The writer declares it as gOut_WorldQueue and defines
// WORLD_QUEUE_APPEND, the reader as gIn_WorldQueue and defines
// WORLD_QUEUE_READ, before including this (the reader after
// gi/world_ray_count.glsl: the entries it takes up are counted).
#ifndef BOUNCE_GI_WORLD_QUEUE_GLSL
#define BOUNCE_GI_WORLD_QUEUE_GLSL

#ifdef WORLD_QUEUE_APPEND
#extension GL_KHR_shader_subgroup_ballot : require
// Appends an entry (one atomic per subgroup: the entries of one subgroup's
// invocations stay together, in lane order).
void enqueue(uint entry) {
  uvec4 lanes = subgroupBallot(true);
  uint base = 0u;
  if (subgroupElect()) base = atomicAdd(gOut_WorldQueue.items[0], subgroupBallotBitCount(lanes));
  uint slot = subgroupBroadcastFirst(base) + subgroupBallotExclusiveBitCount(lanes);
  gOut_WorldQueue.items[1u + slot] = entry;
}

void enqueuePixel(ivec2 halfPixel) { enqueue(uint(halfPixel.x) | (uint(halfPixel.y) << 16)); }
#endif

#ifdef WORLD_QUEUE_READ
// This invocation's number, and how many the dispatch has: a workgroup's
// invocations take consecutive entries, so the entries a writer's subgroup
// appended together (neighbouring pixels) go to one subgroup here, whose
// rays then start close together and walk the same nodes. (Numbered by
// rows of the dispatch instead, a 32-wide subgroup of an 8x8 group took
// four runs of eight entries from four places in the queue.) Every
// invocation has its own number below queueInvocations().
uint queueInvocation() {
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  return group * (gl_WorkGroupSize.x * gl_WorkGroupSize.y) + gl_LocalInvocationIndex;
}
uint queueInvocations() { return gl_NumWorkGroups.x * gl_NumWorkGroups.y * gl_WorkGroupSize.x * gl_WorkGroupSize.y; }

// How many entries the queue holds; the first invocation of the dispatch
// also counts them as taken up by this pass (gi/world_ray_count.glsl), so
// the frame's counts give the pass's rays per entry.
uint queuedCount() {
  uint count = gIn_WorldQueue.items[0];
  if (gl_GlobalInvocationID.x == 0u && gl_GlobalInvocationID.y == 0u) countQueuedEntries(count);
  return count;
}
uint queuedEntry(uint index) { return gIn_WorldQueue.items[1u + index]; }

// The pixel of this invocation's queue entry (invocation i takes entry i);
// false past the end.
bool queuedPixel(out ivec2 halfPixel) {
  halfPixel = ivec2(0);
  uint index = queueInvocation();
  if (index >= queuedCount()) return false;
  uint entry = queuedEntry(index);
  halfPixel = ivec2(entry & 0xffffu, entry >> 16);
  return true;
}
#endif

#endif
