// CPU tests of shaders/shared/specular_target.glsl: the specular branch's
// sampling and target functions. A VNDF sample's f cos / pdf is the Jitter gi pass's
// F G2 / G1; its estimator integrates the lobe (white furnace against an
// independent uniform-hemisphere estimate); the uniform-cone target ignores
// the view inside the cone and rejects outside it; the resolve's geometric
// coverage test agrees with the target being positive; Zyanide's two-level
// resampling (view-independent reservoirs, then a disposable one with the
// BRDF target) converges to the lobe integral over the cone; the resolve's
// sample count and the reuse footprint behave at the ends.
#include <gtest/gtest.h>

#include <cmath>

#include "shared/rng.glsl"
#include "shared/specular_target.glsl"

namespace {

using namespace bounce::shared;

vec3 randomUnit(uint& rng) {
  float z = 2.0f * rngUniform(rng) - 1.0f;
  float phi = 2.0f * kPi * rngUniform(rng);
  float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  return vec3(r * std::cos(phi), r * std::sin(phi), z);
}

// A surface at the origin facing +z, seen from `view` (unit, above the horizon).
GlossySurface surface(vec3 view, float roughness, vec3 baseColor = vec3(0.9f, 0.6f, 0.3f), float metallic = 1.0f) {
  return glossySurface(vec3(0.0f), vec3(0.0f, 0.0f, 1.0f), normalize(view), baseColor, metallic, roughness);
}

// An environment sample in `direction` with radiance L.
Reservoir environmentSample(vec3 direction, vec3 radiance) {
  Reservoir r = emptyReservoir();
  r.position = direction;
  r.radiance = radiance;
  r.flags = kReservoirHasSample | kReservoirEnvironment;
  return r;
}

// An environment whose radiance depends on the direction (so resampling has something to prefer).
vec3 skyRadiance(vec3 d) { return vec3(0.2f + 3.0f * std::max(d.x, 0.0f), 0.5f, 0.2f + d.y * d.y); }

TEST(SpecularTarget, VndfSampleWeightIsFresnelTimesG2OverG1) {
  uint rng = rngSeed(uvec2(1, 2), 0u, 7u);
  for (int i = 0; i < 2000; ++i) {
    vec3 view = randomUnit(rng);
    view.z = std::abs(view.z) + 0.05f;
    float roughness = 0.05f + 0.95f * rngUniform(rng);
    GlossySurface s = surface(view, roughness);
    vec3 direction;
    float pdf;
    float u0 = rngUniform(rng);
    float u1 = rngUniform(rng);
    if (!sampleSpecularDirection(s, kSpecularSamplingVndf, 0.9f, vec2(u0, u1), direction, pdf)) continue;
    vec3 weight = specularSampleContribution(environmentSample(direction, vec3(1.0f)), s) / pdf;
    vec3 h = normalize(s.view + direction);
    vec3 expected = ggxReflectionWeight(s.f0, dot(s.view, h), direction.z, dot(s.normal, s.view), s.alpha);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(weight[c], expected[c], 1e-2f * std::max(1.0f, expected[c])) << i;
  }
}

// The mean of f cos L / pdf over VNDF samples against the same integral
// estimated with uniform hemisphere directions.
TEST(SpecularTarget, VndfEstimatorIntegratesTheLobe) {
  for (float roughness : {0.3f, 0.6f, 1.0f}) {
    GlossySurface s = surface(vec3(0.5f, 0.2f, 0.8f), roughness);
    uint rng = rngSeed(uvec2(3, 4), 0u, 11u);
    const int n = 400000;
    double vndf = 0.0;
    double uniform = 0.0;
    for (int i = 0; i < n; ++i) {
      float u0 = rngUniform(rng);
      float u1 = rngUniform(rng);
      vec3 direction;
      float pdf;
      if (sampleSpecularDirection(s, kSpecularSamplingVndf, 0.9f, vec2(u0, u1), direction, pdf))
        vndf += luminance(specularSampleContribution(environmentSample(direction, skyRadiance(direction)), s)) / pdf;
      float v0 = rngUniform(rng);
      float v1 = rngUniform(rng);
      vec3 d = sampleUniformHemisphere(vec2(v0, v1));
      uniform += luminance(specularSampleContribution(environmentSample(d, skyRadiance(d)), s)) / pdfUniformHemisphere();
    }
    EXPECT_NEAR(vndf / n, uniform / n, 0.03 * uniform / n) << "roughness " << roughness;
  }
}

TEST(SpecularTarget, UniformTargetIgnoresTheViewInsideTheConeAndRejectsOutside) {
  GlossySurface a = surface(vec3(0.4f, 0.0f, 0.9f), 0.5f);
  GlossySurface b = surface(vec3(0.35f, 0.05f, 0.92f), 0.5f);
  const vec3 radiance(2.0f, 1.0f, 0.5f);
  // The two cones' shared middle: between the two axes.
  vec3 inBoth = normalize(specularLobeAxis(a) + specularLobeAxis(b));
  Reservoir r = environmentSample(inBoth, radiance);
  EXPECT_FLOAT_EQ(specularTargetPdf(r, a, kSpecularSamplingUniform, 0.9f), luminance(radiance));
  EXPECT_FLOAT_EQ(specularTargetPdf(r, b, kSpecularSamplingUniform, 0.9f), luminance(radiance));
  // The BRDF target changes with the view.
  EXPECT_NE(specularTargetPdf(r, a, kSpecularSamplingVndf, 0.9f), specularTargetPdf(r, b, kSpecularSamplingVndf, 0.9f));
  // Outside a smooth surface's cone, and below the horizon: rejected.
  GlossySurface smooth = surface(vec3(0.4f, 0.0f, 0.9f), 0.3f);
  EXPECT_EQ(specularTargetPdf(environmentSample(normalize(vec3(0.6f, 0.0f, 0.8f)), radiance), smooth,
                              kSpecularSamplingUniform, 0.9f),
            0.0f);
  EXPECT_EQ(specularTargetPdf(environmentSample(vec3(-0.4f, 0.0f, -0.9f), radiance), a, kSpecularSamplingUniform, 0.9f),
            0.0f);
}

// The resolve's coverage test says the same as the target being positive,
// for surface and environment samples around surfaces seen from any side,
// both samplings, smooth to rough, whenever radiance and F0 are not black.
TEST(SpecularTarget, CoversExactlyWhereTheTargetIsPositive) {
  uint rng = 17u;
  int positive = 0, zero = 0;
  for (int i = 0; i < 20000; ++i) {
    vec3 normal = randomUnit(rng);
    vec3 view = randomUnit(rng);
    float roughness = rngUniform(rng);
    GlossySurface s = glossySurface(vec3(0.0f), normal, view, vec3(0.2f + 0.8f * rngUniform(rng)),
                                    rngUniform(rng), roughness);
    Reservoir r = emptyReservoir();
    r.radiance = vec3(1.0f, 0.5f, 0.25f);
    r.flags = kReservoirHasSample;
    if (i % 2 == 0) {
      r.position = randomUnit(rng);
      r.flags |= kReservoirEnvironment;
    } else {
      r.position = randomUnit(rng) * (0.1f + 4.0f * rngUniform(rng));
      r.normal = randomUnit(rng);
    }
    for (uint sampling : {kSpecularSamplingVndf, kSpecularSamplingUniform}) {
      bool target = specularTargetPdf(r, s, sampling, 0.9f) > 0.0f;
      ASSERT_EQ(specularTargetCovers(r, s, sampling, 0.9f), target) << "sample " << i << " sampling " << sampling;
      (target ? positive : zero) += 1;
    }
  }
  // Both answers were asked about often.
  EXPECT_GT(positive, 2000);
  EXPECT_GT(zero, 2000);
}

// Seed 003's two levels: reservoirs of uniform cone samples with p-hat = L
// (streamed, as temporal reuse does), then a disposable reservoir that
// resamples several of them with p-hat' = luminance(f cos L). Its estimate
// converges to the lobe integral over the cone.
TEST(SpecularTarget, TwoLevelResamplingConvergesToTheConeIntegral) {
  GlossySurface s = surface(vec3(0.5f, 0.1f, 0.85f), 0.6f);
  const float fraction = 0.9f;
  const float cone = specularLobeCone(s, fraction);
  const vec3 axis = specularLobeAxis(s);
  uint rng = rngSeed(uvec2(5, 6), 0u, 13u);
  // The truth: f cos L integrated over the cone, uniformly.
  double truth = 0.0;
  const int truthSamples = 400000;
  for (int i = 0; i < truthSamples; ++i) {
    float u0 = rngUniform(rng);
    float u1 = rngUniform(rng);
    vec3 d = sampleSpecularLobeUniform(axis, cone, vec2(u0, u1));
    truth += luminance(specularSampleContribution(environmentSample(d, skyRadiance(d)), s)) /
             pdfSpecularLobeUniform(cone);
  }
  truth /= truthSamples;

  const int trials = 60000;
  const int candidates = 4;  // uniform candidates per stored reservoir
  const int stored = 4;      // stored reservoirs the disposable one resamples
  double sum = 0.0;
  for (int t = 0; t < trials; ++t) {
    Reservoir shading = emptyReservoir();
    for (int k = 0; k < stored; ++k) {
      Reservoir r = emptyReservoir();
      for (int c = 0; c < candidates; ++c) {
        float u0 = rngUniform(rng);
        float u1 = rngUniform(rng);
        float choice = rngUniform(rng);
        vec3 d = sampleSpecularLobeUniform(axis, cone, vec2(u0, u1));
        Reservoir candidate = environmentSample(d, skyRadiance(d));
        float target = specularTargetPdf(candidate, s, kSpecularSamplingUniform, fraction);
        reservoirStream(r, d, vec3(0.0f, 0.0f, 1.0f), candidate.radiance, kReservoirEnvironment,
                        target / pdfSpecularLobeUniform(cone), 1.0f, choice);
      }
      reservoirFinalize(r, specularTargetPdf(r, s, kSpecularSamplingUniform, fraction), r.M);
      if (!reservoirHasSample(r)) continue;
      float choice = rngUniform(rng);
      reservoirStream(shading, r.position, r.normal, r.radiance, r.flags,
                      specularShadingTarget(r, s) * r.W / float(stored), 1.0f, choice);
    }
    reservoirFinalize(shading, specularShadingTarget(shading, s), 1.0f);
    if (reservoirHasSample(shading)) sum += luminance(specularSampleContribution(shading, s)) * shading.W;
  }
  EXPECT_NEAR(sum / trials, truth, 0.03 * truth);
}

TEST(SpecularTarget, ResolveSampleCountRisesWithRoughness) {
  EXPECT_EQ(resolveSampleCount(0.0f, 8u, 0.5f), 1u);
  EXPECT_EQ(resolveSampleCount(0.5f, 8u, 0.5f), 8u);
  EXPECT_EQ(resolveSampleCount(1.0f, 8u, 0.5f), 8u);
  uint previous = 1u;
  for (float r = 0.0f; r <= 1.0f; r += 0.01f) {
    uint count = resolveSampleCount(r, 8u, 0.5f);
    EXPECT_GE(count, previous);
    previous = count;
  }
  EXPECT_EQ(resolveSampleCount(0.7f, 1u, 0.5f), 1u);
}

TEST(SpecularTarget, FootprintIsNothingForAMirrorAndGrowsWithRoughnessAndDistance) {
  EXPECT_LT(specularFootprintRadius(10.0f, ggxAlpha(0.0f)), 0.01f * 10.0f);
  EXPECT_LT(specularFootprintRadius(10.0f, ggxAlpha(0.2f)), specularFootprintRadius(10.0f, ggxAlpha(0.6f)));
  EXPECT_LT(specularFootprintRadius(1.0f, ggxAlpha(0.6f)), specularFootprintRadius(10.0f, ggxAlpha(0.6f)));
  EXPECT_TRUE(std::isfinite(specularFootprintRadius(1e4f, ggxAlpha(1.0f))));
}

}  // namespace
