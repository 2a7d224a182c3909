// The engine's motion vectors in the library's convention: pixels from this
// frame's pixel to where its surface was in the last one (previous =
// current + motion). gIn_Frame.frame.motionScale turns the engine's units
// into that (gi.input.motion_units, gi.input.motion_scale_x/y). The
// including shader declares gIn_Motion (a sampled image: RG16F or RG32F)
// and includes gi/gi_common.glsl first.
#ifndef BOUNCE_GI_MOTION_GLSL
#define BOUNCE_GI_MOTION_GLSL

// May be non-finite: usableMotion() decides.
vec2 motionAt(ivec2 pixel) {
  vec4 stored = texelFetch(gIn_Motion, pixel, 0);
  return vec2(stored.x, stored.y) * gIn_Frame.frame.motionScale;
}

#endif
