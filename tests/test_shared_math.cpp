// CPU tests of shaders/shared/: the same source the GPU runs, compiled as C++.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <vector>

#include "shared/brdf.glsl"
#include "shared/checkerboard.glsl"
#include "shared/color.glsl"
#include "shared/denoise_weights.glsl"
#include "shared/finite.glsl"
#include "shared/intersect.glsl"
#include "shared/moments.glsl"
#include "shared/packing.glsl"
#include "shared/rng.glsl"

namespace {

using namespace bounce::shared;

std::vector<glm::vec3> randomUnitVectors(int count, uint seed) {
  std::vector<glm::vec3> out;
  uint state = seed;
  while (int(out.size()) < count) {
    glm::vec3 v(rngUniform(state) * 2 - 1, rngUniform(state) * 2 - 1, rngUniform(state) * 2 - 1);
    float len2 = glm::dot(v, v);
    if (len2 > 1e-4f && len2 <= 1.0f) out.push_back(v / std::sqrt(len2));
  }
  // The hard cases: axes (where signs of zero matter) and the octahedron's seams.
  for (glm::vec3 axis : {glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, -1, 0),
                         glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::normalize(glm::vec3(1, 1, 0)),
                         glm::normalize(glm::vec3(-1, 0, -1)), glm::normalize(glm::vec3(0, -1, -1))})
    out.push_back(axis);
  return out;
}

TEST(Rng, UniformIsInUnitIntervalAndPassesChiSquare) {
  constexpr int kBins = 64, kSamples = 640000;
  std::vector<int> histogram(kBins, 0);
  uint state = rngSeed(uvec2(3, 7), 11u, 1u);
  for (int i = 0; i < kSamples; ++i) {
    float u = rngUniform(state);
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    histogram[int(u * kBins)]++;
  }
  double chi2 = 0, expected = double(kSamples) / kBins;
  for (int count : histogram) chi2 += (count - expected) * (count - expected) / expected;
  // 63 degrees of freedom: the 99.9th percentile is about 103.4.
  EXPECT_LT(chi2, 103.4);
}

TEST(Rng, SeedsDecorrelatePixelsFramesAndPasses) {
  std::set<uint> seeds;
  for (uint y = 0; y < 64; ++y)
    for (uint x = 0; x < 64; ++x) seeds.insert(rngSeed(uvec2(x, y), 0u, 0u));
  EXPECT_EQ(seeds.size(), 64u * 64u) << "distinct pixels must get distinct seeds";
  EXPECT_NE(rngSeed(uvec2(1, 0), 0u, 0u), rngSeed(uvec2(0, 1), 0u, 0u));
  EXPECT_NE(rngSeed(uvec2(5, 5), 1u, 0u), rngSeed(uvec2(5, 5), 0u, 1u));
  EXPECT_EQ(rngSeed(uvec2(5, 5), 9u, 2u), rngSeed(uvec2(5, 5), 9u, 2u));
}

TEST(Rng, SuccessiveValuesAreUncorrelated) {
  uint state = rngSeed(uvec2(0, 0), 0u, 0u);
  double sumXY = 0, sumX = 0, sumY = 0, sumX2 = 0, sumY2 = 0;
  constexpr int n = 100000;
  float previous = rngUniform(state);
  for (int i = 0; i < n; ++i) {
    float next = rngUniform(state);
    sumXY += previous * next;
    sumX += previous;
    sumY += next;
    sumX2 += previous * previous;
    sumY2 += next * next;
    previous = next;
  }
  double cov = sumXY / n - (sumX / n) * (sumY / n);
  double corr = cov / std::sqrt((sumX2 / n - sumX * sumX / n / n) * (sumY2 / n - sumY * sumY / n / n));
  EXPECT_LT(std::abs(corr), 0.02);
}

float fromBits(uint bits) {
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

TEST(Finite, OnlyNanAndInfinityAreNotFinite) {
  using limits = std::numeric_limits<float>;
  for (float value : {0.0f, -0.0f, 1.0f, -3.5f, limits::max(), limits::lowest(), limits::min(), limits::denorm_min(),
                      -limits::denorm_min(), kMaxHalf})
    EXPECT_TRUE(isFinite(value)) << value;
  // Every NaN: quiet and signalling, either sign, any payload.
  for (uint bits : {0x7f800000u, 0xff800000u, 0x7fc00000u, 0xffc00000u, 0x7f800001u, 0x7fbfffffu, 0xffffffffu})
    EXPECT_FALSE(isFinite(fromBits(bits))) << std::hex << bits;
  EXPECT_TRUE(isFinite(vec4(1.0f, 2.0f, 3.0f, 4.0f)));
  for (int c = 0; c < 4; ++c) {
    vec4 v(1.0f);
    v[c] = limits::quiet_NaN();
    EXPECT_FALSE(isFinite(v)) << "NaN in component " << c;
    v[c] = -limits::infinity();
    EXPECT_FALSE(isFinite(v)) << "-inf in component " << c;
    if (c < 3) {
      EXPECT_FALSE(isFinite(vec3(v))) << c;
    }
    if (c < 2) {
      EXPECT_FALSE(isFinite(vec2(v))) << c;
    }
  }
}

TEST(Finite, FiniteOrReplacesTheWholeValue) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(finiteOr(2.5f, 7.0f), 2.5f);
  EXPECT_EQ(finiteOr(nan, 7.0f), 7.0f);
  EXPECT_EQ(finiteOr(-inf, 7.0f), 7.0f);
  EXPECT_EQ(finiteOr(vec2(1.0f, inf), vec2(3.0f)), vec2(3.0f)) << "a vector is usable whole or not at all";
  EXPECT_EQ(finiteOr(vec3(1.0f, 2.0f, 3.0f), vec3(0.0f)), vec3(1.0f, 2.0f, 3.0f));
  EXPECT_EQ(finiteOr(vec4(nan, 1.0f, 1.0f, 1.0f), vec4(0.0f)), vec4(0.0f));
}

