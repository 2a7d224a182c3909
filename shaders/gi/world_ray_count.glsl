// World rays counted by purpose and by pass: every ray the library casts
// through the scene bridge adds one to its purpose's counter (the ray
// budget, docs/gi-settings.md "World rays") in the counters of the pass
// that cast it (so bounce bench can give each pass's rays per second), and
// the bridge counts the shadow rays it casts to light what the library's
// rays hit. Compiled as GLSL and C++ (the purposes and passes); the
// counters are a storage buffer the library clears at the start of each
// frame and reads back when the frame is collected
// (gi::FrameResults::worldRays). A shader that includes this file defines
// WORLD_RAY_PASS, its pass's number below, first.
#ifndef BOUNCE_GI_WORLD_RAY_COUNT_GLSL
#define BOUNCE_GI_WORLD_RAY_COUNT_GLSL

#include "shared/lang.glsl"

#ifdef __cplusplus
namespace bounce::shared {
#endif

const uint kWorldRaysDiffuseCandidates = 0u;  // gi.diffuse.gather: closest-hit ray candidates
const uint kWorldRaysSkyReuse = 1u;           // gi.diffuse.spatial_reuse: is the sky open from a neighbour?
const uint kWorldRaysReuseVisibility = 2u;    // temporal and spatial reuse, gi.diffuse.reuse_visibility (unbiased)
const uint kWorldRaysSampleVisibility = 3u;   // gi.diffuse.sample_visibility: each reservoir's sample
const uint kWorldRaysResolveVisibility = 4u;  // gi.diffuse.resolve with gi.diffuse.visibility world
const uint kWorldRaysSpecular = 5u;           // gi.specular.trace: rays screen space cannot finish
const uint kWorldRaysCacheUpdate = 6u;        // gi.cache.update
const uint kWorldRaysHitShadows = 7u;         // the bridge's shadow rays at hits (sceneDirectRadiance)
const uint kWorldRayPurposes = 8u;
// The passes that cast world rays (gi::worldRayPassName gives their names).
const uint kWorldRayPassGather = 0u;               // gi.diffuse.gather
const uint kWorldRayPassWorldCandidates = 1u;      // gi.diffuse.world_candidates
const uint kWorldRayPassTemporalReuse = 2u;        // gi.diffuse.temporal_reuse
const uint kWorldRayPassSpatialReuse = 3u;         // gi.diffuse.spatial_reuse
const uint kWorldRayPassNeighbourVisibility = 4u;  // gi.diffuse.neighbour_visibility
const uint kWorldRayPassSampleVisibility = 5u;     // gi.diffuse.sample_visibility
const uint kWorldRayPassResolve = 6u;              // gi.diffuse.resolve
const uint kWorldRayPassSpecularTrace = 7u;        // gi.specular.trace
const uint kWorldRayPassSpecularWorldTrace = 8u;   // gi.specular.world_trace
const uint kWorldRayPassCacheUpdate = 9u;          // gi.cache.update
const uint kWorldRayPasses = 10u;
// Each purpose has this many counters (summed on readback), so the atomics
// of a frame's workgroups spread over several addresses instead of queueing on one.
const uint kWorldRayCounterCopies = 16u;
// After the ray counters, one word per pass: the entries of its world
// queue (gi/world_queue.glsl) the pass took up in the frame, 0 for passes
// without a queue; rays per entry show that a pass traces only its list.
const uint kWorldRayQueuedCounters = kWorldRayPasses * kWorldRayPurposes * kWorldRayCounterCopies;
const uint kWorldRayCounterWords = kWorldRayQueuedCounters + kWorldRayPasses;

#ifdef __cplusplus
}  // namespace bounce::shared
#else

#extension GL_KHR_shader_subgroup_ballot : require

#ifndef WORLD_RAY_PASS
#error "define WORLD_RAY_PASS (the pass's kWorldRayPass... number) before including gi/world_ray_count.glsl"
#endif

#define WORLD_RAY_COUNT_BINDING 31
layout(set = 0, binding = WORLD_RAY_COUNT_BINDING, std430) buffer WorldRayCounts { uint items[]; } gOut_WorldRays;

// Adds the rays of every invocation calling this (one each) to `purpose`
// of this pass: one atomic per subgroup.
void countWorldRay(uint purpose) {
  uvec4 lanes = subgroupBallot(true);
  if (subgroupElect()) {
    uint copy = (gl_WorkGroupID.x + 5u * gl_WorkGroupID.y) % kWorldRayCounterCopies;
    uint counter = (uint(WORLD_RAY_PASS) * kWorldRayPurposes + purpose) * kWorldRayCounterCopies + copy;
    atomicAdd(gOut_WorldRays.items[counter], subgroupBallotBitCount(lanes));
  }
}

// Adds a queue's entries to this pass's count of them (one invocation calls it).
void countQueuedEntries(uint entries) {
  atomicAdd(gOut_WorldRays.items[kWorldRayQueuedCounters + uint(WORLD_RAY_PASS)], entries);
}

#endif

#endif
