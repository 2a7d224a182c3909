// Screen-space visibility: marches a segment through this frame's depth
// buffer. The including shader declares gIn_ViewZ (r32f) and includes
// gi/gi_common.glsl first.
//
// A step is blocked when the segment there lies behind the depth buffer's
// surface by more than a sliver and by less than that surface's thickness
// (a fraction of its viewZ, gi.diffuse.visibility_thickness): thin objects
// do not cast shadows forever behind themselves.
#ifndef BOUNCE_GI_SCREEN_TRACE_GLSL
#define BOUNCE_GI_SCREEN_TRACE_GLSL

const float kVisible = 1.0f;
const float kOccluded = 0.0f;
const float kLeftScreen = -1.0f;  // the march left the screen (or passed behind the camera) before deciding

// Marches `steps` points evenly from `from` to `to` (ends excluded, start
// offset by `jitter` in [0,1) to trade banding for noise).
float screenVisibility(vec3 from, vec3 to, uint steps, float jitter) {
  float thickness = gIn_Frame.frame.resolveFilter.y;
  for (uint i = 0u; i < steps; ++i) {
    float t = (float(i) + jitter) / float(steps);
    t = mix(0.02f, 0.98f, t);  // keep off the two surfaces themselves
    vec3 projected = projectToScreen(gIn_Frame.frame.view, mix(from, to, t), fullSize());
    ivec2 texel = ivec2(floor(projected.xy));
    if (projected.z <= 0.0f || !insideFull(texel)) return kLeftScreen;
    float sceneViewZ = imageLoad(gIn_ViewZ, texel).x;
    if (sceneViewZ <= 0.0f) continue;  // sky: nothing in the way
    float behind = projected.z - sceneViewZ;
    if (behind > 0.01f * sceneViewZ && behind < thickness * sceneViewZ) return kOccluded;
  }
  return kVisible;
}

#endif