TEST(Finite, SanitizedRadianceIsStorableAsHalfAndNonFiniteIsNoLight) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(sanitizeRadiance(vec3(0.25f, 3.0f, 65504.0f)), vec3(0.25f, 3.0f, 65504.0f)) << "valid radiance passes";
  EXPECT_EQ(sanitizeRadiance(vec3(1e6f, 2.0f, 3e38f)), vec3(kMaxHalf, 2.0f, kMaxHalf)) << "saturates, finite";
  EXPECT_EQ(sanitizeRadiance(vec3(-1.0f, 2.0f, -0.0f)), vec3(0.0f, 2.0f, 0.0f)) << "no negative light";
  EXPECT_EQ(sanitizeRadiance(vec3(nan, 2.0f, 3.0f)), vec3(0.0f)) << "NaN anywhere: no light at all";
  EXPECT_EQ(sanitizeRadiance(vec3(1.0f, inf, 3.0f)), vec3(0.0f)) << "infinity is not the brightest light";
  EXPECT_EQ(sanitizeRadiance(vec3(1.0f, 2.0f, -inf)), vec3(0.0f));
  // What it returns survives the conversion to half floats.
  for (float value : {1e6f, 3e38f, kMaxHalf, 65519.0f}) {
    const vec3 stored = sanitizeRadiance(vec3(value));
    EXPECT_TRUE(isFinite(unpackHalf2x16(packHalf2x16(vec2(stored.x, stored.y))).x)) << value;
  }
}

// What an implementation that truncates does with a float stored to an
// rgba16f image (NVIDIA's does; Vulkan leaves the rounding open).
float truncatedToHalf(float x) { return uintBitsToFloat(floatBitsToUint(x) & 0xffffe000u); }

TEST(Finite, RoundedToHalfIsTheNearestHalfAndStoresExactly) {
  uint state = 99u;
  for (int i = 0; i < 100000; ++i) {
    // Log-uniform over half's normal range, both signs.
    const float x = std::exp2(-14.0f + 29.9f * rngUniform(state)) * (i % 2 ? 1.0f : -1.0f);
    const float rounded = roundedToHalf(x);
    ASSERT_EQ(truncatedToHalf(rounded), rounded) << x << ": not exact in half";
    const float below = truncatedToHalf(std::abs(x));
    const float place = std::exp2(std::floor(std::log2(below)) - 10.0f);
    const float nearest = std::abs(x) - below <= below + place - std::abs(x) ? below : below + place;
    ASSERT_LE(std::abs(std::abs(rounded) - std::abs(x)), 0.5f * place * (1.0f + 1e-6f)) << x;
    if (std::abs(x) - below != 0.5f * place) {
      ASSERT_EQ(std::abs(rounded), nearest) << x;
    }
  }
  EXPECT_EQ(roundedToHalf(1.0f + 1.5f / 1024.0f), 1.0f + 2.0f / 1024.0f) << "a tie goes to the even place";
  EXPECT_EQ(roundedToHalf(1.0f + 0.5f / 1024.0f), 1.0f) << "a tie goes to the even place";
  EXPECT_EQ(roundedToHalf(kMaxHalf), kMaxHalf) << "the largest half stays finite";
  EXPECT_EQ(roundedToHalf(0.0f), 0.0f);
  EXPECT_TRUE(std::isinf(roundedToHalf(std::numeric_limits<float>::infinity()))) << "infinity is not made NaN";
}

// A 30-frame history blended into itself (x += (sample - x) / 30), stored
// to half each frame: truncated, its equilibrium sits far below the mean of
// its samples (1 %); rounded first, within a tenth of a percent.
TEST(Finite, AHalfHistoryRoundedFirstDoesNotDrift) {
  const auto settle = [](bool rounded) {
    uint state = 7u;
    float history = 0.0f;
    double sum = 0.0;
    constexpr int kFrames = 50000, kWarmUp = 1000;
    for (int frame = 0; frame < kFrames; ++frame) {
      const float sample = 0.7f * (0.8f + 0.4f * rngUniform(state));  // mean 0.7
      const float blended = history + (sample - history) / 30.0f;
      history = truncatedToHalf(rounded ? roundedToHalf(blended) : blended);
      if (frame >= kWarmUp) sum += history;
    }
    return sum / double(kFrames - kWarmUp) / 0.7;
  };
  // Truncated: 30 frames x half a place (2^-12 at 0.7) low, 1 %.
  EXPECT_LT(settle(false), 0.992) << "the drift this guards against";
  EXPECT_NEAR(settle(true), 1.0, 0.001);
}

TEST(Moments, StoredAsDeviationTheyKeepASmallVarianceInHalf) {
  const vec3 moments(1.0f, 1.0f + 0.01f * 0.01f, 0.98f);  // mean 1, deviation 0.01, fast mean 0.98
  const vec4 stored = storedMoments(moments, 0.25f);
  EXPECT_NEAR(stored.y, 0.01f, 1e-5f);
  EXPECT_EQ(stored.w, 0.25f);
  const vec3 back = momentsFromStored(stored);
  EXPECT_NEAR(back.x, moments.x, 1e-6f);
  EXPECT_NEAR(back.y, moments.y, 1e-6f);
  EXPECT_EQ(back.z, moments.z);
  // Through half precision: the deviation comes back within 0.1 % ...
  vec4 half(0.0f);
  for (int c = 0; c < 4; ++c) half[c] = truncatedToHalf(roundedToHalf(stored[c]));
  const vec3 fromHalf = momentsFromStored(half);
  EXPECT_NEAR(std::sqrt(fromHalf.y - fromHalf.x * fromHalf.x), 0.01f, 1e-5f);
  // ... where the mean square in half would have lost it entirely.
  const float meanSquareInHalf = truncatedToHalf(roundedToHalf(moments.y));
  EXPECT_EQ(meanSquareInHalf - 1.0f, 0.0f);
  // No negative variance from rounding: the deviation is clamped at 0.
  EXPECT_EQ(storedMoments(vec3(2.0f, 3.9999f, 2.0f), 0.0f).y, 0.0f);
}

