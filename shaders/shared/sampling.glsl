// Importance sampling of the material model (brdf.glsl) with matching pdfs,
// plus the sample sequences that feed it. One source for GLSL and C++
// (lang.glsl); tests/test_sampling.cpp checks every sampler against its pdf
// (chi-square) and docs/material-model.md describes the model and results.
//
// Conventions: the local shading frame has z = the normal (x, y from
// buildOrthonormalBasis); "view" v and "light" l both point away from the
// surface; every pdf is per unit solid angle; every direction is unit length.
// alpha is the GGX alpha (ggxAlpha of the perceptual roughness).
//
// Frames:
//   buildOrthonormalBasis(n, t, b)      t, b, n right-handed, branchless (Duff et al. 2017)
// Hemisphere samplers (local frame):
//   sampleConcentricDisk(u)             the unit disk, area-preserving (Shirley and Chiu 1997)
//   sampleCosineHemisphere(u)           pdfCosineHemisphere(cosTheta) = cosTheta / pi
//   sampleUniformHemisphere(u)          pdfUniformHemisphere() = 1 / (2 pi)
// GGX visible normals (Heitz 2018), local frame, viewLocal.z > 0:
//   sampleGgxVisibleNormal(v, alpha, u) a microfacet normal m ~ D_v(m) = G1(v) max(0, v.m) D(m) / v.z
//   pdfGgxVisibleNormal(v, m, alpha)    D_v(m)
//   smithG1OverCos(cosThetaV, alpha)    G1(v) / v.z, finite down to v.z = 0
//   ggxReflectionPdf(nDotV, sin2ThetaH, cos2ThetaH, alpha)
//                                       pdfGgxReflection from n.v and the half vector's angle (any frame)
//   pdfGgxReflection(v, l, alpha)       pdf of l = reflect(-v, m): D_v(m) / (4 v.m) = G1(v) D(m) / (4 v.z);
//                                       0 for l below the horizon (those samples are rejected, so it
//                                       integrates over the upper hemisphere to the share of valid ones)
//   ggxReflectionWeight(f0, vDotH, nDotL, nDotV, alpha)
//                                       F G2 / G1: ggxSpecularCosine / pdfGgxReflection, the estimator
//                                       weight of a VNDF sample (no D, no division by a pdf)
// The whole material (world space):
//   specularSelectionProbability(baseColor, metallic, nDotV)
//                                       chance of sampling the specular lobe (see its comment)
//   sampleMaterial(n, v, ..., u, direction, pdf)
//                                       one-sample MIS over the two lobes; pdf is the combined pdf
//   pdfMaterial(n, v, l, ...)           that combined pdf; pdfMaterial(direction) == pdf exactly
// Uniform sampling of the specular lobe (ReSTIR GI for specular): a cone
// around an axis the caller picks (ggxDominantDirection), uniform in solid
// angle, so the pdf depends on the roughness only, never on the view:
//   ggxLobeHalfAngle(alpha, fraction)   half-angle of the cone around n holding `fraction` of D(m) cos(theta_m)
//   specularLobeHalfAngle(alpha, fraction)
//                                       the reflected directions' cone: twice that, at most pi / 2
//   sampleSpecularLobeUniform(axis, halfAngle, u)          world space direction
//   pdfSpecularLobeUniform(halfAngle)   1 / (2 pi (1 - cos halfAngle)) inside the cone
//   isInSpecularLobe(axis, halfAngle, direction)           the membership test a reused sample must pass
// GGX dominant direction (Lagarde and de Rousiers 2014, the REBLUR analysis, appendix):
//   ggxDominantFactor(alpha)            lerp factor from n (rough) to the mirror direction (smooth)
//   ggxDominantDirection(n, v, alpha)   normalize(mix(n, reflect(-v, n), factor))
// Sample sequences, each returning a point of [0, 1)^2:
//   unitFloatFromBits(bits)             top 24 bits to [0, 1)
//   radicalInverseBase2(i), radicalInverseBase3(i)
//   haltonPixelSample(sampleIndex, pixelSeed)
//                                       Halton (2, 3), a kHaltonCycleLength-point cycle, per-pixel start
//                                       offset and Cranley-Patterson rotation
//   r2Point(i), r2PixelSample(pixel, frame)
//                                       the R2 sequence (Roberts 2018) over frames, shifted per pixel by a
//                                       lattice so that neighbouring pixels get distant points
#ifndef BOUNCE_SHARED_SAMPLING_GLSL
#define BOUNCE_SHARED_SAMPLING_GLSL

