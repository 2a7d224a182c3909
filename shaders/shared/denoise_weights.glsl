// The denoiser's math (gi/denoise, after NVIDIA's REBLUR): hit-distance
// normalisation, the edge-stopping weights of its spatial passes and their
// disk of taps, the history filter and the disocclusion test of its
// temporal pass, and the blend of surface and reflection (virtual) motion
// that it shares with the specular branch's temporal filter. One source for GLSL and C++ (lang.glsl); tests/
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

// Catmull-Rom weights (REBLUR's history filter) of the four taps at -1, 0,
// 1, 2 around a position `f` in [0, 1) past tap 0: sharper than bilinear,
// so a history resampled every frame for 30 frames keeps its detail. They
// sum to 1; the outer two are negative (the filter's overshoot).
vec4 catmullRomWeights(float f) {
  return vec4(f * (-0.5f + f * (1.0f - 0.5f * f)), 1.0f + f * f * (-2.5f + 1.5f * f),
              f * (0.5f + f * (2.0f - 1.5f * f)), f * f * (-0.5f + 0.5f * f));
}

// The 4x4 Catmull-Rom filter without its corners (12 taps) as 5 bilinear
// taps of a filtering sampler: the centre four in one, at the offset where
// bilinear weights them as the filter does (the two centre weights of each
// axis are positive), and each edge pair in one, on the edge texel's centre
// and at the centre tap's offset along the edge. Offsets from the first of
// the centre four (texel centres at integers); the weights sum to the 12
// taps' (the corners' share short of 1).
const int kCatmullRomBilinearTaps = 5;
struct CatmullRomBilinear {
  vec2 offsets[kCatmullRomBilinearTaps];
  float weights[kCatmullRomBilinearTaps];
};

CatmullRomBilinear catmullRomAsBilinear(vec2 f) {
  vec4 wx = catmullRomWeights(f.x), wy = catmullRomWeights(f.y);
  vec2 centreWeight = vec2(wx.y + wx.z, wy.y + wy.z);
  vec2 centre = vec2(wx.z, wy.z) / centreWeight;
  CatmullRomBilinear taps;
  taps.offsets[0] = centre;
  taps.weights[0] = centreWeight.x * centreWeight.y;
  taps.offsets[1] = vec2(-1.0f, centre.y);
  taps.weights[1] = wx.x * centreWeight.y;
  taps.offsets[2] = vec2(2.0f, centre.y);
  taps.weights[2] = wx.w * centreWeight.y;
  taps.offsets[3] = vec2(centre.x, -1.0f);
  taps.weights[3] = centreWeight.x * wy.x;
  taps.offsets[4] = vec2(centre.x, 2.0f);
  taps.weights[4] = centreWeight.x * wy.w;
  return taps;
}

// How far, as a fraction of the frustum's width at the pixel's depth, last
// frame's surface may lie from where this frame's was and still count as
// the same (REBLUR's disocclusion threshold): `threshold` seen head-on,
// wider as the surface turns away (n.v; a grazing floor's depth changes
// fast across a pixel), less so as the camera's parallax grows (in pixels:
// a large move sees the surface from elsewhere, where n.v says less), and
// 0.05 wider for a camera that barely moves (nothing can be uncovered).
float disocclusionReach(float threshold, float cosView, float parallaxPixels) {
  float relaxed = threshold + 0.05f * clamp(1.0f - parallaxPixels / 0.25f, 0.0f, 1.0f);
  float strictCosView = mix(abs(cosView), 1.0f, clamp(parallaxPixels / 30.0f, 0.0f, 1.0f));
  return clamp(relaxed / max(strictCosView, 0.01f), 0.0f, 1.0f);
}

// A surface's curvature along the edge from point x (normal n) to a
// neighbouring point y (normal m) of the same surface (REBLUR's estimate):
// how fast the normal turns per unit of distance, projected on the edge.
// 1 / R on a sphere of radius R seen from outside (convex), -1 / R from
// inside (concave), 0 on a plane; 0 where the two points coincide.
float surfaceCurvature(vec3 x, vec3 n, vec3 y, vec3 m) {
  vec3 edge = y - x;
  float lengthSquared = dot(edge, edge);
  return lengthSquared > 1e-12f ? dot(m - n, edge) / lengthSquared : 0.0f;
}

// Where a curved mirror shows what it reflects (REBLUR's thin-lens
// equation for a spherical mirror, focal length R / 2): the reflected point
// lies `hitDistance` away along the reflected ray; its image lies this far
// behind the surface. A plane (curvature 0) keeps the hit distance, a
// convex mirror pulls the image towards the surface, a concave one pushes
// it away and, past its focal point, in front of the surface (negative).
float thinLensImageDistance(float cosView, float hitDistance, float curvature) {
  float denominator = 2.0f * curvature * hitDistance * cosView + 1.0f;
  return abs(denominator) > 1e-6f ? hitDistance / denominator : hitDistance * 1e6f;
}