TEST(Packing, OctahedralRoundTripIsWithinHundredthOfADegree) {
  for (glm::vec3 n : randomUnitVectors(20000, 1234u)) {
    glm::vec2 e = encodeOctahedral(n);
    ASSERT_LE(std::abs(e.x), 1.0f);
    ASSERT_LE(std::abs(e.y), 1.0f);
    glm::vec3 exact = decodeOctahedral(e);
    ASSERT_NEAR(glm::dot(exact, n), 1.0f, 1e-6f) << n.x << " " << n.y << " " << n.z;
    glm::vec3 packed = unpackNormalOct32(packNormalOct32(n));
    // The angle from the cross product's length: acos of a float dot product
    // near 1 is itself only good to about 0.02 degrees.
    glm::dvec3 a(packed), b(n);
    double degrees = glm::degrees(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
    ASSERT_LT(degrees, 0.01) << n.x << " " << n.y << " " << n.z;
  }
}

TEST(Packing, NormalAndMaterialRoundTripWithinATenthOfADegree) {
  uint material = 0;
  for (glm::vec3 n : randomUnitVectors(20000, 4321u)) {
    material = (material * 37u + 11u) % 1000u;  // ids past 255 keep their low 8 bits
    const uint packed = packNormalMaterial(n, material);
    EXPECT_EQ(unpackMaterialOfNormalMaterial(packed), material & 0xFFu);
    glm::dvec3 a(unpackNormalOfNormalMaterial(packed)), b(n);
    double degrees = glm::degrees(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
    ASSERT_LT(degrees, 0.1) << n.x << " " << n.y << " " << n.z;
  }
  // The id does not disturb the normal's bits, nor the normal the id's.
  const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.8f, 0.5f));
  EXPECT_EQ(packNormalMaterial(n, 0u) & 0xFFFFFFu, packNormalMaterial(n, 255u) & 0xFFFFFFu);
  EXPECT_EQ(unpackMaterialOfNormalMaterial(packNormalMaterial(glm::vec3(0.0f, 0.0f, -1.0f), 200u)), 200u);
}

TEST(Packing, NormalAndRoughnessRoundTripWithinAFifthOfADegreeAndAThousandth) {
  float roughness = 0.0f;
  double worst = 0.0;
  for (glm::vec3 n : randomUnitVectors(20000, 2468u)) {
    roughness = std::fmod(roughness + 0.1234567f, 1.0f);
    const uint packed = packNormalRoughness(n, roughness);
    EXPECT_NEAR(unpackRoughnessOfNormalRoughness(packed), roughness, 0.5f / 1023.0f + 1e-6f);
    glm::dvec3 a(unpackNormalOfNormalRoughness(packed)), b(n);
    worst = std::max(worst, glm::degrees(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b))));
  }
  std::printf("11-bit octahedral normal: worst %.3f degrees\n", worst);
  EXPECT_LT(worst, 0.2);
  // Roughness is clamped to [0, 1] and keeps its ends exactly; it leaves the normal's bits alone.
  const glm::vec3 n = glm::normalize(glm::vec3(-0.2f, 0.4f, -0.9f));
  EXPECT_EQ(unpackRoughnessOfNormalRoughness(packNormalRoughness(n, 1.0f)), 1.0f);
  EXPECT_EQ(unpackRoughnessOfNormalRoughness(packNormalRoughness(n, -3.0f)), 0.0f);
  EXPECT_EQ(packNormalRoughness(n, 0.0f) & 0x3FFFFFu, packNormalRoughness(n, 1.0f) & 0x3FFFFFu);
}

TEST(Packing, PixelIndexAndUvRoundTrip) {
  const uint width = 37;
  for (uint i = 0; i < 37u * 23u; ++i) EXPECT_EQ(pixelToIndex(indexToPixel(i, width), width), i);
  const glm::vec2 size(37, 23);
  for (uint y = 0; y < 23; ++y)
    for (uint x = 0; x < 37; ++x) {
      glm::uvec2 back = uvToPixel(pixelToUv(uvec2(x, y), size), size);
      ASSERT_EQ(back.x, x);
      ASSERT_EQ(back.y, y);
    }
  EXPECT_EQ(uvToPixel(glm::vec2(1.0f, 1.0f), size).x, 36u) << "uv 1.0 must clamp to the last pixel";
}

TEST(Color, LuminanceOfWhiteIsOneAndWeightsAreRec709) {
  EXPECT_NEAR(luminance(vec3(1.0f)), 1.0f, 1e-6f);
  EXPECT_NEAR(luminance(vec3(0, 1, 0)), 0.7152f, 1e-6f);
}

TEST(Color, SrgbMatchesTheStandardAndRoundTrips) {
  EXPECT_NEAR(srgbEncode(0.5f), 0.735357f, 1e-5f);
  EXPECT_NEAR(srgbEncode(0.0031308f), 0.04045f, 1e-5f) << "the two pieces must meet";
  EXPECT_NEAR(srgbDecode(0.5f), 0.214041f, 1e-5f);
  EXPECT_EQ(srgbEncode(-1.0f), 0.0f);
  EXPECT_NEAR(srgbEncode(2.0f), 1.0f, 1e-6f);
  float previous = -1;
  for (int i = 0; i <= 1000; ++i) {
    float x = float(i) / 1000.0f;
    EXPECT_NEAR(srgbDecode(srgbEncode(x)), x, 2e-6f);
    EXPECT_GT(srgbEncode(x), previous);
    previous = srgbEncode(x);
  }
}

