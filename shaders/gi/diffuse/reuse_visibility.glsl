// gi.diffuse.reuse_visibility: the unbiased option of ReSTIR GI's reuse.
// A sample reused at another surface may be hidden from it; with the option
// on (and a scene bridge that traces), reuse tests it with an any-hit ray
// through the bridge and a hidden sample counts 0 there. Off (the default),
// 1: reuse trusts the resolve's visibility test, and the bias that leaves
// is measured in docs/quality.md. The including shader includes
// gi/diffuse/diffuse_common.glsl and gi/gi_common.glsl first.
#ifndef BOUNCE_GI_REUSE_VISIBILITY_GLSL
#define BOUNCE_GI_REUSE_VISIBILITY_GLSL

#include "gi/scene_bridge.glsl"
#include "gi/world_rays.glsl"
#include "shared/reservoir.glsl"

float reuseVisibility(Reservoir r, Surface at) {
  if (!kSceneBridgeTraces || gIn_DiffuseConstants.diffuse.reuseVisibility == 0u || !reservoirHasSample(r)) return 1.0f;
  bool visible = reservoirIsEnvironment(r) ? worldDirectionOpen(at.position, at.normal, at.viewZ, r.position)
                                           : worldSegmentVisible(at.position, at.normal, at.viewZ, r.position);
  return visible ? 1.0f : 0.0f;
}

#endif
