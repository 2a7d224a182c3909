// How a temporal filter stores its luminance moments: mean, deviation and
// the fast history's mean, not mean and mean square. One source for GLSL
// and C++ (lang.glsl), tested on the CPU in tests/test_shared_math.cpp.
//
// Why the deviation: the variance a clamp and the anti-lag need is
// E[x^2] - E[x]^2, the difference of two nearly equal numbers wherever the
// light is nearly converged. Stored in half precision (11-bit mantissa),
// each rounds by up to 1/2048 of itself, so a pixel of luminance 1 and
// true deviation 0.01 would read back a deviation anywhere in 0..0.03: the
// clamp and the anti-lag would act on noise of the format, not of the
// light. Stored as the deviation, it keeps 11 bits of its own.
#ifndef BOUNCE_SHARED_MOMENTS_GLSL
#define BOUNCE_SHARED_MOMENTS_GLSL
#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

// moments: (mean, mean square, fast mean); `extra` rides in alpha (the
// denoiser's specular virtual-history share, else 0).
vec4 storedMoments(vec3 moments, float extra) {
  float deviation = sqrt(max(moments.y - moments.x * moments.x, 0.0f));
  return vec4(moments.x, deviation, moments.z, extra);
}

// The moments (mean, mean square, fast mean) of a stored texel.
vec3 momentsFromStored(vec4 stored) {
  return vec3(stored.x, stored.y * stored.y + stored.x * stored.x, stored.z);
}

BOUNCE_SHARED_END
#endif
