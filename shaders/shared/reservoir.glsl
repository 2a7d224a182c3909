// Reservoirs for ReSTIR GI (Bitterli et al. 2020; Ouyang et al. 2021), one
// source for GLSL and C++ (lang.glsl); tests/test_reservoir.cpp tests them.
//
// A reservoir holds one chosen sample of incoming light and what it takes to
// re-evaluate that sample in a later frame or at a neighbouring pixel:
//   position  the world position of the surface point that sends the light,
//             or, for an environment sample, the direction towards it;
//   normal    that surface's normal (unused for environment samples);
//   radiance  the light it sends (linear RGB);
//   W         its unbiased contribution weight (an estimate of 1 / pdf);
//   M         its confidence, in frames' worth of candidates (an initial
//             reservoir made from one frame's candidates has M = 1).
// Stored in 32 bytes as two uvec4s (packReservoir): the position as three
// floats and the octahedral normal; radiance and M as half floats, W as a
// float and the flags.
//
// Weights follow generalized resampled importance sampling: a candidate
// from source pdf p gets weight m * p-hat / p (m its MIS weight), the
// reservoir keeps one candidate with probability proportional to its weight,
// and W = weightSum / p-hat(chosen). Merging reservoir r into s weighs r's
// sample by p-hat_s(sample) * r.W * r.M (times the reconnection Jacobian
// when the sample moves to another surface), and then W = weightSum /
// (M * p-hat(chosen)).
#ifndef BOUNCE_SHARED_RESERVOIR_GLSL
#define BOUNCE_SHARED_RESERVOIR_GLSL

#include "shared/color.glsl"
#include "shared/finite.glsl"
#include "shared/lang.glsl"
#include "shared/packing.glsl"

BOUNCE_SHARED_BEGIN

const uint kReservoirHasSample = 1u;   // a sample was chosen
const uint kReservoirEnvironment = 2u; // position is a direction into the environment

struct Reservoir {
  vec3 position;
  vec3 normal;
  vec3 radiance;
  float weightSum;  // while candidates stream in; not stored
  float M;
  float W;
  uint flags;
};

Reservoir emptyReservoir() {
  Reservoir r;
  r.position = vec3(0.0f);
  r.normal = vec3(0.0f, 0.0f, 1.0f);
  r.radiance = vec3(0.0f);
  r.weightSum = 0.0f;
  r.M = 0.0f;
  r.W = 0.0f;
  r.flags = 0u;
  return r;
}

bool reservoirHasSample(Reservoir r) { return (r.flags & kReservoirHasSample) != 0u; }
bool reservoirIsEnvironment(Reservoir r) { return (r.flags & kReservoirEnvironment) != 0u; }

// Streams one candidate (or a whole reservoir, with `count` its M) into r:
// keeps it with probability weight / (weightSum + weight), u uniform in
// [0,1). Returns whether it was kept. A weight that is not a finite
// positive number is refused: an infinite one would take the reservoir over
// for good (every later weight is nothing beside it), a NaN would make its W NaN.
bool reservoirStream(INOUT(Reservoir) r, vec3 position, vec3 normal, vec3 radiance, uint flags, float weight,
                     float count, float u) {
  r.M += count;
  if (!(weight > 0.0f) || !isFinite(weight)) return false;
  r.weightSum += weight;
  if (u * r.weightSum >= weight) return false;
  r.position = position;
  r.normal = normal;
  r.radiance = radiance;
  r.flags = flags | kReservoirHasSample;
  return true;
}

// The scalar brightness the target function weighs: luminance, or the
// length of the colour vector (the Jitter gi pass's diffuse ReSTIR) for targetFunction 1.
float targetBrightness(vec3 radiance, uint targetFunction) {
  return targetFunction == 1u ? length(radiance) : luminance(radiance);
}

// The direction from a shaded point towards a reservoir's sample.
vec3 sampleDirection(Reservoir r, vec3 shadedPosition) {
  if (reservoirIsEnvironment(r)) return r.position;
  vec3 d = r.position - shadedPosition;
  float length2 = dot(d, d);
  return length2 > 0.0f ? d * inversesqrt(length2) : vec3(0.0f, 0.0f, 1.0f);
}

// p-hat of a sample at a shaded point: brightness times the cosine there,
// and zero when the sending surface faces away (a Lambertian sender sends
// nothing backwards).
float targetPdf(Reservoir r, vec3 shadedPosition, vec3 shadedNormal, uint targetFunction) {
  vec3 direction = sampleDirection(r, shadedPosition);
  float cosine = dot(shadedNormal, direction);
  if (cosine <= 0.0f) return 0.0f;
  if (!reservoirIsEnvironment(r) && dot(r.normal, direction) >= 0.0f) return 0.0f;
  return targetBrightness(r.radiance, targetFunction) * cosine;
}

// W = weightSum / (M p-hat) after merging reservoirs; for a freshly
// gathered reservoir, whose candidate weights carry their MIS weights
// (1 / candidate count), pass M = 1.
void reservoirFinalize(INOUT(Reservoir) r, float chosenTargetPdf, float confidence) {
  r.W = (chosenTargetPdf > 0.0f && confidence > 0.0f) ? r.weightSum / (confidence * chosenTargetPdf) : 0.0f;
  if (!(r.W > 0.0f) || !isFinite(r.W)) {
    r.W = 0.0f;
    r.flags = r.flags & ~kReservoirHasSample;
  }
}

