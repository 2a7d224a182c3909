// The visibility tests of spatial reuse's normalisation, traced apart from
// it (gi/diffuse/reuse_visibility.glsl says why there are tests at all).
// gi.diffuse.spatial_reuse merges a pixel's neighbours and, where a
// neighbour must be asked whether it sees the chosen sample, fills one of
// the pixel's test slots and queues it; gi.diffuse.neighbour_visibility
// traces every queued test, one invocation per ray, so a warp's lanes all
// trace (inside the merge only the few pixels holding a sky sample did,
// one neighbour after another); gi.diffuse.spatial_normalize then counts
// in the verdicts. The three share the push constants below, run once per
// spatial pass, and leave a summary per pixel (gi.diffuse.neighbour_tests,
// dumpable):
//   x  tests queued
//   y  M of the neighbours not tested (the budget ran out), which count
//      with the tested ones' seen fraction
//   z  the confidence the merge normalised W by, every tested neighbour
//      counted as seeing the sample
//   w  the M found hidden (written by gi.diffuse.spatial_normalize)
// A test slot is a uvec2: the neighbour's half-resolution pixel (x | y <<
// 16) and its M as float bits, negated once its test finds the sample hidden.
#ifndef BOUNCE_GI_DIFFUSE_NEIGHBOUR_TESTS_GLSL
#define BOUNCE_GI_DIFFUSE_NEIGHBOUR_TESTS_GLSL

layout(push_constant) uniform Params {
  float radius;        // half-resolution pixels at the surface
  uint samples;        // neighbours tried
  uint passIndex;      // decorrelates the two passes' random numbers
  uint slotsPerPixel;  // test slots each pixel has (none: no tests)
} params;

uint neighbourTestSlot(ivec2 halfPixel, uint test) { return halfPixelSlot(halfPixel, params.slotsPerPixel, test); }

#endif
