// Screen-space visibility: marches a segment through this frame's depth
// buffer: gi.store_history's copy of it, gIn_MarchDepth (r32f, 0 where the
// engine's viewZ is unusable), which the including shader declares after
// including gi/gi_common.glsl. A storage image of the library's own, read
// with imageLoad: the engine's viewZ through the texture path made the
// resolve 7 % slower on an H100. A step can only answer visible, occluded
// or left the screen, so a broken depth can change one decision, never make
// a value non-finite.
//
// A step is blocked when the segment there lies behind the depth buffer's
// surface by more than a sliver and by less than that surface's thickness
// (`thickness`, a fraction of its viewZ: gi.diffuse.visibility_thickness for
// the diffuse branch): thin objects do not cast shadows forever behind themselves.
// With `strict` the march does not assume anything beyond that: a step
// farther behind a surface than its thickness ends it undecided
// (kLeftScreen), for a world ray to settle (gi.diffuse.visibility hybrid).
#ifndef BOUNCE_GI_SCREEN_TRACE_GLSL
#define BOUNCE_GI_SCREEN_TRACE_GLSL

#include "gi/screen_exit.glsl"

float marchViewZ(ivec2 texel) { return imageLoad(gIn_MarchDepth, texel).x; }

const float kVisible = 1.0f;
const float kOccluded = 0.0f;
const float kLeftScreen = -1.0f;  // the march left the screen (or passed behind the camera) before deciding

// Whether a march step `behind` a depth-buffer surface at sceneViewZ ends
// the march; `occluded` says how (true: blocked, false: undecided).
bool behindEnds(float behind, float sceneViewZ, float thickness, bool strict, out bool occluded) {
  occluded = false;
  if (behind <= 0.01f * sceneViewZ) return false;
  occluded = behind < thickness * sceneViewZ;
  return occluded || strict;
}

// Marches `steps` points evenly from `from` to `to` (ends excluded, start
// offset by `jitter` in [0,1) to trade banding for noise).
float screenVisibility(vec3 from, vec3 to, uint steps, float jitter, float thickness, bool strict) {
  vec3 start = toViewSpace(gIn_Frame.frame.view, from);
  vec3 end = toViewSpace(gIn_Frame.frame.view, to);
  for (uint i = 0u; i < steps; ++i) {
    float t = (float(i) + jitter) / float(steps);
    t = mix(0.02f, 0.98f, t);  // keep off the two surfaces themselves
    vec3 projected = projectViewPoint(gIn_Frame.frame.view, mix(start, end, t), fullSize());
    ivec2 texel = ivec2(floor(projected.xy));
    if (projected.z <= 0.0f || !insideFull(texel)) return kLeftScreen;
    float sceneViewZ = marchViewZ(texel);
    if (sceneViewZ <= 0.0f) continue;  // sky: nothing in the way
    bool occluded;
    if (behindEnds(projected.z - sceneViewZ, sceneViewZ, thickness, strict, occluded))
      return occluded ? kOccluded : kLeftScreen;
  }
  return kVisible;
}

