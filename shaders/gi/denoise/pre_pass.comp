#version 460
#extension GL_GOOGLE_include_directive : require
// gi.denoise.pre_pass: REBLUR's pre-blur of each noisy signal before it
// meets the history (every signal of the dispatch in turn, from one load of
// the pixel's surface): 8 taps of a disk rotated per frame,
// radius gi.denoise.diffuse_pre_pass_radius (specular_pre_pass_radius)
// times the square root of how far the light came from (a fraction of the
// frustum's width: light from far away varies slowly across the screen,
// a contact shadow does not); for specular also of the roughness, and no
// wider than the lobe's footprint at the hit (shared/denoise_weights.glsl,
// prePassRadius). Weights: the blur's plane, normal cone and roughness
// weights as for a history of 10 frames with cone and roughness reach
// doubled (REBLUR's), the hit-distance weight (light from a much nearer or
// farther hit is other light), a Gaussian falloff over the disk, and for
// specular REBLUR's contact protection (a neighbour's hit nearer than the
// distance between the two points reflects something else). Radiance and
// hit distance are both averaged: the blurs and the reflection motion read
// the averaged hit distance.
// Checkerboard mode (an engine's signal with gi.denoise.checkerboard:
// every other pixel of a row has a sample, pixelHasSample): the pass runs
// even at radius 0, and first fills each pixel without a sample (REBLUR's
// checkerboard resolve) from its left and right neighbours, which have
// one, each weighed by how well it lies on the pixel's surface; from the
// neighbours above and below (which have one too) where neither does, and
// where none of the four does (a surface a pixel wide), from every
// neighbour with a surface alike, rather than no light. The pre-blur then
// takes the filled value as its centre and reads only pixels with a
// sample: a tap that lands on one without moves a pixel sideways (to the
// left on even taps, to the right on odd ones, as REBLUR's), so a sample
// is never counted again through a neighbour's reconstruction of it.
#include "gi/gi_common.glsl"
#define DENOISE_READS_TILES
#include "gi/denoise/denoise_common.glsl"
#include "shared/color.glsl"
#include "shared/sampling.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

DENOISE_SLOT_IMAGES(readonly, gIn_Signal, 20)
DENOISE_SLOT_IMAGES(writeonly, gOut_PrePassed, 24)
DENOISE_SLOT_LOAD(gIn_Signal)
DENOISE_SLOT_STORE(gOut_PrePassed)

// REBLUR's pre-pass constants: its weights are those of a 10-frame history
// with the normal cone and roughness reach doubled; a tap of another hit
// distance keeps a fifth of its weight; the lobe footprint holds 30 % of
// the lobe.
const float kPrePassHistoryFrames = 10.0f;
const float kPrePassWidening = 2.0f;
const float kHitWeightFloor = 0.2f;
const float kPrePassLobeShare = 0.3f;

// A slot's signal at a pixel with a sample.
vec4 signalAt(uint slot, ivec2 pixel) {
  vec4 s = gIn_SignalAt(slot, pixel);
  return vec4(sanitizeRadiance(s.xyz), max(finiteOr(s.w, 0.0f), 0.0f));
}

// Checkerboard resolve of a pixel without a sample (surface x): its four
// direct neighbours have samples. Each weighs as the blur weighs a
// neighbour of a history just begun (plane, normal cone, roughness: the
// widest reach it grants); left and right first (REBLUR's), then above
// and below, then every neighbour with a surface alike. The hit distance
// averages over the neighbours that know theirs.
vec4 checkerboardResolve(uint slot, ivec2 pixel, Surface x, float roughness) {
  const ivec2 kSteps[4] = ivec2[](ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1));
  NeighbourWeighting weighting = neighbourWeighting(slot, x, roughness, 0.0f, 1.0f);
  vec4 samples[4];
  float weights[4];
  bool onSurface[4];
  for (int i = 0; i < 4; ++i) {
    ivec2 tap = pixel + kSteps[i];
    samples[i] = vec4(0.0f);
    weights[i] = 0.0f;
    onSurface[i] = false;
    if (!insideFull(tap)) continue;
    float tapRoughness;
    Surface y = denoiseSurfaceRoughness(tap, tapRoughness);
    if (y.viewZ <= 0.0f) continue;
    onSurface[i] = true;
    samples[i] = signalAt(slot, tap);
    weights[i] = neighbourWeight(weighting, y, tapRoughness);
  }
  if (weights[0] + weights[1] > 0.0f) {
    weights[2] = 0.0f;
    weights[3] = 0.0f;
  } else if (weights[2] + weights[3] <= 0.0f) {
    for (int i = 0; i < 4; ++i) weights[i] = onSurface[i] ? 1.0f : 0.0f;
  }
  vec3 radiance = vec3(0.0f);
  float weightSum = 0.0f, hitSum = 0.0f, hitWeightSum = 0.0f;
  for (int i = 0; i < 4; ++i) {
    radiance += samples[i].xyz * weights[i];
    weightSum += weights[i];
    if (samples[i].w > 0.0f) {
      hitSum += samples[i].w * weights[i];
      hitWeightSum += weights[i];
    }
  }
  return vec4(weightSum > 0.0f ? radiance / weightSum : vec3(0.0f),
              hitWeightSum > 0.0f ? hitSum / hitWeightSum : 0.0f);
}