#include "shared/brdf.glsl"
#include "shared/color.glsl"
#include "shared/lang.glsl"
#include "shared/rng.glsl"

BOUNCE_SHARED_BEGIN

// --- Frames

// Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT 2017): no
// branch, no normalisation, and accurate for every n, including n.z = -1.
void buildOrthonormalBasis(vec3 n, OUT(vec3) t, OUT(vec3) b) {
  float s = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (s + n.z);
  float c = n.x * n.y * a;
  t = vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
  b = vec3(c, s + n.y * n.y * a, -n.y);
}

// --- Hemispheres

// Shirley and Chiu's concentric map from the square to the unit disk: it keeps
// strata (and the low discrepancy of Halton or R2 points) nearly intact, which
// the polar map (r = sqrt(u.x)) squeezes at the centre.
vec2 sampleConcentricDisk(vec2 u) {
  float a = 2.0f * u.x - 1.0f;
  float b = 2.0f * u.y - 1.0f;
  if (a == 0.0f && b == 0.0f) return vec2(0.0f);
  float radius;
  float phi;
  if (abs(a) > abs(b)) {
    radius = a;
    phi = 0.25f * kPi * (b / a);
  } else {
    radius = b;
    phi = 0.5f * kPi - 0.25f * kPi * (a / b);
  }
  return vec2(radius * cos(phi), radius * sin(phi));
}

// Malley's method: a uniform disk point lifted to the hemisphere.
vec3 sampleCosineHemisphere(vec2 u) {
  vec2 d = sampleConcentricDisk(u);
  return vec3(d.x, d.y, sqrt(max(0.0f, 1.0f - d.x * d.x - d.y * d.y)));
}

float pdfCosineHemisphere(float cosTheta) { return max(cosTheta, 0.0f) * kInvPi; }

vec3 sampleUniformHemisphere(vec2 u) {
  float cosTheta = u.x;
  float sinTheta = sqrt(max(0.0f, 1.0f - cosTheta * cosTheta));
  float phi = 2.0f * kPi * u.y;
  return vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
}

float pdfUniformHemisphere() { return 0.5f * kInvPi; }

// --- GGX visible normals

// G1(v) / cos(theta_v), the normalisation of the visible-normal distribution,
// written so that it stays finite as cos(theta_v) -> 0 (it tends to 2 / alpha)
// where G1 / cos would divide two vanishing numbers.
float smithG1OverCos(float cosThetaV, float alpha) {
  float c = max(cosThetaV, 0.0f);
  return 2.0f / (c + sqrt(alpha * alpha + (1.0f - alpha * alpha) * c * c));
}