TEST(Color, AcesIsMonotonicBoundedAndBlackAtZero) {
  EXPECT_NEAR(tonemapAcesFitted(vec3(0.0f)).x, 0.0f, 1e-3f);
  float previous = -1;
  for (float x = 0.0f; x < 100.0f; x = x * 1.1f + 0.001f) {
    float y = tonemapAcesFitted(vec3(x)).y;
    EXPECT_GE(y, previous);
    EXPECT_LE(y, 1.0f);
    previous = y;
  }
  EXPECT_GT(tonemapAcesFitted(vec3(1e6f)).x, 0.99f) << "very bright must saturate to white";
  // Reference values of Hill's fit, computed independently in double
  // precision from his published matrices; a transposed matrix or a wrong
  // coefficient moves them far beyond the tolerance.
  vec3 grey = tonemapAcesFitted(vec3(0.18f));
  EXPECT_NEAR(grey.x, 0.105591f, 2e-4f);
  vec3 warm = tonemapAcesFitted(vec3(1.0f, 0.5f, 0.1f));
  EXPECT_NEAR(warm.x, 0.638871f, 2e-4f);
  EXPECT_NEAR(warm.y, 0.383867f, 2e-4f);
  EXPECT_NEAR(warm.z, 0.082200f, 2e-4f);
  vec3 negative = tonemapAcesFitted(vec3(-5.0f, 1.0f, 0.5f));
  EXPECT_GE(negative.x, 0.0f) << "negative input must not produce negative output";
}

TEST(Intersect, SphereAndPlaneHitsMatchClosedForm) {
  // Unit sphere at z = -5 seen along -z: near hit at 4, far hit at 6.
  EXPECT_NEAR(intersectSphere(vec3(0.0f), vec3(0, 0, -1), vec3(0, 0, -5), 1.0f, 0.0f), 4.0f, 1e-5f);
  EXPECT_NEAR(intersectSphere(vec3(0, 0, -5), vec3(0, 0, -1), vec3(0, 0, -5), 1.0f, 0.0f), 1.0f, 1e-5f)
      << "from inside, the exit point";
  EXPECT_EQ(intersectSphere(vec3(0.0f), vec3(0, 1, 0), vec3(0, 0, -5), 1.0f, 0.0f), kNoHit);
  EXPECT_EQ(intersectSphere(vec3(0.0f), vec3(0, 0, 1), vec3(0, 0, -5), 1.0f, 0.0f), kNoHit) << "behind the ray";
  // Far small sphere: the geometric form keeps the hit accurate.
  EXPECT_NEAR(intersectSphere(vec3(0.0f), vec3(0, 0, -1), vec3(0, 0, -10000), 0.01f, 0.0f), 9999.99f, 2e-3f);
  EXPECT_NEAR(intersectPlane(vec3(0, 2, 0), glm::normalize(vec3(1, -1, 0)), vec3(0, 1, 0), 0.0f, 0.0f),
              2.0f * std::sqrt(2.0f), 1e-5f);
  EXPECT_EQ(intersectPlane(vec3(0, 2, 0), vec3(1, 0, 0), vec3(0, 1, 0), 0.0f, 0.0f), kNoHit) << "parallel";
}

// --- brdf.glsl

vec3 directionAt(float cosTheta, float phi) {
  const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  return vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
}

// Directional albedo of the specular lobe, integrated on a fine grid in
// (cos theta, phi): the share of light from v the lobe reflects.
float specularAlbedo(float cosThetaV, float roughness, vec3 f0) {
  const vec3 n(0, 0, 1);
  const vec3 v = directionAt(cosThetaV, 0.0f);
  const int steps = 400;
  double sum = 0.0;
  for (int i = 0; i < steps; ++i)
    for (int j = 0; j < steps; ++j) {
      const float cosTheta = (float(i) + 0.5f) / float(steps);
      const float phi = 2.0f * kPi * (float(j) + 0.5f) / float(steps);
      sum += ggxSpecularCosine(n, v, directionAt(cosTheta, phi), f0, ggxAlpha(roughness)).x;
    }
  return float(sum * (2.0 * kPi) / double(steps * steps));  // d(omega) = d(cos) d(phi)
}

TEST(Brdf, WhiteFurnaceReflectsAtMostAllLight) {
  for (float roughness : {0.3f, 0.6f, 1.0f})
    for (float cosThetaV : {1.0f, 0.5f, 0.1f}) {
      const float albedo = specularAlbedo(cosThetaV, roughness, vec3(1.0f));
      EXPECT_LE(albedo, 1.0f + 1e-2f) << roughness << " " << cosThetaV;
      EXPECT_GT(albedo, 0.25f) << roughness << " " << cosThetaV;
    }
  // A smooth lobe keeps almost everything; single scattering loses more as
  // the surface gets rougher.
  EXPECT_NEAR(specularAlbedo(1.0f, 0.3f, vec3(1.0f)), 1.0f, 0.03f);
  EXPECT_GT(specularAlbedo(1.0f, 0.6f, vec3(1.0f)), specularAlbedo(1.0f, 1.0f, vec3(1.0f)));
}

// The GGX NDF is normalized: the projected microfacet area is one.
TEST(Brdf, GgxDistributionProjectsToUnitArea) {
  for (float roughness : {0.3f, 0.6f, 1.0f}) {
    const int steps = 20000;
    double sum = 0.0;
    for (int i = 0; i < steps; ++i) {
      const float cosTheta = (float(i) + 0.5f) / float(steps);
      sum += ggxD(cosTheta, ggxAlpha(roughness)) * cosTheta;
    }
    EXPECT_NEAR(sum * 2.0 * kPi / steps, 1.0, 2e-3) << roughness;
  }
}

