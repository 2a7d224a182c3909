// Where a surface point was on last frame's screen, for the passes that read
// last frame's composite there (the radiance a point sends now: hits of
// rays, samples reused from earlier frames). The including shader includes
// gi/gi_common.glsl first and declares gPrev_Surface.
#ifndef BOUNCE_GI_PREVIOUS_SCREEN_GLSL
#define BOUNCE_GI_PREVIOUS_SCREEN_GLSL

// The pixel of last frame's screen that shows `position` (a surface facing
// `normal`), if one does; -1 otherwise. The caller makes sure last frame's
// images hold a frame.
ivec2 previousPixelShowing(vec3 position, vec3 normal) {
  vec3 projected = projectToScreen(gIn_Frame.frame.previousView, position, fullSize());
  ivec2 pixel = ivec2(floor(projected.xy));
  if (projected.z <= 0.0f || !insideFull(pixel)) return ivec2(-1);
  Surface shown = historySurfaceAt(pixel, imageLoad(gPrev_Surface, pixel).xy);
  if (shown.viewZ <= 0.0f || abs(shown.viewZ - projected.z) > 0.02f * projected.z || dot(shown.normal, normal) < 0.5f)
    return ivec2(-1);
  return pixel;
}

#endif
