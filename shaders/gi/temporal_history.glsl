// What the branches' temporal filters and the denoiser's temporal
// accumulation share: a bilinear (or Catmull-Rom) history fetch whose taps
// count only where they saw the surface the pixel expects
// (gi/history_taps.glsl), the reflection's (virtual) history of specular
// light and its blend with the surface's, and the clamp of that history to
// the fast history. The including shader includes gi/gi_common.glsl first
// and declares gPrev_Surface (rg32ui) and the history it reads: by
// default gPrev_Filtered (radiance, history length) and gPrev_Moments
// (luminance moments as shared/moments.glsl stores them: mean and deviation
// over the history, mean of the fast history; decoded a tap at a time, so
// that interpolation averages mean squares, as the moments it stands for).
// A shader that keeps several signals' histories (the denoiser, one slot
// per signal) defines HISTORY_FILTERED(slot, tap) and
// HISTORY_MOMENTS(slot, tap) first: the taps are tested once for every
// signal (catmullRomFootprint, historyTapWeights) and each slot's history
// read with those weights. One that samples its history through a
// filtering sampler also defines HISTORY_FILTERED_LINEAR(slot, position)
// (bilinear at a continuous texel-space position, texel centres at
// integers): a fetch where all the taps count takes one bilinear tap for
// four, and the Catmull-Rom fetch (catmullRomHistory, which needs it) five
// for twelve.
#ifndef BOUNCE_GI_TEMPORAL_HISTORY_GLSL
#define BOUNCE_GI_TEMPORAL_HISTORY_GLSL

#include "gi/history_taps.glsl"
#include "shared/color.glsl"
#include "shared/denoise_weights.glsl"
#include "shared/moments.glsl"

#ifndef HISTORY_FILTERED
#define HISTORY_FILTERED(slot, tap) imageLoad(gPrev_Filtered, tap)
#define HISTORY_MOMENTS(slot, tap) imageLoad(gPrev_Moments, tap)
#endif

// The fast history averages about this many frames (REBLUR's fast history).
const float kFastFrames = 6.0f;

struct History {
  bool found;
  vec3 radiance;
  vec3 moments;  // long history: mean, mean square; fast history: mean
  float frames;  // history length
};

History noHistory() {
  History h;
  h.found = false;
  h.radiance = vec3(0.0f);
  h.moments = vec3(0.0f);
  h.frames = 0.0f;
  return h;
}