// reflectsAlikeTowards accepts exactly the turns of the outgoing direction
// that keep the GGX peak of a light at least a quarter as high: with the
// light mirrored about the normal from `seen`, turning `seen` by theta in its
// plane of incidence moves the half vector off the normal.
TEST(Brdf, ReflectsAlikeWhereTheTurnedPeakKeepsAQuarter) {
  const vec3 n(0, 0, 1);
  int accepted = 0;
  int rejected = 0;
  for (float roughness : {0.1f, 0.17f, 0.3f, 0.5f, 0.7f, 0.9f}) {
    const float alpha = ggxAlpha(roughness);
    for (float seenAngle : {0.1f, 0.5f, 0.9f}) {
      const vec3 seen(std::sin(seenAngle), 0.0f, std::cos(seenAngle));
      const vec3 light(-seen.x, 0.0f, seen.z);
      for (int i = 1; i < 400; ++i) {
        const float wantedAngle = seenAngle - 1.5f + 3.0f * float(i) / 400.0f;
        if (std::abs(wantedAngle) > 1.5f) continue;
        const vec3 wanted(std::sin(wantedAngle), 0.0f, std::cos(wantedAngle));
        const vec3 h = normalize(light + wanted);
        const float peakKept = ggxD(dot(n, h), alpha) / ggxD(1.0f, alpha);
        if (std::abs(peakKept - 0.25f) < 0.01f) continue;  // rounding decides at the boundary
        const bool alike = reflectsAlikeTowards(seen, wanted, roughness);
        EXPECT_EQ(alike, peakKept > 0.25f) << roughness << " " << seenAngle << " " << wantedAngle;
        (alike ? accepted : rejected)++;
      }
    }
  }
  EXPECT_GT(accepted, 100);
  EXPECT_GT(rejected, 100);
  // A rough surface looks the same from every side; polished metal 30 degrees off does not.
  EXPECT_TRUE(reflectsAlikeTowards(vec3(0, 0, 1), normalize(vec3(1, 0, 0.05f)), 1.0f));
  EXPECT_FALSE(reflectsAlikeTowards(vec3(0, 0, 1), vec3(0.5f, 0, std::sqrt(0.75f)), 0.17f));
}

TEST(Brdf, LambertPartIsAlbedoOverPi) {
  const vec3 n(0, 0, 1);
  const vec3 l = directionAt(0.6f, 1.0f);
  const vec3 v = directionAt(0.8f, 2.5f);
  // A rough dielectric's diffuse part: base colour * (1 - metallic) / pi * cos.
  const vec3 total = materialBrdfCosine(n, v, l, vec3(0.5f), 0.0f, 1.0f);
  const vec3 specular = ggxSpecularCosine(n, v, l, vec3(0.04f), ggxAlpha(1.0f));
  EXPECT_NEAR(total.x - specular.x, 0.5f * kInvPi * 0.6f, 1e-6f);
  // Metals have no diffuse lobe.
  const vec3 metal = materialBrdfCosine(n, v, l, vec3(0.5f), 1.0f, 1.0f);
  EXPECT_NEAR(metal.x, ggxSpecularCosine(n, v, l, vec3(0.5f), ggxAlpha(1.0f)).x, 1e-6f);
}

TEST(Brdf, ReciprocalFiniteAndZeroBelowTheHorizon) {
  uint state = rngSeed(uvec2(3, 4), 5u, 6u);
  const vec3 n(0, 0, 1);
  for (int i = 0; i < 5000; ++i) {
    const vec3 a = directionAt(rngUniform(state), 2.0f * kPi * rngUniform(state));
    const vec3 b = directionAt(rngUniform(state), 2.0f * kPi * rngUniform(state));
    const float roughness = rngUniform(state);
    const vec3 f0(0.04f + 0.9f * rngUniform(state));
    const vec3 ab = ggxSpecularCosine(n, a, b, f0, ggxAlpha(roughness));
    const vec3 ba = ggxSpecularCosine(n, b, a, f0, ggxAlpha(roughness));
    ASSERT_TRUE(std::isfinite(ab.x)) << i;
    // f(a, b) cos(b) / cos(b) == f(b, a) cos(a) / cos(a)
    if (a.z > 1e-3f && b.z > 1e-3f) {
      EXPECT_NEAR(ab.x / b.z, ba.x / a.z, 1e-3f * std::max(1.0f, ab.x / b.z)) << i;
    }
  }
  // Grazing and roughness 0 stay finite.
  EXPECT_TRUE(
      std::isfinite(ggxSpecularCosine(n, directionAt(1e-7f, 0), directionAt(1e-7f, kPi), vec3(1), ggxAlpha(0)).x));
  EXPECT_TRUE(std::isfinite(ggxSpecularCosine(n, n, n, vec3(1), ggxAlpha(0.0f)).x));
  EXPECT_EQ(materialBrdfCosine(n, n, vec3(0, 0, -1), vec3(1), 0.0f, 0.5f), vec3(0.0f));
}

