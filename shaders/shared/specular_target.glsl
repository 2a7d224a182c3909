// The specular branch's reservoirs (the Jitter gi pass's specular ReSTIR and Zyanide's uniform-lobe reservoirs): the same 32-byte
// Reservoir as the diffuse branch (shared/reservoir.glsl: the hit point, its
// normal and radiance, or a direction into the environment), weighed by
// target functions of the glossy surface that shades them. One source for
// GLSL and C++; tests/test_specular_target.cpp tests them.
//
// Two ways to draw the sample (gi::SpecularSampling):
//   VNDF     GGX visible normals reflected about the view: pdf
//            pdfGgxReflection, target p-hat = luminance(f cos L). One
//            candidate has W = 1 / pdf, and f cos L W = F G2 / G1 L (the Jitter
//            gi pass's weight, ggxReflectionWeight).
//   Uniform  uniform in a cone around the lobe's dominant direction (Zyanide's
//            uniform-lobe reservoirs): the pdf is the same for every view, and the target
//            p-hat = luminance(L) inside the cone (0 outside) ignores the
//            view too, so a stored reservoir stays valid when the camera
//            moves. Shading then resamples such reservoirs with the real
//            BRDF (specularShadingTarget), a reservoir used once and thrown away.
#ifndef BOUNCE_SHARED_SPECULAR_TARGET_GLSL
#define BOUNCE_SHARED_SPECULAR_TARGET_GLSL

#include "shared/brdf.glsl"
#include "shared/color.glsl"
#include "shared/lang.glsl"
#include "shared/reservoir.glsl"
#include "shared/sampling.glsl"

BOUNCE_SHARED_BEGIN

const uint kSpecularSamplingVndf = 0u;
const uint kSpecularSamplingUniform = 1u;

// A glossy surface as the specular passes see it.
struct GlossySurface {
  vec3 position;
  vec3 normal;
  vec3 view;  // unit, from the surface towards the camera
  vec3 f0;    // specular reflectance at normal incidence
  float roughness;  // perceptual
  float alpha;      // GGX alpha = roughness^2 (ggxAlpha)
};

GlossySurface glossySurface(vec3 position, vec3 normal, vec3 view, vec3 baseColor, float metallic,
                            float perceptualRoughness) {
  GlossySurface s;
  s.position = position;
  s.normal = normal;
  s.view = view;
  s.f0 = specularF0(baseColor, metallic);
  s.roughness = clamp(perceptualRoughness, 0.0f, 1.0f);
  s.alpha = ggxAlpha(s.roughness);
  return s;
}

// The cone uniform sampling draws from: around the dominant direction.
vec3 specularLobeAxis(GlossySurface s) { return ggxDominantDirection(s.normal, s.view, s.alpha); }
float specularLobeCone(GlossySurface s, float lobeFraction) { return specularLobeHalfAngle(s.alpha, lobeFraction); }

// Whether the sample can light s at all: it arrives from above s's horizon
// and, for a point on a surface, that surface faces s.
bool specularSampleReaches(Reservoir r, GlossySurface s, vec3 direction) {
  if (dot(s.normal, direction) <= 0.0f) return false;
  return reservoirIsEnvironment(r) || dot(r.normal, direction) < 0.0f;
}

// f cos L of the sample at s (before W): what shading sums.
vec3 specularSampleContribution(Reservoir r, GlossySurface s) {
  vec3 direction = sampleDirection(r, s.position);
  if (!specularSampleReaches(r, s, direction)) return vec3(0.0f);
  return ggxSpecularCosine(s.normal, s.view, direction, s.f0, s.alpha) * r.radiance;
}

// The BRDF-weighted target, p-hat' = luminance(f cos L): VNDF reservoirs'
// own target, and the disposable reservoir's of uniform sampling.
float specularShadingTarget(Reservoir r, GlossySurface s) {
  return luminance(specularSampleContribution(r, s));
}