// Slot `slot`'s history over last frame's four pixels from `corner` (as
// historyTapWeights gives them), bilinear over the taps of weight > 0.
History bilinearHistory(uint slot, ivec2 corner, vec4 weights) {
  History h = noHistory();
  vec4 accumulated = vec4(0.0f);
  vec3 accumulatedMoments = vec3(0.0f);
  float weightSum = 0.0f;
#ifdef HISTORY_FILTERED_LINEAR
  // All four count: their weights are bilinear's, one filtered fetch.
  bool allFour = all(greaterThan(weights, vec4(0.0f)));
  if (allFour)
    accumulated = HISTORY_FILTERED_LINEAR(slot, vec2(corner) + vec2(weights.y + weights.w, weights.z + weights.w)) *
                  (weights.x + weights.y + weights.z + weights.w);
#else
  const bool allFour = false;
#endif
  for (int i = 0; i < 4; ++i) {
    if (weights[i] <= 0.0f) continue;
    ivec2 tap = corner + ivec2(i & 1, i >> 1);
    if (!allFour) accumulated += HISTORY_FILTERED(slot, tap) * weights[i];
    accumulatedMoments += momentsFromStored(HISTORY_MOMENTS(slot, tap)) * weights[i];
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

// Last frame's filtered value at continuous pixel position `previous`
// (texel space: a pixel's centre + motion - 0.5), bilinear over the taps
// that show the expected surface.
History fetchHistory(uint slot, vec2 previous, ExpectedSurface expected) {
  ivec2 corner;
  vec4 weights = historyTapWeights(previous, expected, corner);
  return bilinearHistory(slot, corner, weights);
}

// The same fetch with a Catmull-Rom filter (REBLUR's), in two steps: which
// of the 12 taps of its 4x4 footprint without the corners show the
// expected surface (catmullRomFootprint, once for every signal), then a
// slot's history over them (catmullRomHistory, for a shader that defines
// HISTORY_FILTERED_LINEAR): Catmull-Rom where all 12 show it, in five
// bilinear fetches (shared/denoise_weights.glsl, catmullRomAsBilinear);
// else bilinear over the centre four that do (an edge, a disocclusion),
// as fetchHistory. Only the radiance is filtered sharply;
// the moments and the history length are bilinear, as REBLUR's fast
// history is. The overshoot of the negative lobes is cut at 0.
struct HistoryFootprint {
  ivec2 origin;  // the first of the centre four
  vec2 f;        // the position past it
  uint shows;    // bit (i + 1) + 4 (j + 1) for the tap at origin + (i, j), i and j in -1..2
};
const uint kFootprintAllShow = 0x6FF6u;  // the 12 taps: all but the corners 0, 3, 12, 15

HistoryFootprint catmullRomFootprint(vec2 previous, ExpectedSurface expected) {
  HistoryFootprint footprint;
  footprint.origin = ivec2(floor(previous));
  footprint.f = previous - vec2(footprint.origin);
  footprint.shows = 0u;
  for (int j = -1; j <= 2; ++j)
    for (int i = -1; i <= 2; ++i) {
      if ((i == -1 || i == 2) && (j == -1 || j == 2)) continue;
      ivec2 tap = footprint.origin + ivec2(i, j);
      if (insideFull(tap) && tapShows(expected, tap, imageLoad(gPrev_Surface, tap).xy))
        footprint.shows |= 1u << uint((i + 1) + 4 * (j + 1));
    }
  return footprint;
}

#ifdef HISTORY_FILTERED_LINEAR
History catmullRomHistory(uint slot, HistoryFootprint footprint) {
  History h = noHistory();
  vec2 f = footprint.f;
  // The centre four that show the surface, weighed bilinearly.
  vec4 centreWeights = vec4(0.0f);
  for (int i = 0; i < 4; ++i) {
    uint bit = 1u << uint(((i & 1) + 1) + 4 * ((i >> 1) + 1));
    if ((footprint.shows & bit) != 0u)
      centreWeights[i] = ((i & 1) == 1 ? f.x : 1.0f - f.x) * ((i >> 1) == 1 ? f.y : 1.0f - f.y);
  }
  float bilinearWeight = centreWeights.x + centreWeights.y + centreWeights.z + centreWeights.w;
  if (bilinearWeight <= kMinHistoryWeight) return h;
  h.found = true;
  vec2 origin = vec2(footprint.origin);
  if (footprint.shows == kFootprintAllShow) {
    // All 12 show it: Catmull-Rom in five bilinear fetches, and the
    // history length bilinear in a sixth.
    CatmullRomBilinear taps = catmullRomAsBilinear(f);
    vec3 sharp = vec3(0.0f);
    float sharpWeight = 0.0f;
    for (int t = 0; t < kCatmullRomBilinearTaps; ++t) {
      sharp += HISTORY_FILTERED_LINEAR(slot, origin + taps.offsets[t]).xyz * taps.weights[t];
      sharpWeight += taps.weights[t];
    }
    h.radiance = max(sharp / sharpWeight, vec3(0.0f));
    h.frames = HISTORY_FILTERED_LINEAR(slot, origin + f).w;
  } else {
    vec4 bilinear = vec4(0.0f);
    for (int i = 0; i < 4; ++i)
      if (centreWeights[i] > 0.0f)
        bilinear += HISTORY_FILTERED(slot, footprint.origin + ivec2(i & 1, i >> 1)) * centreWeights[i];
    h.radiance = bilinear.xyz / bilinearWeight;
    h.frames = bilinear.w / bilinearWeight;
  }
  for (int i = 0; i < 4; ++i)
    if (centreWeights[i] > 0.0f)
      h.moments += momentsFromStored(HISTORY_MOMENTS(slot, footprint.origin + ivec2(i & 1, i >> 1))) * centreWeights[i];
  h.moments /= bilinearWeight;
  return h;
}
#endif

// Where last frame's camera saw the reflection's (virtual) point of a
// specular pixel (shared/denoise_weights.glsl, virtualPoint): behind the
// surface along the view ray, at the hit distance for a flat mirror
// (curvature 0, dominant factor 1), nearer for a convex one and a rougher
// lobe. z <= 0 where the point was behind last frame's camera.
vec3 virtualReprojection(Surface x, float hitDistance, float curvature, float dominantFactor) {
  vec3 viewDirection = normalize(x.position - viewPosition(gIn_Frame.frame.view));
  float cosView = abs(dot(x.normal, viewDirection));
  vec3 point = virtualPoint(x.position, viewDirection, cosView, hitDistance, curvature, dominantFactor);
  return projectToScreen(gIn_Frame.frame.previousView, point, fullSize());
}

// The reflection's (virtual) history of a specular pixel: last frame's
// pixels around where last frame's camera saw the reflection
// (virtualReprojection, `projected`), on the pixel's reflector, whose plane
// (and material, unless kAnyMaterial) the taps must have. Not found where
// the point was behind last frame's camera.
History fetchVirtualHistory(uint slot, Surface x, vec3 projected, float depthTolerance, float cosNormalTolerance,
                            uint material) {
  History h = noHistory();
  if (projected.z <= 0.0f) return h;
  return fetchHistory(slot, vec2(projected) - 0.5f,
                      ExpectedSurface(x.position, x.normal, 0.0f, depthTolerance, cosNormalTolerance, material));
}

// Surface and virtual histories blended: each weighs its prior (by
// roughness) times its agreement with this frame's local luminance mean and
// deviation; `virtualShare` comes back with the virtual one's share.
History blendReflectionHistories(History surface, History virtualHistory, float roughness, float mean,
                                 float deviation, out float virtualShare) {
  virtualShare = 0.0f;
  if (surface.found && virtualHistory.found)
    virtualShare = virtualHistoryShare(virtualHistoryPrior(roughness),
                                       historyAgreement(luminance(virtualHistory.radiance), mean, deviation),
                                       historyAgreement(luminance(surface.radiance), mean, deviation));
  else if (virtualHistory.found)
    virtualShare = 1.0f;
  History history = virtualShare >= 1.0f ? virtualHistory : surface;
  if (virtualShare > 0.0f && virtualShare < 1.0f) {
    history.radiance = mix(surface.radiance, virtualHistory.radiance, virtualShare);
    history.moments = mix(surface.moments, virtualHistory.moments, virtualShare);
    history.frames = mix(surface.frames, virtualHistory.frames, virtualShare);
  }
  return history;
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
