// Visibility in ReSTIR GI's reuse, through the scene bridge (without a
// bridge that traces, everything counts as visible).
//
// A reservoir's sample came from its owner's own candidates: ray candidates
// are the first thing their ray hit, so its owner could only ever hold
// samples it sees. Where a neighbour's M counts towards normalising a
// sample (Z, spatial reuse), it must count only if that neighbour could
// have held the sample, i.e. sees it, or every sample that neighbour could
// not see is weighed down: biased reuse loses light wherever visibility
// differs across the disk. For sky directions it differs most (one point
// sees the sky through a window in a direction, one a metre away sees the
// wall), so sky samples are tested by default (gi.diffuse.sky_reuse_visibility;
// measured on sun-room, 320x180, frame 32: 0.61 -> 0.71 of the reference,
// and after 300 frames the same as without reuse, where it was 10 % below).
// With gi.diffuse.reuse_visibility on (the unbiased option), every sample
// is, and each reused candidate is also tested at the surface reusing it,
// so a hidden one never takes the selection.
#ifndef BOUNCE_GI_REUSE_VISIBILITY_GLSL
#define BOUNCE_GI_REUSE_VISIBILITY_GLSL

#include "gi/scene_bridge.glsl"
#include "gi/world_rays.glsl"
#include "shared/reservoir.glsl"

// A reused candidate's visibility at the surface reusing it (1 unless the
// unbiased option is on).
float reuseVisibility(Reservoir r, Surface at) {
  if (!kSceneBridgeTraces || gIn_DiffuseConstants.diffuse.reuseVisibility == 0u || !reservoirHasSample(r)) return 1.0f;
  return worldSeesSample(r, at, kWorldRaysReuseVisibility) ? 1.0f : 0.0f;
}

// Whether the neighbours' visibility of the chosen sample is tested with
// world rays: for sky samples with gi.diffuse.sky_reuse_visibility, for all
// with the unbiased option.
bool neighbourVisibilityTested(Reservoir r) {
  if (!kSceneBridgeTraces || !reservoirHasSample(r)) return false;
  DiffuseConstants d = gIn_DiffuseConstants.diffuse;
  return d.reuseVisibility != 0u || (d.skyReuseVisibility != 0u && reservoirIsEnvironment(r));
}

// How many neighbours one spatial pass tests with a ray, at most (the
// unbiased option tests every one; gi.diffuse.sky_reuse_rays otherwise).
uint neighbourVisibilityRays() {
  DiffuseConstants d = gIn_DiffuseConstants.diffuse;
  return d.reuseVisibility != 0u ? 0xffffffffu : d.skyReuseRays;
}

// Whether a neighbour at `at` could have held the chosen sample, as far as
// visibility goes (only where neighbourVisibilityTested).
bool neighbourSeesSample(Reservoir r, Surface at) {
  uint purpose = gIn_DiffuseConstants.diffuse.reuseVisibility != 0u ? kWorldRaysReuseVisibility : kWorldRaysSkyReuse;
  return worldSeesSample(r, at, purpose);
}

#endif