// The target a reservoir of `sampling` is stored with, at s.
float specularTargetPdf(Reservoir r, GlossySurface s, uint sampling, float lobeFraction) {
  if (sampling != kSpecularSamplingUniform) return specularShadingTarget(r, s);
  vec3 direction = sampleDirection(r, s.position);
  if (!specularSampleReaches(r, s, direction)) return 0.0f;
  // Zyanide's uniform-lobe reservoirs: a sample outside this surface's cone could never have been
  // drawn here; rejecting it is what keeps the uniform pdf valid.
  if (!isInSpecularLobe(specularLobeAxis(s), specularLobeCone(s, lobeFraction), direction)) return 0.0f;
  return luminance(r.radiance);
}

// Whether specularTargetPdf(r, s, ...) can be positive: the geometry alone
// (the sample reaches s; and s faces the camera, or for uniform sampling
// its cone holds the sample), without the BRDF. Equal to specularTargetPdf > 0 wherever the
// sample's radiance and s's F0 are not black (a black one makes the target
// 0 where this says true). The resolve's coverage count, which asks it of
// every pair of its reservoirs, needs only this much.
bool specularTargetCovers(Reservoir r, GlossySurface s, uint sampling, float lobeFraction) {
  vec3 direction = sampleDirection(r, s.position);
  if (!specularSampleReaches(r, s, direction)) return false;
  if (sampling == kSpecularSamplingUniform)
    return isInSpecularLobe(specularLobeAxis(s), specularLobeCone(s, lobeFraction), direction);
  return dot(s.normal, s.view) > 0.0f;
}

// Draws the direction of one pixel's ray (u from the pixel's Halton cycle);
// false when it leaves the hemisphere (a VNDF reflection can, and a cone
// around a grazing dominant direction too). pdf is per unit solid angle.
bool sampleSpecularDirection(GlossySurface s, uint sampling, float lobeFraction, vec2 u, OUT(vec3) direction,
                             OUT(float) pdf) {
  direction = s.normal;
  pdf = 0.0f;
  float nDotV = dot(s.normal, s.view);
  if (nDotV <= 0.0f) return false;
  if (sampling == kSpecularSamplingUniform) {
    float cone = specularLobeCone(s, lobeFraction);
    direction = sampleSpecularLobeUniform(specularLobeAxis(s), cone, u);
    pdf = pdfSpecularLobeUniform(cone);
  } else {
    vec3 t;
    vec3 b;
    buildOrthonormalBasis(s.normal, t, b);
    vec3 viewLocal = vec3(dot(s.view, t), dot(s.view, b), nDotV);
    vec3 m = sampleGgxVisibleNormal(viewLocal, s.alpha, u);
    vec3 lightLocal = reflect(-viewLocal, m);
    if (lightLocal.z <= 0.0f) return false;
    direction = normalize(t * lightLocal.x + b * lightLocal.y + s.normal * lightLocal.z);
    pdf = pdfGgxReflection(viewLocal, lightLocal, s.alpha);
  }
  return dot(s.normal, direction) > 0.0f && pdf > 0.0f && isFinite(pdf);
}

// How many reservoirs the resolve evaluates at this roughness: one for a
// mirror (its lobe holds no other pixel's sample), rising linearly to
// maxSamples at fullRoughness (the Jitter gi pass's wish: rough lobes need more).
uint resolveSampleCount(float perceptualRoughness, uint maxSamples, float fullRoughness) {
  float t = clamp(perceptualRoughness / max(fullRoughness, 1e-4f), 0.0f, 1.0f);
  return clamp(uint(floor(1.0f + t * float(maxSamples - 1u) + 0.5f)), 1u, maxSamples);
}

// The radius (world units, at the shaded surface) within which neighbours'
// samples are likely to lie in this lobe too: the lobe's footprint where
// the reflected rays meet the scene, hit distance times tan of the cone
// holding most of the lobe (REBLUR sizes its specular blur the same way).
// Capped by the caller in pixels; 0 for a mirror.
float specularFootprintRadius(float hitDistance, float alpha) {
  float cone = specularLobeHalfAngle(alpha, 0.75f);
  return hitDistance * tan(min(cone, 1.4f));
}

BOUNCE_SHARED_END
#endif
