// The material model's evaluation: Cook-Torrance GGX specular with Schlick
// Fresnel and height-correlated Smith masking-shadowing, plus Lambert diffuse
// weighted by (1 - metallic). One source for GLSL and C++ (lang.glsl).
//
// Roughness everywhere is the glTF perceptual roughness r; the GGX alpha is
// r * r, computed only in ggxAlpha(). Sampling and pdfs are in sampling.glsl;
// docs/material-model.md describes the whole model and its tests.
#ifndef BOUNCE_SHARED_BRDF_GLSL
#define BOUNCE_SHARED_BRDF_GLSL

#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

// Below this alpha the GGX lobe is a near-delta that float32 cannot evaluate
// (D overflows at the peak); punctual lights would give single-pixel
// fireflies. 0.0025 is perceptual roughness 0.05.
const float kMinGgxAlpha = 0.0025f;

float ggxAlpha(float perceptualRoughness) {
  float r = clamp(perceptualRoughness, 0.0f, 1.0f);
  return max(r * r, kMinGgxAlpha);
}

// F0 of the metallic workflow: 4 % for dielectrics, base colour for metals.
vec3 specularF0(vec3 baseColor, float metallic) { return mix(vec3(0.04f), baseColor, metallic); }

vec3 fresnelSchlick(vec3 f0, float cosTheta) {
  float m = clamp(1.0f - cosTheta, 0.0f, 1.0f);
  float m2 = m * m;
  return f0 + (vec3(1.0f) - f0) * (m2 * m2 * m);
}

// GGX normal distribution D(m) for cos(theta_m) = nDotH.
float ggxD(float nDotH, float alpha) {
  float a2 = alpha * alpha;
  float d = (nDotH * a2 - nDotH) * nDotH + 1.0f;
  return a2 / (kPi * d * d);
}

// ggxD from sin^2 and cos^2 of theta_m: the same value, but exact for the
// tiny angles of smooth lobes, where 1 - nDotH^2 in float is mostly rounding
// (at alpha = 0.0025 that moves D near its peak by a few per cent). The pdfs
// of sampling.glsl use it, with sin^2 from the normal's tangential part.
float ggxDSinCos(float sin2Theta, float cos2Theta, float alpha) {
  float a2 = alpha * alpha;
  float d = sin2Theta + a2 * cos2Theta;
  return a2 / (kPi * d * d);
}

// Smith Lambda for GGX; G1 = 1 / (1 + Lambda).
float ggxLambda(float cosTheta, float alpha) {
  float c2 = max(cosTheta * cosTheta, 1e-8f);
  float tan2 = max(1.0f - c2, 0.0f) / c2;
  return 0.5f * (sqrt(1.0f + alpha * alpha * tan2) - 1.0f);
}

float smithG1(float cosTheta, float alpha) { return 1.0f / (1.0f + ggxLambda(cosTheta, alpha)); }

// Height-correlated masking-shadowing (Heitz 2014).
float smithG2(float nDotL, float nDotV, float alpha) {
  return 1.0f / (1.0f + ggxLambda(nDotL, alpha) + ggxLambda(nDotV, alpha));
}

// Specular BRDF times cos(theta_l): D F G2 / (4 nDotV), zero below either horizon.
vec3 ggxSpecularCosine(vec3 n, vec3 v, vec3 l, vec3 f0, float alpha) {
  float nDotL = dot(n, l);
  float nDotV = dot(n, v);
  if (nDotL <= 0.0f || nDotV <= 0.0f) return vec3(0.0f);
  vec3 h = normalize(v + l);
  float nDotH = max(dot(n, h), 0.0f);
  float vDotH = max(dot(v, h), 0.0f);
  // D from the half vector's tangential part, |n x h|^2 = sin^2: for the
  // smoothest lobes 1 - cos^2 is all rounding error, and f cos / pdf of a
  // VNDF sample (whose pdf uses this form) would be off by percents.
  vec3 tangential = cross(n, h);
  float d = ggxDSinCos(dot(tangential, tangential), nDotH * nDotH, alpha);
  return fresnelSchlick(f0, vDotH) * (d * smithG2(nDotL, nDotV, alpha) / (4.0f * nDotV));
}

// Selectable diffuse lobes for materialBrdfCosineWithDiffuse. Lambert is the
// renderer's default (materialBrdfCosine); Burley is the Disney diffuse.
const int kDiffuseLambert = 0;
const int kDiffuseBurley = 1;

