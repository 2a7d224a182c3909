// The denoiser's math (gi/denoise, after NVIDIA's REBLUR): hit-distance
// normalisation, the edge-stopping weights of its spatial passes and their
// disk of taps. One source for GLSL and C++ (lang.glsl); tests/
// test_shared_math.cpp checks each on the CPU.
#ifndef BOUNCE_SHARED_DENOISE_WEIGHTS_GLSL
#define BOUNCE_SHARED_DENOISE_WEIGHTS_GLSL

#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

// REBLUR's hit-distance normalisation: the distance at which a hit counts
// as "far" for a surface at viewZ of this roughness, (A + viewZ B) scaled up
// to C times for rough lobes (whose hits matter less for their shape).
float hitDistanceScale(vec4 parameters, float viewZ, float roughness) {
  return (parameters.x + abs(viewZ) * parameters.y) * mix(1.0f, parameters.z, exp2(parameters.w * roughness * roughness));
}

// Hit distance in [0, 1]: 0 a contact reflection, 1 far or unknown.
float normalizedHitDistance(vec4 parameters, float hitDistance, float viewZ, float roughness) {
  if (!(hitDistance > 0.0f)) return 1.0f;
  return clamp(hitDistance / hitDistanceScale(parameters, viewZ, roughness), 0.0f, 1.0f);
}

// The half angle (radians) of the cone around a pixel's normal whose
// neighbours may be averaged with it (REBLUR's normal weight parameter):
// the cone holding the share p of a GGX lobe of perceptual roughness r,
// tan = r sqrt(p / (1 - p)) (diffuse: r = 1), with p = 0.75 while the
// history is new (historyWeight 1 = 1 / (1 + 0 frames)) narrowing to 0.75
// fraction^2 as it grows: a long history needs only close neighbours.
float lobeHalfAngle(float roughness, float fraction, float historyWeight) {
  float p = 0.75f * mix(fraction * fraction, 1.0f, clamp(historyWeight, 0.0f, 1.0f));
  return atan(clamp(roughness, 0.0f, 1.0f) * sqrt(p / (1.0f - p + 1e-6f)));
}

// A neighbour off the pixel's tangent plane weighs less, nothing past
// `sensitivity` * viewZ (REBLUR's geometry weight with its cut-off).
float planeWeight(vec3 normal, vec3 position, vec3 neighbour, float viewZ, float sensitivity) {
  float distance = abs(dot(normal, neighbour - position)) / max(sensitivity * viewZ, 1e-6f);
  return clamp(1.0f - distance, 0.0f, 1.0f);
}

// A neighbour whose normal leaves the cone of half angle `halfAngle`
// weighs nothing (REBLUR: smoothstep from 1 at the centre to 0 at the edge).
float normalWeight(vec3 normal, vec3 neighbourNormal, float halfAngle) {
  float angle = acos(clamp(dot(normal, neighbourNormal), -1.0f, 1.0f));
  float t = clamp(1.0f - angle / max(halfAngle, 2e-3f), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// A neighbour of another roughness reflects another lobe.
float roughnessWeight(float roughness, float neighbourRoughness, float fraction) {
  return clamp(1.0f - abs(roughness - neighbourRoughness) / max(fraction * roughness, 0.02f), 0.0f, 1.0f);
}

// 8 taps in the unit disk (a golden-angle spiral, radii sqrt((i + 0.5) / 8)):
// even coverage, rotated per pixel and frame so the pattern does not show.
vec2 diskTap(uint i, float rotation) {
  float radius = sqrt((float(i) + 0.5f) / 8.0f);
  float angle = float(i) * 2.39996323f + rotation;
  return radius * vec2(cos(angle), sin(angle));
}

BOUNCE_SHARED_END

#endif