// The denoiser's weights (shared/denoise_weights.glsl): REBLUR's hit
// distance normalisation at its published constants, a cone that narrows
// with the history and with the roughness, weights that are 1 at the pixel
// and 0 past their reach.
// REBLUR's virtual motion: curvature from two points of a surface, the
// thin-lens image of a curved mirror, the virtual point.
TEST(DenoiseWeights, CurvatureIsOneOverTheRadiusOfASphere) {
  for (float radius : {0.5f, 2.0f, 10.0f}) {
    const glm::vec3 centre(1.0f, -2.0f, 3.0f);
    const glm::vec3 n = glm::normalize(glm::vec3(0.2f, 0.9f, 0.3f));
    const glm::vec3 m = glm::normalize(n + glm::vec3(0.02f, -0.01f, 0.015f));  // a neighbour a little away
    const float convex = surfaceCurvature(centre + n * radius, n, centre + m * radius, m);
    const float concave = surfaceCurvature(centre + n * radius, -n, centre + m * radius, -m);
    EXPECT_NEAR(convex, 1.0f / radius, 0.01f / radius) << radius;
    EXPECT_NEAR(concave, -1.0f / radius, 0.01f / radius) << radius;
  }
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  EXPECT_EQ(surfaceCurvature(glm::vec3(0.0f), up, glm::vec3(1.0f, 0.0f, 0.3f), up), 0.0f) << "a plane";
  EXPECT_EQ(surfaceCurvature(glm::vec3(1.0f), up, glm::vec3(1.0f), glm::vec3(1.0f, 0.0f, 0.0f)), 0.0f)
      << "one point: no edge";
}

TEST(DenoiseWeights, ThinLensImageFollowsTheMirrorEquation) {
  // A plane mirror: the image lies as far behind as the object in front.
  EXPECT_FLOAT_EQ(thinLensImageDistance(0.7f, 3.0f, 0.0f), 3.0f);
  // A convex mirror of radius R seen head-on: 1 / image = 1 / object + 2 / R.
  const float radius = 2.0f, object = 3.0f;
  EXPECT_NEAR(1.0f / thinLensImageDistance(1.0f, object, 1.0f / radius), 1.0f / object + 2.0f / radius, 1e-5f);
  // A concave mirror: past the focal point (R / 2) the image is real, in front (negative).
  EXPECT_LT(thinLensImageDistance(1.0f, 3.0f, -1.0f / radius), 0.0f);
  EXPECT_GT(thinLensImageDistance(1.0f, 0.5f, -1.0f / radius), 0.5f) << "inside the focal point: farther";
  EXPECT_TRUE(std::isfinite(thinLensImageDistance(1.0f, 1.0f, -0.5f))) << "exactly at the focal point";
  // The virtual point: on the view ray, at the image distance times the dominant factor.
  const glm::vec3 x(1.0f, 2.0f, 3.0f), v = glm::normalize(glm::vec3(0.0f, -0.6f, -0.8f));
  EXPECT_NEAR(glm::distance(virtualPoint(x, v, 0.8f, 4.0f, 0.0f, 1.0f), x + v * 4.0f), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::distance(virtualPoint(x, v, 0.8f, 4.0f, 0.0f, 0.0f), x), 0.0f, 1e-6f) << "a rough lobe";
  EXPECT_LT(glm::distance(virtualPoint(x, v, 0.8f, 4.0f, 0.5f, 1.0f), x), 4.0f) << "convex: nearer";
}

TEST(DenoiseWeights, HitDistanceNormalisationFollowsReblur) {
  const vec4 abcd(3.0f, 0.1f, 20.0f, -25.0f);
  // Rough lobes: (A + viewZ B) * C at roughness 1 (exp2(-25) ~ 0).
  EXPECT_NEAR(hitDistanceScale(abcd, 10.0f, 0.0f), 4.0f * 20.0f, 1e-3f);
  EXPECT_NEAR(hitDistanceScale(abcd, 10.0f, 1.0f), 4.0f, 1e-3f);
  EXPECT_NEAR(normalizedHitDistance(abcd, 2.0f, 10.0f, 1.0f), 0.5f, 1e-5f);
  EXPECT_EQ(normalizedHitDistance(abcd, 100.0f, 10.0f, 1.0f), 1.0f);
  EXPECT_EQ(normalizedHitDistance(abcd, 0.0f, 10.0f, 1.0f), 1.0f) << "unknown counts as far";
}

TEST(DenoiseWeights, TheNormalConeNarrowsWithHistoryAndRoughness) {
  const float fresh = lobeHalfAngle(1.0f, 0.15f, 1.0f);
  const float settled = lobeHalfAngle(1.0f, 0.15f, 1.0f / 31.0f);
  EXPECT_NEAR(fresh, std::atan(std::sqrt(3.0f)), 1e-4f);  // p = 0.75: 60 degrees for diffuse
  EXPECT_LT(settled, 0.5f * fresh);
  EXPECT_LT(lobeHalfAngle(0.2f, 0.15f, 1.0f), lobeHalfAngle(0.6f, 0.15f, 1.0f));
  const vec3 n(0.0f, 0.0f, 1.0f);
  EXPECT_FLOAT_EQ(normalWeight(n, n, fresh), 1.0f);
  EXPECT_EQ(normalWeight(n, vec3(std::sin(fresh * 1.01f), 0.0f, std::cos(fresh * 1.01f)), fresh), 0.0f);
  const float half = normalWeight(n, vec3(std::sin(0.5f * fresh), 0.0f, std::cos(0.5f * fresh)), fresh);
  EXPECT_NEAR(half, 0.5f, 1e-3f);  // smoothstep at the middle
}

TEST(DenoiseWeights, PlaneAndRoughnessWeightsReachAsFarAsTheirSensitivity) {
  const vec3 n(0.0f, 1.0f, 0.0f), x(0.0f, 0.0f, -5.0f);
  EXPECT_FLOAT_EQ(planeWeight(n, x, x + vec3(3.0f, 0.0f, 0.0f), 5.0f, 0.02f), 1.0f) << "along the plane";
  EXPECT_NEAR(planeWeight(n, x, x + vec3(0.0f, 0.05f, 0.0f), 5.0f, 0.02f), 0.5f, 1e-4f);
  EXPECT_EQ(planeWeight(n, x, x + vec3(0.0f, 0.2f, 0.0f), 5.0f, 0.02f), 0.0f);
  EXPECT_FLOAT_EQ(roughnessWeight(0.5f, 0.5f, 0.15f), 1.0f);
  EXPECT_EQ(roughnessWeight(0.5f, 0.6f, 0.15f), 0.0f);
  for (std::uint32_t i = 0; i < 8; ++i) EXPECT_LE(length(diskTap(i, 0.3f)), 1.0f);
}

