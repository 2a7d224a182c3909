// What the branches' temporal filters and the denoiser's temporal
// accumulation share: a bilinear history fetch whose taps count only where
// they saw the surface the pixel expects (gi/history_taps.glsl), and the
// clamp of that history to the fast history. The including shader
// includes gi/gi_common.glsl first and declares gPrev_Surface (rg32ui),
// gPrev_Filtered (rgba32f: radiance, history length) and gPrev_Moments
// (rgba32f: luminance mean and mean square over the history, mean of the
// fast history).
#ifndef BOUNCE_GI_TEMPORAL_HISTORY_GLSL
#define BOUNCE_GI_TEMPORAL_HISTORY_GLSL

#include "gi/history_taps.glsl"
#include "shared/color.glsl"

// The fast history averages about this many frames (REBLUR's fast history).
const float kFastFrames = 6.0f;

struct History {
  bool found;
  vec3 radiance;
  vec3 moments;  // long history: mean, mean square; fast history: mean
  float frames;  // history length
};

// Last frame's filtered value at continuous pixel position `previous`
// (texel space: a pixel's centre + motion - 0.5), bilinear over the taps
// that show the expected surface.
History fetchHistory(vec2 previous, ExpectedSurface expected) {
  History h;
  h.found = false;
  h.radiance = vec3(0.0f);
  h.moments = vec3(0.0f);
  h.frames = 0.0f;
  ivec2 corner;
  vec4 weights = historyTapWeights(previous, expected, corner);
  vec4 accumulated = vec4(0.0f);
  vec3 accumulatedMoments = vec3(0.0f);
  float weightSum = 0.0f;
  for (int i = 0; i < 4; ++i) {
    if (weights[i] <= 0.0f) continue;
    ivec2 tap = corner + ivec2(i & 1, i >> 1);
    accumulated += imageLoad(gPrev_Filtered, tap) * weights[i];
    accumulatedMoments += imageLoad(gPrev_Moments, tap).xyz * weights[i];
    weightSum += weights[i];
  }
  if (weightSum > kMinHistoryWeight) {
    h.found = true;
    h.radiance = vec3(accumulated) / weightSum;
    h.moments = accumulatedMoments / weightSum;
    h.frames = accumulated.w / weightSum;
  }
  return h;
}

// Adds this frame (its luminance and luminance squared, `fresh`: of the
// pixel, or averaged over a neighbourhood; blend weight 1 / frames) to the
// moments and clamps the history's luminance to the fast history +- gamma
// times the deviation: where light changes, the fast history moves within
// a few frames and drags the long one along. `moments` comes back updated.
vec3 clampToFastHistory(vec3 history, INOUT(vec3) moments, vec2 freshMoments, float blend, float gamma) {
  vec3 fresh = vec3(freshMoments.x, freshMoments.y, freshMoments.x);
  moments = vec3(mix(vec2(moments), vec2(fresh), blend), mix(moments.z, fresh.z, max(blend, 1.0f / kFastFrames)));
  float sigma = sqrt(max(moments.y - moments.x * moments.x, 0.0f));
  float reach = gamma * sigma;
  float historyLuminance = luminance(history);
  float clipped = clamp(historyLuminance, max(moments.z - reach, 0.0f), moments.z + reach);
  // A black history raised by the clamp turns grey; taking `current` in its
  // place would count this frame in full where it should count 1 / frames.
  return historyLuminance > 0.0f ? history * (clipped / historyLuminance) : vec3(clipped);
}

#endif
