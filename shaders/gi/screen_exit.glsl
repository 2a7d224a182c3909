// Where a ray's path on screen leaves it: what screen-only mode's policy
// (gi/screen_only_policy.glsl) looks up for a ray that left the screen
// before screen space could decide it. The including shader includes
// gi/gi_common.glsl first.
#ifndef BOUNCE_GI_SCREEN_EXIT_GLSL
#define BOUNCE_GI_SCREEN_EXIT_GLSL

// The last pixel on screen along the screen-space segment from `inside`
// (on screen) towards `beyond`.
ivec2 screenExitPixel(vec2 inside, vec2 beyond) {
  vec2 size = fullSize();
  vec2 d = beyond - inside;
  float t = 1.0f;
  for (int axis = 0; axis < 2; ++axis) {
    if (d[axis] > 0.0f) t = min(t, (size[axis] - 0.5f - inside[axis]) / d[axis]);
    if (d[axis] < 0.0f) t = min(t, (0.5f - inside[axis]) / d[axis]);
  }
  vec2 exit = inside + d * max(t, 0.0f);
  return clamp(ivec2(floor(isFinite(exit) ? exit : inside)), ivec2(0), ivec2(size) - 1);
}

#endif