// Heitz, "Sampling the GGX Distribution of Visible Normals" (JCGT 2018):
// stretch the view to the alpha = 1 configuration, sample the projected
// visible half-disk of the unit hemisphere there, and unstretch. Requires
// viewLocal.z > 0; the returned normal always faces the view (v.m >= 0).
vec3 sampleGgxVisibleNormal(vec3 viewLocal, float alpha, vec2 u) {
  vec3 stretched = normalize(vec3(alpha * viewLocal.x, alpha * viewLocal.y, viewLocal.z));
  float lengthSquared = stretched.x * stretched.x + stretched.y * stretched.y;
  vec3 t1 = lengthSquared > 0.0f ? vec3(-stretched.y, stretched.x, 0.0f) * inversesqrt(lengthSquared)
                                 : vec3(1.0f, 0.0f, 0.0f);
  vec3 t2 = cross(stretched, t1);
  float radius = sqrt(u.x);
  float phi = 2.0f * kPi * u.y;
  float p1 = radius * cos(phi);
  float p2 = radius * sin(phi);
  // Fold the lower half of the disk onto the part of the hemisphere the
  // tilted view still sees.
  float s = 0.5f * (1.0f + stretched.z);
  p2 = (1.0f - s) * sqrt(max(0.0f, 1.0f - p1 * p1)) + s * p2;
  vec3 stretchedNormal = p1 * t1 + p2 * t2 + sqrt(max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * stretched;
  return normalize(vec3(alpha * stretchedNormal.x, alpha * stretchedNormal.y, max(0.0f, stretchedNormal.z)));
}

// D evaluated from the normal's tangential part (ggxDSinCos), so that the
// pdf stays exact for the smoothest lobes.
float pdfGgxVisibleNormal(vec3 viewLocal, vec3 normalLocal, float alpha) {
  if (viewLocal.z <= 0.0f || normalLocal.z <= 0.0f) return 0.0f;
  float sin2Theta = normalLocal.x * normalLocal.x + normalLocal.y * normalLocal.y;
  return smithG1OverCos(viewLocal.z, alpha) * max(dot(viewLocal, normalLocal), 0.0f) *
         ggxDSinCos(sin2Theta, normalLocal.z * normalLocal.z, alpha);
}

// The reflection's Jacobian 1 / (4 v.h) cancels the v.h of the visible-normal
// pdf, leaving a function of cos(theta_v) and theta_h alone.
float ggxReflectionPdf(float nDotV, float sin2ThetaH, float cos2ThetaH, float alpha) {
  return 0.25f * smithG1OverCos(nDotV, alpha) * ggxDSinCos(sin2ThetaH, cos2ThetaH, alpha);
}

float pdfGgxReflection(vec3 viewLocal, vec3 lightLocal, float alpha) {
  if (viewLocal.z <= 0.0f || lightLocal.z <= 0.0f) return 0.0f;
  vec3 h = normalize(viewLocal + lightLocal);
  return ggxReflectionPdf(viewLocal.z, h.x * h.x + h.y * h.y, h.z * h.z, alpha);
}

// f cos / pdf of a VNDF-sampled reflection: D and the 4 v.n cancel, leaving
// Fresnel times the share of the visible microfacets that also see the light.
// At most 1, with no pdf to divide by: the Jitter gi pass's weight for reservoir samples.
vec3 ggxReflectionWeight(vec3 f0, float vDotH, float nDotL, float nDotV, float alpha) {
  if (nDotL <= 0.0f || nDotV <= 0.0f) return vec3(0.0f);
  return fresnelSchlick(f0, vDotH) * (smithG2(nDotL, nDotV, alpha) / smithG1(nDotV, alpha));
}

// --- The whole material

// Neither lobe's probability goes below this while the lobe carries energy,
// so that one-sample MIS keeps the estimator f cos / pdf bounded (by 1 / 0.1
// times each lobe's albedo) even where the energy estimate below is poor.
const float kMinLobeProbability = 0.1f;

// The chance of sampling the specular lobe: its share of the estimated
// reflected energy. Specular is estimated by the Fresnel reflectance at the
// view angle (luminance of F(F0, n.v)), diffuse by its albedo, luminance of
// baseColor * (1 - metallic) (the model's Lambert lobe has no Fresnel
// factor). Clamped to [0.1, 0.9]; exactly 1 when there is no diffuse lobe
// (metals, black dielectrics), so no sample is wasted on a lobe with no energy.
float specularSelectionProbability(vec3 baseColor, float metallic, float nDotV) {
  float diffuse = luminance(baseColor) * (1.0f - metallic);
  if (diffuse <= 0.0f) return 1.0f;
  float specular = luminance(fresnelSchlick(specularF0(baseColor, metallic), max(nDotV, 0.0f)));
  return clamp(specular / (specular + diffuse), kMinLobeProbability, 1.0f - kMinLobeProbability);
}

// Views closer to the horizon than this are not sampled (sampleMaterial
// returns false, pdfMaterial 0): below it ggxLambda clamps cos(theta_v), so
// materialBrdfCosine overestimates G2 / (4 n.v) against the exact G1 / n.v of
// the VNDF pdf and f cos / pdf would grow like 1e-4 / n.v. Such views are a
// sliver of a silhouette pixel; terminating their paths loses nothing visible.
const float kMinViewCosine = 1e-4f;

// The pdf of sampleMaterial: p_s pdfGgxReflection + (1 - p_s) cos / pi, with
// p_s = specularSelectionProbability. World space; 0 below either horizon.
float pdfMaterial(vec3 n, vec3 v, vec3 l, vec3 baseColor, float metallic, float perceptualRoughness) {
  float nDotV = dot(n, v);
  float nDotL = dot(n, l);
  if (nDotV < kMinViewCosine || nDotL <= 0.0f) return 0.0f;
  float specularProbability = specularSelectionProbability(baseColor, metallic, nDotV);
  vec3 h = normalize(v + l);
  float cosThetaH = dot(n, h);
  vec3 tangentialH = cross(n, h);  // |n x h| = sin(theta_h), exact where 1 - cos^2 is not
  float specularPdf =
      ggxReflectionPdf(nDotV, dot(tangentialH, tangentialH), cosThetaH * cosThetaH, ggxAlpha(perceptualRoughness));
  return specularProbability * specularPdf + (1.0f - specularProbability) * pdfCosineHemisphere(nDotL);
}

// Samples materialBrdfCosine: u.z picks the lobe (specular if u.z < p_s), u.x
// and u.y sample it (GGX VNDF reflection or the cosine hemisphere). Returns
// false, with pdf = 0, when v is below the horizon (or within kMinViewCosine
// of it) or the sample is (a VNDF reflection can leave the hemisphere). pdf
// is the combined pdf of both lobes, computed by pdfMaterial itself so that
// the two agree bit for bit (MIS against light sampling needs that); the
// estimator is then materialBrdfCosine(n, v, direction, ...) / pdf.
bool sampleMaterial(vec3 n, vec3 v, vec3 baseColor, float metallic, float perceptualRoughness, vec3 u,
                    OUT(vec3) direction, OUT(float) pdf) {
  direction = n;
  pdf = 0.0f;
  float nDotV = dot(n, v);
  if (nDotV < kMinViewCosine) return false;
  vec3 t;
  vec3 b;
  buildOrthonormalBasis(n, t, b);
  vec3 viewLocal = vec3(dot(v, t), dot(v, b), nDotV);
  vec3 lightLocal;
  if (u.z < specularSelectionProbability(baseColor, metallic, nDotV)) {
    vec3 m = sampleGgxVisibleNormal(viewLocal, ggxAlpha(perceptualRoughness), vec2(u.x, u.y));
    lightLocal = reflect(-viewLocal, m);
  } else {
    lightLocal = sampleCosineHemisphere(vec2(u.x, u.y));
  }
  if (lightLocal.z <= 0.0f) return false;
  direction = normalize(t * lightLocal.x + b * lightLocal.y + n * lightLocal.z);
  pdf = pdfMaterial(n, v, direction, baseColor, metallic, perceptualRoughness);
  return pdf > 0.0f;
}

// --- Uniform sampling of the specular lobe

// The angle around n within which `fraction` of the microfacet normals'
// projected area D(m) cos(theta_m) lies: the GGX cdf in theta_m,
// tan^2 / (alpha^2 + tan^2), inverted. REBLUR sizes its blur by such an angle;
// here it sizes the cone of uniform lobe sampling.
float ggxLobeHalfAngle(float alpha, float fraction) {
  float f = clamp(fraction, 0.0f, 0.999999f);
  return atan(alpha * sqrt(f / (1.0f - f)));
}

// The cone of reflected directions: reflection doubles the angle of the
// microfacet normal, exactly so at normal incidence (where this cone holds
// exactly `fraction` of the VNDF-sampled reflections). At most a hemisphere.
float specularLobeHalfAngle(float alpha, float fraction) {
  return min(2.0f * ggxLobeHalfAngle(alpha, fraction), 0.5f * kPi);
}

// Uniform in solid angle over the cone of half-angle halfAngle around axis
// (world space). Works with 1 - cos(theta) throughout: for a smooth lobe cos
// is within float rounding of 1, and sin computed from it would be noise.
// Directions may fall below the surface's horizon; callers reject those.
vec3 sampleSpecularLobeUniform(vec3 axis, float halfAngle, vec2 u) {
  float sinHalf = sin(0.5f * halfAngle);
  float oneMinusCos = u.x * 2.0f * sinHalf * sinHalf;
  float sinTheta = sqrt(max(0.0f, oneMinusCos * (2.0f - oneMinusCos)));
  float phi = 2.0f * kPi * u.y;
  vec3 t;
  vec3 b;
  buildOrthonormalBasis(axis, t, b);
  return normalize(t * (sinTheta * cos(phi)) + b * (sinTheta * sin(phi)) + axis * (1.0f - oneMinusCos));
}

// The same for every view and every direction in the cone, which is what lets
// reservoirs of such samples be reused across pixels and frames.
float pdfSpecularLobeUniform(float halfAngle) {
  float sinHalf = sin(0.5f * halfAngle);
  return 1.0f / (4.0f * kPi * sinHalf * sinHalf);
}

// Whether direction is in the cone; compares chord lengths, |d - axis|^2 =
// 4 sin^2(angle / 2), which unlike dot products keeps its precision for
// narrow cones.
bool isInSpecularLobe(vec3 axis, float halfAngle, vec3 direction) {
  vec3 chord = direction - axis;
  float sinHalf = sin(0.5f * halfAngle);
  return dot(chord, chord) <= 4.0f * sinHalf * sinHalf;
}

// --- GGX dominant direction

// Lagarde and de Rousiers, "Moving Frostbite to PBR" (2014), the reference
// the REBLUR analysis gives for REBLUR's dominant direction (REBLUR also has fits that
// depend on n.v; this one depends on alpha alone): the peak of the GGX BRDF
// times cos moves from the mirror direction towards the normal as the
// surface gets rougher.
float ggxDominantFactor(float alpha) {
  float smoothness = clamp(1.0f - alpha, 0.0f, 1.0f);
  return smoothness * (sqrt(smoothness) + alpha);
}

vec3 ggxDominantDirection(vec3 n, vec3 v, float alpha) {
  return normalize(mix(n, reflect(-v, n), ggxDominantFactor(alpha)));
}

// --- Sample sequences

// Top 24 bits to a float in [0, 1): exact, and never 1.0.
float unitFloatFromBits(uint bits) { return float(bits >> 8u) * (1.0f / 16777216.0f); }

float radicalInverseBase2(uint index) { return unitFloatFromBits(bitfieldReverse(index)); }

float radicalInverseBase3(uint index) {
  float result = 0.0f;
  float scale = 1.0f / 3.0f;
  while (index > 0u) {
    result += float(index % 3u) * scale;
    index /= 3u;
    scale *= 1.0f / 3.0f;
  }
  return min(result, 0.99999994f);
}

// The Jitter gi pass's specular ReSTIR cycles through the first 64 Halton points: few enough that a pixel
// covers its whole set within a short history, many enough to stratify a lobe.
const uint kHaltonCycleLength = 64u;

// Point sampleIndex of one pixel's Halton (2, 3) cycle. pixelSeed (constant
// over frames for the pixel, e.g. rngSeed(pixel, 0, pass)) picks where in the
// cycle the pixel starts, so neighbours do not use the same point in the same
// frame, and a Cranley-Patterson rotation (a toroidal shift), so neighbours do
// not share one point set. Pass the frame index as sampleIndex.
vec2 haltonPixelSample(uint sampleIndex, uint pixelSeed) {
  uint startOffset = pcgHash(pixelSeed);
  uint index = (sampleIndex + startOffset) % kHaltonCycleLength;
  uint rotationX = pcgHash(startOffset);
  uint rotationY = pcgHash(rotationX);
  vec2 point = vec2(radicalInverseBase2(index), radicalInverseBase3(index));
  return fract(point + vec2(unitFloatFromBits(rotationX), unitFloatFromBits(rotationY)));
}

// The R2 sequence's steps 1/g and 1/g^2 (g = 1.3247..., the plastic number)
// in 0.32 fixed point: integer wrap-around is the fract(), with no rounding
// at any index, where fract(float(index) * 0.7548...) keeps fewer bits of
// the fraction every time index doubles (none past 2^24).
const uint kR2StepX = 3242174889u;
const uint kR2StepY = 2447445414u;
// The pixel lattice's steps, the squares of the R2 steps (mod 1). Deliberately
// not R2 steps: with those a neighbouring pixel would replay this pixel's
// sequence one frame later, and temporal filters would see the echo.
const uint kR2PixelStepX = 2447445414u;
const uint kR2PixelStepY = 1394653007u;

vec2 r2Point(uint index) {
  return vec2(unitFloatFromBits(index * kR2StepX + 2147483648u), unitFloatFromBits(index * kR2StepY + 2147483648u));
}

// Frame `frame` of the pixel's R2 sequence (low discrepancy over time),
// shifted by a rank-1 lattice over pixels (Roberts' R2 dither mask idea in
// two dimensions): neighbouring pixels are far apart on the torus in every
// frame, a blue-noise-like pattern without a texture.
vec2 r2PixelSample(uvec2 pixel, uint frame) {
  uint shiftX = pixel.x * kR2PixelStepX + pixel.y * kR2PixelStepY;
  uint shiftY = pixel.x * kR2PixelStepY + pixel.y * kR2PixelStepX;
  return vec2(unitFloatFromBits(frame * kR2StepX + 2147483648u + shiftX),
              unitFloatFromBits(frame * kR2StepY + 2147483648u + shiftY));
}

BOUNCE_SHARED_END

#endif
