// One function that exercises every shared-math function on one input. The
// GPU test runs it in tests/shared_math_check.comp, the CPU runs the same
// source through the C++ shim, and the test compares the two.
#ifndef BOUNCE_TESTS_SHARED_MATH_CHECK_GLSL
#define BOUNCE_TESTS_SHARED_MATH_CHECK_GLSL
#include "shared/color.glsl"
#include "shared/finite.glsl"
#include "shared/intersect.glsl"
#include "shared/packing.glsl"
#include "shared/rng.glsl"
#include "shared/brdf.glsl"
#include "shared/sampling.glsl"

BOUNCE_SHARED_BEGIN

struct SharedMathCheckInput {
  vec4 values;  // each in [0,1)
  uvec4 bits;   // random 32-bit words
};

struct SharedMathCheckOutput {
  uvec4 integers;  // pcgHash, rngSeed, rngNext, packNormalOct32
  vec4 scalars;    // rngUniform, luminance, srgbEncode, srgbDecode
  vec4 normalHit;  // unpackNormalOct32 (xyz), intersectSphere (w)
  vec4 display;    // tonemapAcesFitted (xyz), displayEncode (w, red channel)
  vec4 material;   // luminance of materialBrdfCosine, pdfMaterial, specularReflectance (red), pdf of sampleMaterial
  vec4 sampled;    // sampleMaterial's direction (xyz), 1 if it returned a sample (w)
  vec4 finite;     // bits.xyzw as floats (NaN and infinity among them): isFinite of each as bits 0-3 of x;
                   // sanitizeRadiance of the first three (yzw)
};

SharedMathCheckOutput runSharedMathCheck(SharedMathCheckInput args) {
  SharedMathCheckOutput result;
  uint state = args.bits.w;
  uint next = rngNext(state);
  float uniformValue = rngUniform(state);
  vec3 direction = vec3(args.values.x, args.values.y, args.values.z) * 2.0f - vec3(1.0f);
  vec3 normal = dot(direction, direction) > 1e-6f ? normalize(direction) : vec3(0.0f, 0.0f, 1.0f);
  uint packedNormal = packNormalOct32(normal);
  result.integers = uvec4(pcgHash(args.bits.x), rngSeed(uvec2(args.bits.y & 0xffffu, args.bits.y >> 16u),
                                                        args.bits.z, args.bits.w & 7u), next, packedNormal);
  vec3 radiance = vec3(args.values.x, args.values.y, args.values.z) * 8.0f;
  result.scalars = vec4(uniformValue, luminance(radiance), srgbEncode(args.values.w),
                        srgbDecode(args.values.x));
  float t = intersectSphere(vec3(0.0f), normal, vec3(0.5f, 0.25f, 2.0f) * (args.values.w * 2.0f),
                            0.2f + args.values.w, 1e-4f);
  result.normalHit = vec4(unpackNormalOct32(packedNormal), t);
  result.display = vec4(tonemapAcesFitted(radiance), displayEncode(radiance, 1.0f).x);

  // The material model at a random surface and view (some below the horizon).
  // One random number per statement: C++ leaves the order in which a call's
  // arguments are evaluated open, GLSL does not.
  uint materialState = args.bits.z;
  float r0 = rngUniform(materialState);
  float r1 = rngUniform(materialState);
  float r2 = rngUniform(materialState);
  vec3 jitter = vec3(r0, r1, r2) * 2.0f - vec3(1.0f);
  vec3 view = normalize(normal * 1.05f + jitter);
  vec3 light = normalize(normal * 1.05f - jitter * 0.7f);
  vec3 baseColor = vec3(args.values.z, args.values.y, args.values.x);
  float metallic = args.values.x > 0.5f ? 1.0f : args.values.y;
  float roughness = 0.1f + 0.9f * args.values.w;
  float u0 = rngUniform(materialState);
  float u1 = rngUniform(materialState);
  float u2 = rngUniform(materialState);
  vec3 u = vec3(u0, u1, u2);
  vec3 sampledDirection;
  float sampledPdf;
  bool sampled = sampleMaterial(normal, view, baseColor, metallic, roughness, u, sampledDirection, sampledPdf);
  result.material = vec4(luminance(materialBrdfCosine(normal, view, light, baseColor, metallic, roughness)),
                         pdfMaterial(normal, view, light, baseColor, metallic, roughness),
                         specularReflectance(specularF0(baseColor, metallic), dot(normal, view), roughness).x,
                         sampledPdf);
  result.sampled = vec4(sampledDirection, sampled ? 1.0f : 0.0f);

  // Random words hold NaN and infinity (all exponent bits set) one time in 256.
  vec4 words = vec4(uintBitsToFloat(args.bits.x), uintBitsToFloat(args.bits.y), uintBitsToFloat(args.bits.z),
                    uintBitsToFloat(args.bits.w));
  float finiteMask = (isFinite(words.x) ? 1.0f : 0.0f) + (isFinite(words.y) ? 2.0f : 0.0f) +
                     (isFinite(words.z) ? 4.0f : 0.0f) + (isFinite(words.w) ? 8.0f : 0.0f);
  result.finite = vec4(finiteMask, sanitizeRadiance(vec3(words.x, words.y, words.z)));
  return result;
}

BOUNCE_SHARED_END
#endif