// Catmull-Rom: the taps' own values at f = 0, weights that sum to 1, and
// lines and parabolas reproduced exactly (what makes it sharper than
// bilinear: bilinear bends a parabola).
TEST(DenoiseWeights, CatmullRomInterpolatesAndKeepsParabolas) {
  EXPECT_EQ(catmullRomWeights(0.0f), vec4(0.0f, 1.0f, 0.0f, 0.0f));
  for (float f : {0.1f, 0.37f, 0.5f, 0.9f}) {
    const vec4 w = catmullRomWeights(f);
    EXPECT_NEAR(w.x + w.y + w.z + w.w, 1.0f, 1e-6f) << f;
    EXPECT_LE(w.x, 0.0f);
    EXPECT_LE(w.w, 0.0f);
    // Taps at -1, 0, 1, 2 of g(t) = 3 t^2 - t + 2.
    const auto g = [](float t) { return 3.0f * t * t - t + 2.0f; };
    EXPECT_NEAR(w.x * g(-1) + w.y * g(0) + w.z * g(1) + w.w * g(2), g(f), 1e-4f) << f;
    // Bilinear would not: it lies above the parabola between taps.
    EXPECT_GT((1.0f - f) * g(0) + f * g(1), g(f) + 0.05f) << f;
  }
}

// The five bilinear taps weigh every texel of the 4x4 footprint as the
// 12-tap Catmull-Rom filter without corners does: expanded into texel
// weights (each bilinear tap over its four texels), they match
// catmullRomWeights(x) * catmullRomWeights(y) on the 12 and give the
// corners nothing.
TEST(DenoiseWeights, CatmullRomAsFiveBilinearTapsWeighsTheTwelveTexelsAlike) {
  for (float fx : {0.0f, 0.1f, 0.37f, 0.5f, 0.9f, 0.999f})
    for (float fy : {0.0f, 0.25f, 0.61f, 0.98f}) {
      const CatmullRomBilinear taps = catmullRomAsBilinear(vec2(fx, fy));
      float texel[4][4] = {};  // [y + 1][x + 1]
      for (int t = 0; t < kCatmullRomBilinearTaps; ++t) {
        const vec2 p = taps.offsets[t];
        const int x0 = int(std::floor(p.x)), y0 = int(std::floor(p.y));
        const float ax = p.x - float(x0), ay = p.y - float(y0);
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 2; ++i) {
            const float b = (i == 1 ? ax : 1.0f - ax) * (j == 1 ? ay : 1.0f - ay);
            if (b == 0.0f) continue;
            ASSERT_GE(x0 + i, -1);
            ASSERT_LE(x0 + i, 2);
            ASSERT_GE(y0 + j, -1);
            ASSERT_LE(y0 + j, 2);
            texel[y0 + j + 1][x0 + i + 1] += taps.weights[t] * b;
          }
      }
      const vec4 wx = catmullRomWeights(fx), wy = catmullRomWeights(fy);
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          const bool corner = (i == 0 || i == 3) && (j == 0 || j == 3);
          EXPECT_NEAR(texel[j][i], corner ? 0.0f : wx[i] * wy[j], 1e-5f) << fx << " " << fy << " " << i << " " << j;
        }
    }
}

// The disocclusion reach: REBLUR's threshold head-on, wider at grazing
// angles, wider again for a still camera; a large parallax makes n.v count
// less.
TEST(DenoiseWeights, TheDisocclusionReachWidensAtGrazingAnglesAndForAStillCamera) {
  const float moving = 5.0f;
  EXPECT_NEAR(disocclusionReach(0.01f, 1.0f, moving), 0.01f, 1e-6f);
  EXPECT_NEAR(disocclusionReach(0.01f, 0.1f, moving), 0.01f / (0.1f + 0.9f * moving / 30.0f), 1e-5f);
  EXPECT_GT(disocclusionReach(0.01f, 0.1f, moving), 3.0f * disocclusionReach(0.01f, 1.0f, moving));
  EXPECT_NEAR(disocclusionReach(0.01f, 1.0f, 0.0f), 0.06f, 1e-6f) << "a still camera: +0.05";
  EXPECT_LT(disocclusionReach(0.01f, 0.1f, 60.0f), disocclusionReach(0.01f, 0.1f, 5.0f)) << "large parallax: strict";
  EXPECT_EQ(disocclusionReach(0.01f, 0.0f, 0.0f), 1.0f) << "capped at the frustum";
  EXPECT_EQ(disocclusionReach(0.01f, -1.0f, moving), disocclusionReach(0.01f, 1.0f, moving)) << "back faces too";
}

// The blend of surface and virtual histories: the prior by roughness where
// both agree alike, and the source that disagrees with this frame loses.
TEST(DenoiseWeights, TheReflectionHistoryThatDisagreesLoses) {
  EXPECT_EQ(virtualHistoryPrior(0.0f), 1.0f);
  EXPECT_EQ(virtualHistoryPrior(1.0f), 0.0f);
  EXPECT_GT(virtualHistoryPrior(0.2f), virtualHistoryPrior(0.4f));
  EXPECT_FLOAT_EQ(historyAgreement(2.0f, 2.0f, 0.3f), 1.0f);
  EXPECT_LT(historyAgreement(4.0f, 2.0f, 0.3f), 0.01f);
  EXPECT_NEAR(virtualHistoryShare(0.3f, 0.8f, 0.8f), 0.3f, 1e-6f);
  EXPECT_GT(virtualHistoryShare(0.3f, 1.0f, 0.01f), 0.9f);
  EXPECT_LT(virtualHistoryShare(0.7f, 0.01f, 1.0f), 0.1f);
  EXPECT_EQ(virtualHistoryShare(0.4f, 0.0f, 0.0f), 0.4f) << "neither agrees: the prior";
}