// Burley's diffuse (Burley 2012, "Physically-Based Shading at Disney") as a
// factor on Lambert: rough surfaces brighten towards grazing retro-reflection,
// smooth ones darken at grazing angles. Symmetric in l and v, so reciprocal.
// Takes the perceptual roughness, as Disney's model does.
float burleyDiffuseFactor(float nDotL, float nDotV, float lDotH, float perceptualRoughness) {
  float fd90 = 0.5f + 2.0f * clamp(perceptualRoughness, 0.0f, 1.0f) * lDotH * lDotH;
  float ml = clamp(1.0f - nDotL, 0.0f, 1.0f);
  float mv = clamp(1.0f - nDotV, 0.0f, 1.0f);
  float ml2 = ml * ml;
  float mv2 = mv * mv;
  return (1.0f + (fd90 - 1.0f) * (ml2 * ml2 * ml)) * (1.0f + (fd90 - 1.0f) * (mv2 * mv2 * mv));
}

// materialBrdfCosine with the diffuse lobe chosen by diffuseModel
// (kDiffuseLambert gives exactly materialBrdfCosine). Both diffuse lobes are
// importance-sampled by the cosine lobe of sampleMaterial (sampling.glsl).
vec3 materialBrdfCosineWithDiffuse(vec3 n, vec3 v, vec3 l, vec3 baseColor, float metallic, float perceptualRoughness,
                                   int diffuseModel) {
  float nDotL = dot(n, l);
  float nDotV = dot(n, v);
  if (nDotL <= 0.0f || nDotV <= 0.0f) return vec3(0.0f);
  float diffuseShape = 1.0f;
  if (diffuseModel == kDiffuseBurley) {
    vec3 h = normalize(v + l);
    diffuseShape = burleyDiffuseFactor(nDotL, nDotV, max(dot(l, h), 0.0f), perceptualRoughness);
  }
  vec3 diffuse = baseColor * ((1.0f - metallic) * kInvPi * nDotL * diffuseShape);
  return diffuse + ggxSpecularCosine(n, v, l, specularF0(baseColor, metallic), ggxAlpha(perceptualRoughness));
}

// The whole material (diffuse + specular) times cos(theta_l). The diffuse
// lobe is Lambert, scaled by (1 - metallic) since metals have no diffuse.
vec3 materialBrdfCosine(vec3 n, vec3 v, vec3 l, vec3 baseColor, float metallic, float perceptualRoughness) {
  return materialBrdfCosineWithDiffuse(n, v, l, baseColor, metallic, perceptualRoughness, kDiffuseLambert);
}

// Whether the light a surface of this roughness was seen sending towards
// `seen` (unit) stands for what it sends towards `wanted` (unit): last
// frame's screen holds the first, a ray arriving from `wanted` needs the
// second. Turning the outgoing direction by theta turns the half vector of
// any one light by theta / 2, so the question is how far the GGX peak falls
// over theta / 2: here, to no less than a quarter of its height, which
// solved for D gives cos(theta) (1 - alpha^2) >= 1 - 3 alpha^2 (theta up to
// about 2 alpha for smooth lobes, any angle at alpha 1). A glint of the sun
// on polished metal, seen from the camera, is not what the metal sends a
// nearby reflector; a rough wall's light is the same from every side.
bool reflectsAlikeTowards(vec3 seen, vec3 wanted, float perceptualRoughness) {
  float a2 = ggxAlpha(perceptualRoughness) * ggxAlpha(perceptualRoughness);
  return dot(seen, wanted) * (1.0f - a2) >= 1.0f - 3.0f * a2;
}

// The specular lobe's directional albedo: the fraction of uniform incoming
// light it reflects towards v, integral of F G2 D / (4 n.v) over the
// hemisphere. Karis's analytic fit ("Physically Based Shading on Mobile",
// 2014, after Lazarov 2013) of the split-sum DFG terms, F0 * A + B. Indirect
// specular is *demodulated* by this (divided by it) until composite, where it
// is multiplied back; the reference path tracer and the GI passes use this one
// function, so the two agree exactly whatever the fit's error (a few percent;
// tests/test_sampling.cpp measures it). Floored at kMinSpecularReflectance so
// that dividing by it stays finite for black metals.
const float kMinSpecularReflectance = 0.01f;
vec3 specularReflectance(vec3 f0, float nDotV, float perceptualRoughness) {
  float r = clamp(perceptualRoughness, 0.0f, 1.0f);
  float c = clamp(nDotV, 0.0f, 1.0f);
  float rx = 1.0f - r;
  float ry = 0.0425f - 0.0275f * r;
  float rz = 1.04f - 0.572f * r;
  float rw = 0.022f * r - 0.04f;
  float a004 = min(rx * rx, exp2(-9.28f * c)) * rx + ry;
  float scale = -1.04f * a004 + rz;
  float bias = 1.04f * a004 + rw;
  return max(f0 * scale + vec3(bias), vec3(kMinSpecularReflectance));
}

BOUNCE_SHARED_END

#endif