// How much larger a solid angle the same patch of the sending surface covers
// seen from `to` than seen from `from` (ReSTIR GI's reconnection Jacobian):
// a sample reused from a neighbour has its W scaled by this. 0 when the
// sender faces away from `to`.
float reconnectionJacobian(vec3 samplePosition, vec3 sampleNormal, vec3 from, vec3 to) {
  vec3 toFrom = from - samplePosition;
  vec3 toTo = to - samplePosition;
  float distanceFrom2 = dot(toFrom, toFrom);
  float distanceTo2 = dot(toTo, toTo);
  if (!(distanceFrom2 > 0.0f) || !(distanceTo2 > 0.0f)) return 0.0f;
  float cosFrom = abs(dot(sampleNormal, toFrom)) * inversesqrt(distanceFrom2);
  float cosTo = dot(sampleNormal, toTo) * inversesqrt(distanceTo2);
  if (cosTo <= 0.0f || cosFrom <= 1e-4f) return 0.0f;
  return (cosTo / cosFrom) * (distanceFrom2 / distanceTo2);
}

// Spatial reuse rejects reconnection Jacobians above this. Its outputs can
// feed the next frame (DiffuseSettings::spatialFeedback), where a sample
// could hop from pixel to pixel, its W multiplied by a Jacobian at every
// hop; a loose limit grows a few huge weights near creases: unbiased, but a
// picture darker than the truth most of the time with rare bright blotches
// (tests/test_reservoir.cpp measures the chain).
const float kMaxSpatialJacobian = 3.0f;
// The resolve evaluates reservoirs one pixel away, once: a looser limit.
const float kMaxResolveJacobian = 10.0f;

// The factor a reservoir's sample gets when reused from the surface at
// `from` at the surface at `to`: the reconnection Jacobian, 0 when it is
// above maxJacobian (rejected), 1 for environment samples (directions do
// not move) or without the Jacobian.
float reuseJacobian(Reservoir r, vec3 from, vec3 to, float maxJacobian, bool useJacobian) {
  if (!useJacobian || !reservoirHasSample(r) || reservoirIsEnvironment(r)) return 1.0f;
  float jacobian = reconnectionJacobian(r.position, r.normal, from, to);
  return jacobian > maxJacobian ? 0.0f : jacobian;
}

// Whether a reservoir at (position, normal) could have handed sample r on
// to a surface at `to`: r lies where that reservoir's target is positive,
// and its Jacobian from there is not rejected. Summing the M of those that
// could (Z) and dividing by it, instead of by every M merged, keeps a merge
// unbiased where neighbours see less than the pixel does (Bitterli et al.
// 2020, Algorithm 6).
bool canHandOver(Reservoir r, vec3 position, vec3 normal, vec3 to, float maxJacobian, bool useJacobian,
                 uint targetFunction) {
  return targetPdf(r, position, normal, targetFunction) > 0.0f &&
         reuseJacobian(r, position, to, maxJacobian, useJacobian) > 0.0f;
}

// Stores a reservoir; what it stores is finite whatever went in, since the
// reservoirs are next frame's history and a NaN there would be reused into
// the neighbours frame after frame. A sample with a non-finite position,
// normal or W is dropped (the reservoir keeps its M: the candidates were
// seen); radiance goes through sanitizeRadiance (half floats top out at
// kMaxHalf), M is clamped to [0, kMaxHalf].
void packReservoir(Reservoir r, OUT(uvec4) first, OUT(uvec4) second) {
  bool keep = reservoirHasSample(r) && isFinite(r.position) && isFinite(r.normal) && isFinite(r.W);
  vec3 position = keep ? r.position : vec3(0.0f);
  vec3 normal = keep ? r.normal : vec3(0.0f, 0.0f, 1.0f);
  float W = keep ? r.W : 0.0f;
  uint flags = keep ? r.flags : 0u;
  first = uvec4(floatBitsToUint(position.x), floatBitsToUint(position.y), floatBitsToUint(position.z),
                packNormalOct32(normal));
  vec3 radiance = sanitizeRadiance(r.radiance);
  float M = clamp(finiteOr(r.M, 0.0f), 0.0f, kMaxHalf);
  second = uvec4(packHalf2x16(vec2(radiance.x, radiance.y)), packHalf2x16(vec2(radiance.z, M)), floatBitsToUint(W),
                 flags);
}

Reservoir unpackReservoir(uvec4 first, uvec4 second) {
  Reservoir r;
  r.position = vec3(uintBitsToFloat(first.x), uintBitsToFloat(first.y), uintBitsToFloat(first.z));
  r.normal = unpackNormalOct32(first.w);
  vec2 rg = unpackHalf2x16(second.x);
  vec2 bm = unpackHalf2x16(second.y);
  r.radiance = vec3(rg.x, rg.y, bm.x);
  r.M = bm.y;
  r.W = uintBitsToFloat(second.z);
  r.flags = second.w;
  r.weightSum = 0.0f;
  return r;
}

BOUNCE_SHARED_END
#endif