// Where a pre-blur tap reads: the tap itself, or in checkerboard mode,
// where it has no sample, its neighbour to the left (even taps) or right
// (odd ones), the other way at the frame's edge (outside a frame one
// pixel wide: the caller skips it).
ivec2 tapWithSample(uint slot, ivec2 tap, uint index) {
  if (pixelHasSample(slot, tap)) return tap;
  int shift = (index & 1u) == 0u ? -1 : 1;
  ivec2 moved = tap + ivec2(shift, 0);
  return insideFull(moved) ? moved : tap - ivec2(shift, 0);
}

// The pre-passed value of a slot's signal at a pixel with a surface.
vec4 prePassed(uint slot, ivec2 pixel, Surface x, float roughness) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  vec4 center = pixelHasSample(slot, pixel) ? signalAt(slot, pixel) : checkerboardResolve(slot, pixel, x, roughness);
  bool specular = specularKind(slot);
  float maxRadius = (specular ? d.specularPrePassRadius : d.diffusePrePassRadius) * gSignals.radiusScale;
  // Radius 0: the pass runs for the checkerboard resolve alone (or, for a
  // signal of full samples, to hand the later passes a sanitised copy).
  if (maxRadius <= 0.0f) return vec4(sanitizeRadiance(center.xyz), center.w);
  float r = specular ? roughness : 1.0f;
  float hit = center.w;

  vec2 size = fullSize();
  float tanHalfY = gIn_Frame.frame.view.projection.y;
  float frustumWidth = 2.0f * tanHalfY * x.viewZ * min(size.x, size.y) / size.y;
  float hitFraction = hit > 0.0f ? hit / frustumWidth : 1.0f;
  float lobePixels = 0.0f;
  if (specular) {
    vec3 v = normalize(viewPosition(gIn_Frame.frame.view) - x.position);
    float alpha = r * r;
    float dominant = ggxDominantFactor(alpha);
    float cosDominant = abs(dot(x.normal, ggxDominantDirection(x.normal, v, alpha)));
    float reach = hit > 0.0f ? hit : frustumWidth;
    float lobeWorld = reach * cosDominant * r * sqrt(kPrePassLobeShare / (1.0f - kPrePassLobeShare));
    float pixelWorld = 2.0f * tanHalfY * (x.viewZ + reach * dominant) / size.y;
    lobePixels = lobeWorld / max(pixelWorld, 1e-6f);
  }
  float radius = max(prePassRadius(maxRadius, hitFraction, r, specular, lobePixels),
                     d.minBlurRadius * (specular ? specularMagicCurve(r) : 1.0f));

  float normalizedHit = normalizedHitDistance(d.hitDistanceParameters, hit, x.viewZ, r);
  float historyWeight = 1.0f / (1.0f + kPrePassHistoryFrames);
  float rotation = diskRotation(d.frameIndex, 4u + gSignals.indices[slot]);
  NeighbourWeighting weighting = neighbourWeighting(slot, x, roughness, kPrePassHistoryFrames, kPrePassWidening);
  vec3 sum = center.xyz;
  float weightSum = 1.0f;
  // Hit distances average over the taps that know theirs (0: unknown).
  float hitSum = hit;
  float hitWeightSum = hit > 0.0f ? 1.0f : 0.0f;
  for (uint i = 0u; i < 8u; ++i) {
    vec2 offset = diskTap(i, rotation);
    ivec2 tap = pixel + ivec2(round(offset * radius));
    if (!insideFull(tap)) continue;
    tap = tapWithSample(slot, tap, i);
    if (!insideFull(tap) || tap == pixel) continue;
    float tapRoughness;
    Surface y = denoiseSurfaceRoughness(tap, tapRoughness);
    float w = neighbourWeight(weighting, y, tapRoughness);
    if (w <= 0.0f) continue;
    vec4 s = signalAt(slot, tap);
    float tapNormalizedHit = normalizedHitDistance(d.hitDistanceParameters, s.w, y.viewZ, r);
    w *= hitDistanceWeight(normalizedHit, tapNormalizedHit, historyWeight, r, kHitWeightFloor);
    w *= exp(-0.66f * dot(offset, offset));
    if (specular && s.w > 0.0f) {
      // A neighbour's reflection of something nearer than the two points
      // are apart is another reflection (REBLUR's contact protection; rough lobes need it less).
      float apart = length(y.position - x.position);
      w *= mix(clamp(s.w / (apart + hit), 0.0f, 1.0f), 1.0f, clamp((r - 0.5f) / 0.5f, 0.0f, 1.0f));
    }
    sum += s.xyz * w;
    weightSum += w;
    if (s.w > 0.0f) {
      hitSum += s.w * w;
      hitWeightSum += w;
    }
  }
  float averageHit = hitWeightSum > 0.0f ? hitSum / hitWeightSum : 0.0f;
  return vec4(sanitizeRadiance(sum / weightSum), averageHit);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  float roughness;
  Surface x = denoiseSurfaceRoughness(pixel, roughness);
  bool surface = !tileEmpty(pixel) && x.viewZ > 0.0f;
  for (uint slot = 0u; slot < gSignals.count; ++slot)
    gOut_PrePassedStore(slot, pixel, surface ? prePassed(slot, pixel, x, roughness) : vec4(0.0f));
}