// The pre-pass: a radius that grows with the hit distance (and for
// specular with the roughness, up to the lobe's footprint), and a
// hit-distance weight that keeps its floor and narrows as the history grows.
TEST(DenoiseWeights, ThePrePassRadiusFollowsHitDistanceRoughnessAndLobe) {
  EXPECT_FLOAT_EQ(prePassRadius(30.0f, 1.0f, 1.0f, false, 0.0f), 30.0f);
  EXPECT_FLOAT_EQ(prePassRadius(30.0f, 0.25f, 1.0f, false, 0.0f), 15.0f);
  EXPECT_FLOAT_EQ(prePassRadius(30.0f, 4.0f, 1.0f, false, 0.0f), 30.0f) << "hit beyond the frustum: capped";
  EXPECT_FLOAT_EQ(prePassRadius(50.0f, 1.0f, 0.25f, true, 1000.0f), 25.0f);
  EXPECT_FLOAT_EQ(prePassRadius(50.0f, 1.0f, 0.25f, true, 3.0f), 3.0f) << "cut to the lobe's footprint";
  EXPECT_EQ(specularMagicCurve(0.0f), 0.0f);
  EXPECT_GT(specularMagicCurve(0.2f), 0.5f);
  EXPECT_FLOAT_EQ(specularMagicCurve(1.0f), 1.0f);
  EXPECT_FLOAT_EQ(hitDistanceWeight(0.3f, 0.3f, 0.1f, 1.0f, 0.2f), 1.0f);
  EXPECT_LT(hitDistanceWeight(0.3f, 0.9f, 0.1f, 1.0f, 0.2f), 0.25f);
  EXPECT_GE(hitDistanceWeight(0.3f, 0.9f, 0.1f, 1.0f, 0.2f), 0.2f) << "the floor";
  EXPECT_LT(hitDistanceWeight(0.3f, 0.4f, 0.05f, 1.0f, 0.0f), hitDistanceWeight(0.3f, 0.4f, 0.5f, 1.0f, 0.0f))
      << "a longer history (smaller weight 1 / (1 + frames)) asks for closer hits";
  EXPECT_LT(hitDistanceWeight(0.3f, 0.35f, 1.0f, 0.0f, 0.0f), 0.01f) << "a mirror: only the same hit";
}

// The spatial passes' disk turns every frame and differs between passes,
// so the pattern averages away over the history.
TEST(DenoiseWeights, TheDiskTurnsEveryFrameAndDiffersPerPass) {
  for (std::uint32_t frame : {0u, 1u, 7u, 4095u, 4096u, 100000u}) {
    const float rotation = diskRotation(frame, 0);
    EXPECT_GE(rotation, 0.0f);
    EXPECT_LT(rotation, 6.2832f);
    EXPECT_GT(std::abs(rotation - diskRotation(frame + 1, 0)), 0.1f) << frame;
    EXPECT_GT(std::abs(rotation - diskRotation(frame, 1)), 0.1f) << frame;
  }
}

// The checkerboard input (gi.denoise.checkerboard): REBLUR's parity
// ((x ^ y) ^ frame) & 1; every other pixel of a row holds a sample, the
// next row and the next frame the others; diffuse and specular take
// opposite pixels; a row's samples pack into ceil(width / 2) columns
// without two sharing one.
TEST(Checkerboard, SamplesAlternateByRowAndFrameAndPackIntoHalfTheWidth) {
  EXPECT_EQ(checkerboardParity(uvec2(0, 0), 0), 0u);
  EXPECT_EQ(checkerboardParity(uvec2(1, 0), 0), 1u);
  EXPECT_EQ(checkerboardParity(uvec2(1, 1), 0), 0u);
  EXPECT_EQ(checkerboardParity(uvec2(0, 0), 1), 1u);
  EXPECT_EQ(checkerboardParity(uvec2(6, 3), 0xFFFFFFFFu), 0u);
  EXPECT_NE(kCheckerboardDiffuseParity, kCheckerboardSpecularParity);
  EXPECT_EQ(checkerboardParityOfKind(false), kCheckerboardDiffuseParity);
  EXPECT_EQ(checkerboardParityOfKind(true), kCheckerboardSpecularParity);
  for (uint width : {1u, 2u, 7u, 64u, 65u}) {
    EXPECT_EQ(checkerboardPackedWidth(width), (width + 1) / 2);
    for (uint frame : {0u, 1u, 2u, 9u})
      for (uint y = 0; y < 3; ++y)
        for (uint parity : {kCheckerboardDiffuseParity, kCheckerboardSpecularParity}) {
          std::set<uint> columns;
          uint samples = 0;
          for (uint x = 0; x < width; ++x) {
            const bool has = checkerboardHasData(uvec2(x, y), frame, parity);
            EXPECT_NE(has, checkerboardHasData(uvec2(x, y), frame + 1, parity)) << "the next frame: the others";
            EXPECT_NE(has, checkerboardHasData(uvec2(x, y + 1), frame, parity)) << "the next row: the others";
            EXPECT_NE(has, checkerboardHasData(uvec2(x, y), frame, 1u - parity)) << "the other signal";
            if (x + 1 < width) {
              EXPECT_NE(has, checkerboardHasData(uvec2(x + 1, y), frame, parity)) << "every other pixel";
            }
            if (!has) continue;
            ++samples;
            EXPECT_TRUE(columns.insert(checkerboardPackedColumn(x)).second) << "two samples in one column";
            EXPECT_LT(checkerboardPackedColumn(x), checkerboardPackedWidth(width));
          }
          EXPECT_GE(samples, width / 2);
        }
  }
}

}  // namespace