// Whether a direction from `from` reaches the sky, as far as the screen can
// tell. Screen space knows the sky only where it is shown (background
// pixels), so the march goes far (points spaced more widely with distance)
// and the sky counts as reached when the ray meets a background pixel, or
// leaves the screen where the screen's edge shows sky. A ray that leaves
// through a surface at the edge, turns behind the camera, or ends over a
// surface most likely hits what is beyond: it is undecided (kLeftScreen),
// for a world ray or screen-only mode's policy (gi/screen_only_policy.glsl)
// to settle, and `exit` is the pixel where its path on screen leaves it (or
// where the march ended over a surface). Counted as open, rooms would leak
// the sky through their off-screen walls.
float environmentVisibilityExit(vec3 from, vec3 direction, float viewZ, uint steps, float jitter, float thickness,
                                bool strict, out ivec2 exit, out bool towardsCamera) {
  const float kFarthest = 64.0f;  // in multiples of the pixel's viewZ
  ivec2 size = ivec2(fullSize());
  vec3 start = toViewSpace(gIn_Frame.frame.view, from);
  vec3 step = toViewSpace(gIn_Frame.frame.view, from + direction) - start;  // one unit along the ray
  vec2 origin = projectViewPoint(gIn_Frame.frame.view, start, fullSize()).xy;
  vec2 lastInside = origin;  // the last step on screen
  exit = clamp(ivec2(floor(origin)), ivec2(0), size - 1);
  towardsCamera = false;
  for (uint i = 0u; i < steps; ++i) {
    float t = (float(i) + jitter) / float(steps);
    float distance = viewZ * (0.02f + kFarthest * t * t);
    vec3 projected = projectViewPoint(gIn_Frame.frame.view, start + step * distance, fullSize());
    ivec2 texel = ivec2(floor(projected.xy));
    if (projected.z <= 0.0f) {
      // Towards the camera: the ray's path on screen is a line from the
      // origin's pixel, which it follows out of the screen before it passes
      // the camera plane.
      vec2 ahead = projectViewPoint(gIn_Frame.frame.view, start + step * (1e-3f * viewZ), fullSize()).xy;
      vec2 along = ahead - origin;
      float length2 = dot(along, along);
      if (length2 > 0.0f && isFinite(length2))
        exit = screenExitPixel(origin, origin + along * inversesqrt(length2) * float(size.x + size.y) * 4.0f);
      towardsCamera = true;
      return kLeftScreen;
    }
    if (!insideFull(texel)) {
      exit = screenExitPixel(lastInside, projected.xy);
      towardsCamera = projected.z < -start.z;  // nearer the camera than where it started
      return marchViewZ(clamp(texel, ivec2(0), size - 1)) <= 0.0f ? kVisible : kLeftScreen;
    }
    lastInside = projected.xy;
    exit = texel;
    float sceneViewZ = marchViewZ(texel);
    if (sceneViewZ <= 0.0f) return kVisible;
    bool occluded;
    if (behindEnds(projected.z - sceneViewZ, sceneViewZ, thickness, strict, occluded))
      return occluded ? kOccluded : kLeftScreen;
  }
  return kLeftScreen;  // still over surfaces after the longest march
}

float environmentVisibility(vec3 from, vec3 direction, float viewZ, uint steps, float jitter, float thickness,
                            bool strict) {
  ivec2 exit;
  bool towardsCamera;
  return environmentVisibilityExit(from, direction, viewZ, steps, jitter, thickness, strict, exit, towardsCamera);
}

// A gather ray through the depth buffer: what screen space can say about the
// first surface along origin + t * direction.
struct ScreenRay {
  bool hit;  // it met a depth-buffer surface: the one at `texel`
  ivec2 texel;
};

// Marches `steps` points spaced more widely with distance (as
// environmentVisibility) up to 64 viewZ. A step that falls behind the depth
// buffer by less than `thickness` right after one in front of it hit that
// surface; one farther behind (a surface of unknown thickness), one off
// screen, and the end of the march leave the ray undecided. An undecided
// ray vouches for no part of its path: the steps are far apart, and a thin
// surface between two free steps (a chair leg, a window frame) would be
// jumped; a world ray from the start measured 20 % less light leaking
// through them on sun-room than one from the last free step.
ScreenRay screenRay(vec3 from, vec3 direction, float viewZ, uint steps, float jitter, float thickness) {
  const float kFarthest = 64.0f;
  ScreenRay ray;
  ray.hit = false;
  ray.texel = ivec2(0);
  vec3 start = toViewSpace(gIn_Frame.frame.view, from);
  vec3 step = toViewSpace(gIn_Frame.frame.view, from + direction) - start;
  for (uint i = 0u; i < steps; ++i) {
    float t = (float(i) + jitter) / float(steps);
    float distance = viewZ * (0.02f + kFarthest * t * t);
    vec3 projected = projectViewPoint(gIn_Frame.frame.view, start + step * distance, fullSize());
    ivec2 texel = ivec2(floor(projected.xy));
    if (projected.z <= 0.0f || !insideFull(texel)) return ray;
    float sceneViewZ = marchViewZ(texel);
    float behind = sceneViewZ > 0.0f ? projected.z - sceneViewZ : -1.0f;
    if (behind > 0.01f * sceneViewZ) {
      ray.hit = behind < thickness * sceneViewZ;
      ray.texel = texel;
      return ray;
    }
  }
  return ray;
}

#endif
