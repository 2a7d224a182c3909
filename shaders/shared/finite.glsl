// Telling finite values from NaN and infinity, and making radiance safe to
// use and to store. One source for GLSL and C++ (lang.glsl), tested on the
// CPU in tests/test_shared_math.cpp and on the GPU in
// tests/test_gpu_shared_math.cpp.
//
// The policy (docs/conventions.md, "Non-finite values"): no pass trusts a
// value it reads from another stage to be finite, and none stores a value
// that is not. Non-finite radiance is no light (0), never the brightest
// light: it says nothing about how bright anything is, and reading +inf as
// "very bright" would let one bad pixel light the whole frame through
// reuse. Finite radiance is clamped to [0, kMaxHalf], so an rgba16f image
// saturates at its largest finite value instead of rounding to +inf.
#ifndef BOUNCE_SHARED_FINITE_GLSL
#define BOUNCE_SHARED_FINITE_GLSL
#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

// The largest finite half float (rgba16f, rg16f).
const float kMaxHalf = 65504.0f;

// Whether x is finite: an IEEE-754 binary32 value is NaN or infinite exactly
// when its eight exponent bits are all ones. Tested on the bits rather than
// with isnan()/isinf(): GLSL does not require NaN support, and a driver may
// compile float code as if NaN and infinity never occurred (as fast-math
// does), folding isnan(x), isinf(x) and x != x to false. An integer test on
// floatBitsToUint(x) cannot be folded that way.
bool isFinite(float x) { return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u; }
bool isFinite(vec2 v) { return isFinite(v.x) && isFinite(v.y); }
bool isFinite(vec3 v) { return isFinite(v.x) && isFinite(v.y) && isFinite(v.z); }
bool isFinite(vec4 v) { return isFinite(v.x) && isFinite(v.y) && isFinite(v.z) && isFinite(v.w); }

// The value where it is finite (every component), else the fallback.
float finiteOr(float x, float fallback) { return isFinite(x) ? x : fallback; }
vec2 finiteOr(vec2 v, vec2 fallback) { return isFinite(v) ? v : fallback; }
vec3 finiteOr(vec3 v, vec3 fallback) { return isFinite(v) ? v : fallback; }
vec4 finiteOr(vec4 v, vec4 fallback) { return isFinite(v) ? v : fallback; }

// Radiance fit to be used and stored: 0 when any channel is NaN or infinite,
// else every channel clamped to [0, kMaxHalf] (there is no negative light,
// and above kMaxHalf a half float rounds to +inf). Valid radiance read from
// a 16-bit image passes unchanged.
vec3 sanitizeRadiance(vec3 radiance) {
  return isFinite(radiance) ? clamp(radiance, vec3(0.0f), vec3(kMaxHalf)) : vec3(0.0f);
}

// x rounded to the nearest half float (ties to even), returned as a float
// that a 16-bit image stores exactly. Why: Vulkan leaves the rounding of a
// float stored to an rgba16f image to the implementation, and NVIDIA's
// truncates. A feedback loop (a history blended into itself frame after
// frame) then loses up to a place every frame, and its equilibrium sits
// about frames / 2 places low: 1-2 % for a 30-frame history (measured: the
// denoiser's histories in rgba16f raised cornell's diffuse relMSE 28 %).
// Rounded here first, the store is exact whatever the implementation does.
// For |x| in half's normal range; below it (under 6.1e-5) the store keeps
// fewer bits and may truncate those, a bias under 6e-8 absolute.
float roundedToHalf(float x) {
  if (!isFinite(x)) return x;
  uint bits = floatBitsToUint(x);
  // 13 of binary32's 23 mantissa bits go: add half their place, and one
  // more where the kept bits are odd, so that a tie rounds to even.
  bits += 0x00000fffu + ((bits >> 13u) & 1u);
  return uintBitsToFloat(bits & 0xffffe000u);
}
vec3 roundedToHalf(vec3 v) { return vec3(roundedToHalf(v.x), roundedToHalf(v.y), roundedToHalf(v.z)); }
vec4 roundedToHalf(vec4 v) { return vec4(roundedToHalf(v.x), roundedToHalf(v.y), roundedToHalf(v.z), roundedToHalf(v.w)); }

BOUNCE_SHARED_END
#endif