// The point whose motion a glossy reflection follows (REBLUR's virtual
// point): the mirror image along the view ray, `viewDirection` pointing
// from the camera to the surface at `x`, at the thin lens's image distance
// times the GGX lobe's dominant factor (a rough lobe's reflection sticks
// to the surface: factor 0).
vec3 virtualPoint(vec3 x, vec3 viewDirection, float cosView, float hitDistance, float curvature,
                  float dominantFactor) {
  return x + viewDirection * thinLensImageDistance(cosView, hitDistance, curvature) * dominantFactor;
}

// Reflection (virtual) motion against surface motion (the Jitter gi pass's
// dual-source reprojection): the prior for the virtual history, 1 on a
// mirror (its reflection swims over the surface with the view), 0 on rough
// surfaces (their reflection sticks to the surface).
float virtualHistoryPrior(float roughness) { return 1.0f - smoothstep(0.1f, 0.6f, roughness); }

// How well a history of luminance `history` agrees with this frame's local
// mean and deviation: a Gaussian in local deviations, 1.5 wide, so the
// source that reprojected the wrong reflection loses.
float historyAgreement(float history, float mean, float deviation) {
  float d = (history - mean) / (deviation + 0.05f * mean + 1e-4f);
  return exp(-0.5f * d * d / (1.5f * 1.5f));
}

// The share of the virtual history in the blend of both sources: the prior
// times each source's agreement.
float virtualHistoryShare(float prior, float virtualAgreement, float surfaceAgreement) {
  float wv = prior * virtualAgreement;
  float ws = (1.0f - prior) * surfaceAgreement;
  return wv + ws > 1e-6f ? wv / (wv + ws) : prior;
}

// REBLUR's "specular magic curve": 0 for a mirror, rising steeply to about
// 1 by roughness 0.2 and on to 1 at roughness 1: how much a lobe of this
// roughness may be blurred or its hit distance averaged.
float specularMagicCurve(float roughness) {
  float r = clamp(roughness, 0.0f, 1.0f);
  return (1.0f - exp2(-200.0f * r * r)) * pow(r, 0.25f);
}

// The pre-pass's radius in pixels (REBLUR's): `maxRadius` times the square
// root of how far the light came from, as a fraction of the frustum's
// width (`hitFraction`: hit distance / frustum width at the pixel; 1 where
// unknown); for specular also of the roughness, and no wider than the
// lobe's footprint at the hit (`lobePixels`: hit distance * n.d * the tan
// of the lobe's half angle, in pixels at the virtual image's depth), so a
// sharp reflection stays sharp.
float prePassRadius(float maxRadius, float hitFraction, float roughness, bool specular, float lobePixels) {
  float f = clamp(hitFraction, 0.0f, 1.0f);
  if (!specular) return maxRadius * sqrt(f);
  return min(maxRadius * sqrt(clamp(roughness, 0.0f, 1.0f) * f), lobePixels);
}

// The share of a tap whose normalised hit distance differs from the
// pixel's (REBLUR's hit-distance weight, exponential, over a reach that
// widens with the roughness and shrinks as the history grows), floored at
// `floor`: light from a much nearer or farther hit is another light.
float hitDistanceWeight(float normalizedHit, float tapNormalizedHit, float historyWeight, float roughness,
                        float floor) {
  float reach = mix(0.0005f, 1.0f, min(historyWeight, specularMagicCurve(roughness)));
  float x = 3.0f * abs(tapNormalizedHit - normalizedHit) / reach;
  return mix(floor, 1.0f, 1.0f / (x * x + x + 1.0f));
}

// The rotation (radians) of the spatial passes' disk in a frame: the same
// for every pixel (REBLUR's per-frame rotation; neighbouring pixels then
// read neighbouring texels, which a per-pixel rotation scatters over the
// caches), turning by the golden ratio of a turn a frame, offset per pass,
// so the history averages the pattern away.
float diskRotation(uint frameIndex, uint pass) {
  return fract(float(frameIndex % 4096u) * 0.618034f + float(pass) * 0.381966f) * 6.28318531f;
}

// 8 taps in the unit disk (a golden-angle spiral, radii sqrt((i + 0.5) / 8)):
// even coverage, rotated per frame (diskRotation).
vec2 diskTap(uint i, float rotation) {
  float radius = sqrt((float(i) + 0.5f) / 8.0f);
  float angle = float(i) * 2.39996323f + rotation;
  return radius * vec2(cos(angle), sin(angle));
}

BOUNCE_SHARED_END

#endif
