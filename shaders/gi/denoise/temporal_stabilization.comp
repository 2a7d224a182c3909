#version 460
#extension GL_GOOGLE_include_directive : require
// gi.denoise.temporal_stabilization: each post-blurred signal blended with last frame's stabilised output, reprojected like temporal
// accumulation, after clamping that history to the post-blurred 3x3
// neighbourhood's mean +- clamp_sigma sigma (REBLUR's stabilisation with
// its anti-lag: light that changed is not dragged along). Its history
// keeps at most gi.denoise.stabilization_frames frames (0: off, the output
// is the post-blur's). The output is the denoiser's result for the
// composite and next frame's stabilisation history; alpha: its history
// length. The signals of a dispatch share the reprojection's four taps.
#include "gi/gi_common.glsl"
#define DENOISE_READS_TILES
#include "gi/denoise/denoise_common.glsl"
#include "shared/color.glsl"

// 16x16 pixels a workgroup (one denoiser tile), sharing their neighbourhood.
const int kGroupSize = 16;
layout(local_size_x = kGroupSize, local_size_y = kGroupSize) in;

layout(set = 0, binding = 5) uniform sampler2D gIn_Motion;
layout(set = 0, binding = 7, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 10, rg32ui) readonly uniform uimage2D gIn_Surface;
DENOISE_SLOT_IMAGES(readonly, gIn_Filtered, 20)
DENOISE_SLOT_TEXTURES(gPrev_Stabilized, 24)
DENOISE_SLOT_IMAGES(writeonly, gOut_Stabilized, 28)
DENOISE_SLOT_LOAD(gIn_Filtered)
DENOISE_SLOT_SAMPLE(gPrev_Stabilized)
DENOISE_SLOT_STORE(gOut_Stabilized)
#define LIGHT_CHANGE_BINDING 16
#include "gi/light_change/light_change.glsl"

#include "gi/motion.glsl"
#define NEIGHBOURHOOD_AT(slot, pixel) gIn_FilteredAt(slot, pixel)
#include "gi/denoise/neighbourhood_tile.glsl"
#include "gi/history_taps.glsl"

// Where last frame's stabilised values lie for the pixel's surface: the
// bilinear weights of the four taps that showed it (all 0 where none can).
vec4 stabilizedTapWeights(Surface x, ivec2 pixel, out ivec2 corner) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  corner = ivec2(0);
  vec2 motion = motionAt(pixel);
  if (!usableMotion(motion)) return vec4(0.0f);
  float expectedViewZ = projectToScreen(gIn_Frame.frame.previousView, x.position, fullSize()).z;
  if (!(expectedViewZ > 0.0f)) return vec4(0.0f);
  uint material = materialOf(imageLoad(gIn_Surface, pixel).xy);
  return historyTapWeights(vec2(pixel) + motion, ExpectedSurface(x.position, x.normal, expectedViewZ,
                                                                 d.depthTolerance, d.cosNormalTolerance, material),
                           corner);
}

// A slot's stabilised value of last frame over those taps; w: its history
// length, 0 if none showed the surface. Where all four show it, their
// weights are bilinear's: one filtered fetch.
vec4 stabilizedHistory(uint slot, ivec2 corner, vec4 weights) {
  if (all(greaterThan(weights, vec4(0.0f))))
    return gPrev_StabilizedLinear(slot, vec2(corner) + vec2(weights.y + weights.w, weights.z + weights.w));
  vec4 sum = vec4(0.0f);
  float weightSum = 0.0f;
  for (int i = 0; i < 4; ++i) {
    if (weights[i] <= 0.0f) continue;
    sum += gPrev_StabilizedAt(slot, corner + ivec2(i & 1, i >> 1)) * weights[i];
    weightSum += weights[i];
  }
  return weightSum > kMinHistoryWeight ? sum / weightSum : vec4(0.0f);
}

// A slot's stabilised value at the pixel.
vec4 stabilized(uint slot, ivec2 pixel, ivec2 corner, vec4 weights) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  vec3 current = gIn_FilteredAt(slot, pixel).xyz;
  vec4 history = signalHasHistory(slot) ? stabilizedHistory(slot, corner, weights) : vec4(0.0f);
  if (history.w <= 0.0f) return roundedToHalf(vec4(current, 1.0f));
  // The neighbourhood's luminance statistics bound the history (anti-lag).
  float mean = 0.0f, meanSquare = 0.0f, count = 0.0f;
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      vec2 texel = neighbourhoodTexel(slot, ivec2(i, j));
      if (texel.y == 0.0f) continue;
      float l = texel.x;
      mean += l;
      meanSquare += l * l;
      count += 1.0f;
    }
  mean /= count;
  float sigma = sqrt(max(meanSquare / count - mean * mean, 0.0f));
  float reach = d.clampSigma * sigma + 1e-4f * mean;
  float historyLuminance = luminance(history.xyz);
  float clamped = clamp(historyLuminance, max(mean - reach, 0.0f), mean + reach);
  vec3 previous = historyLuminance > 0.0f ? history.xyz * (clamped / historyLuminance) : vec3(clamped);
  float frames = min(historyAfterLightChange(history.w) + 1.0f, d.stabilizationFrames);
  return roundedToHalf(vec4(sanitizeRadiance(mix(previous, current, 1.0f / frames)), frames));
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  // The group is one tile: it leaves whole, before the shared load.
  if (tileEmpty(pixel)) {
    if (insideFull(pixel))
      for (uint slot = 0u; slot < gSignals.count; ++slot) gOut_StabilizedStore(slot, pixel, vec4(0.0f));
    return;
  }
  loadNeighbourhoodTile();
  if (!insideFull(pixel)) return;
  Surface x = denoiseSurface(pixel);
  if (x.viewZ <= 0.0f) {
    for (uint slot = 0u; slot < gSignals.count; ++slot) gOut_StabilizedStore(slot, pixel, vec4(0.0f));
    return;
  }
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  bool anyHistory = false;
  for (uint slot = 0u; slot < gSignals.count; ++slot) anyHistory = anyHistory || signalHasHistory(slot);
  ivec2 corner = ivec2(0);
  vec4 weights = d.stabilizationFrames > 0.0f && anyHistory ? stabilizedTapWeights(x, pixel, corner) : vec4(0.0f);
  for (uint slot = 0u; slot < gSignals.count; ++slot)
    gOut_StabilizedStore(slot, pixel, stabilized(slot, pixel, corner, weights));
}
