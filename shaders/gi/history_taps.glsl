// Which of last frame's pixels around a reprojected position show the
// surface a pixel expects: the taps every history fetch weighs (the
// branches' temporal filters and the denoiser's temporal passes, through
// gi/temporal_history.glsl or directly). The including shader includes
// gi/gi_common.glsl first and declares gPrev_Surface (rg32ui).
#ifndef BOUNCE_GI_HISTORY_TAPS_GLSL
#define BOUNCE_GI_HISTORY_TAPS_GLSL

// Below this share of the bilinear weight the history counts as lost.
const float kMinHistoryWeight = 0.05f;

// Which surface a history tap must show.
struct ExpectedSurface {
  vec3 position;  // this frame's surface point
  vec3 normal;
  float viewZ;           // where the previous camera saw it (surface motion), or 0: test the plane (virtual motion)
  float depthTolerance;  // fraction of viewZ
  float cosNormalTolerance;
};

bool tapShows(ExpectedSurface expected, Surface then) {
  if (then.viewZ <= 0.0f || dot(expected.normal, then.normal) < expected.cosNormalTolerance) return false;
  if (expected.viewZ > 0.0f) return abs(then.viewZ - expected.viewZ) <= expected.depthTolerance * expected.viewZ;
  // Virtual motion lands elsewhere on the reflecting surface: the tap must lie on its plane.
  return abs(dot(expected.normal, then.position - expected.position)) <= expected.depthTolerance * then.viewZ;
}

// The bilinear weights of last frame's four pixels around continuous
// position `previous` (texel space: a pixel's centre + motion - 0.5),
// 0 for a tap off screen or not showing the expected surface; `corner` is
// the first tap, the others follow as (i & 1, i >> 1).
vec4 historyTapWeights(vec2 previous, ExpectedSurface expected, out ivec2 corner) {
  corner = ivec2(floor(previous));
  vec2 f = previous - vec2(corner);
  vec4 weights = vec4(0.0f);
  for (int i = 0; i < 4; ++i) {
    ivec2 tap = corner + ivec2(i & 1, i >> 1);
    if (!insideFull(tap)) continue;
    float weight = ((i & 1) == 1 ? f.x : 1.0f - f.x) * ((i >> 1) == 1 ? f.y : 1.0f - f.y);
    if (weight > 0.0f && tapShows(expected, historySurfaceAt(tap, imageLoad(gPrev_Surface, tap).xy))) weights[i] = weight;
  }
  return weights;
}

#endif
