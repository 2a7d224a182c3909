// Where a surface point was on last frame's screen, for the passes that read
// last frame's composite there (gi.diffuse.gather: screen-space hits of ray
// candidates; gi.diffuse.temporal_reuse: fresh radiance for reused
// samples). The including shader includes gi/gi_common.glsl and
// gi/diffuse/diffuse_common.glsl first and declares gPrev_Surface.
#ifndef BOUNCE_GI_DIFFUSE_PREVIOUS_SCREEN_GLSL
#define BOUNCE_GI_DIFFUSE_PREVIOUS_SCREEN_GLSL

// The pixel of last frame's screen that shows `position`, if one does (the
// point a screen candidate could have picked); -1 otherwise.
ivec2 previousPixelOf(vec3 position, vec3 normal) {
  if (gIn_DiffuseConstants.diffuse.screenCandidates + gIn_DiffuseConstants.diffuse.brightCandidates == 0u)
    return ivec2(-1);  // no last frame to read (or to have sampled from)
  vec3 projected = projectToScreen(gIn_Frame.frame.previousView, position, fullSize());
  ivec2 pixel = ivec2(floor(projected.xy));
  if (projected.z <= 0.0f || !insideFull(pixel)) return ivec2(-1);
  Surface shown = historySurfaceAt(pixel, imageLoad(gPrev_Surface, pixel).xy);
  if (shown.viewZ <= 0.0f || abs(shown.viewZ - projected.z) > 0.02f * projected.z || dot(shown.normal, normal) < 0.5f)
    return ivec2(-1);
  return pixel;
}

#endif
