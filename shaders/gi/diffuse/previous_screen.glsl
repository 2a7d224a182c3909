// Where a surface point was on last frame's screen, as the diffuse branch
// asks (gi.diffuse.gather: screen-space hits of ray candidates;
// gi.diffuse.temporal_reuse: fresh radiance for reused samples). The
// including shader includes gi/gi_common.glsl and
// gi/diffuse/diffuse_common.glsl first and declares gPrev_Surface.
#ifndef BOUNCE_GI_DIFFUSE_PREVIOUS_SCREEN_GLSL
#define BOUNCE_GI_DIFFUSE_PREVIOUS_SCREEN_GLSL

#include "gi/previous_screen.glsl"

// The pixel of last frame's screen that shows `position`, if one does and
// the branch reads last frame at all (the point a screen candidate could
// have picked); -1 otherwise.
ivec2 previousPixelOf(vec3 position, vec3 normal) {
  if (gIn_DiffuseConstants.diffuse.screenCandidates + gIn_DiffuseConstants.diffuse.brightCandidates == 0u)
    return ivec2(-1);  // no last frame to read (or to have sampled from)
  return previousPixelShowing(position, normal);
}

#endif
