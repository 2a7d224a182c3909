// Which of last frame's pixels around a reprojected position show the
// surface a pixel expects: the taps every history fetch weighs (the
// branches' temporal filters and the denoiser's temporal passes, through
// gi/temporal_history.glsl or directly). The including shader includes
// gi/gi_common.glsl first and declares gPrev_Surface (rg32ui).
#ifndef BOUNCE_GI_HISTORY_TAPS_GLSL
#define BOUNCE_GI_HISTORY_TAPS_GLSL

// Below this share of the bilinear weight the history counts as lost.
const float kMinHistoryWeight = 0.05f;
// An expected material that every tap matches (the passes that do not read this frame's ids).
const uint kAnyMaterial = 0xFFFFFFFFu;

// Which surface a history tap must show.
struct ExpectedSurface {
  vec3 position;  // this frame's surface point
  vec3 normal;
  float viewZ;           // where the previous camera saw it (surface motion), or 0: test the plane (virtual motion)
  float depthTolerance;  // fraction of viewZ
  float cosNormalTolerance;
  uint material;  // this frame's material id (low 8 bits; gi.store_history), or kAnyMaterial
};

// This frame's material id at a pixel, from this frame's history surface
// (gi.store_history), for ExpectedSurface::material.
uint materialOf(uvec2 packedSurface) { return unpackMaterialOfNormalMaterial(packedSurface.y); }

// Whether last frame's pixel `tap` (its gi.history_surface texel `packed`)
// shows the expected surface, of the expected material. The depth test
// comes first and the tap's position is rebuilt only for the plane test:
// most taps cost a compare.
bool tapShows(ExpectedSurface expected, ivec2 tap, uvec2 packed) {
  float viewZ = uintBitsToFloat(packed.x);
  if (viewZ <= 0.0f) return false;
  if (expected.viewZ > 0.0f && abs(viewZ - expected.viewZ) > expected.depthTolerance * expected.viewZ) return false;
  if (expected.material != kAnyMaterial && unpackMaterialOfNormalMaterial(packed.y) != expected.material) return false;
  if (dot(expected.normal, unpackNormalOfNormalMaterial(packed.y)) < expected.cosNormalTolerance) return false;
  if (expected.viewZ > 0.0f) return true;
  // Virtual motion lands elsewhere on the reflecting surface: the tap must lie on its plane.
  vec3 position = reconstructPosition(gIn_Frame.frame.previousView, vec2(tap), viewZ, fullSize());
  return abs(dot(expected.normal, position - expected.position)) <= expected.depthTolerance * viewZ;
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
    if (weight > 0.0f && tapShows(expected, tap, imageLoad(gPrev_Surface, tap).xy)) weights[i] = weight;
  }
  return weights;
}

#endif
