// Image metrics: FLIP against NVIDIA's FLIP v1.6 on fixed pairs, value errors
// on hand-made cases with known answers, percentiles, temporal stability, and
// `bounce compare` as a script uses it (exit codes, one-line messages, files).
#include <gtest/gtest.h>
#include <malloc.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <new>
#include <random>
#include <string>
#include <vector>

#include "io/colormap.h"
#include "io/image_io.h"
#include "metrics/flip.h"
#include "metrics/image_metrics.h"
#include "shared/color.glsl"
#include "zero_png.h"

// Every allocation through new is counted, so that tests can see the most
// memory a computation held beyond what it started with (e.g. that FLIP's
// intermediates do not grow with the image).
namespace {
std::atomic<std::int64_t> gAllocated{0};
std::atomic<std::int64_t> gPeakAllocated{0};

void* countedAllocation(std::size_t size) {
  void* block = std::malloc(size == 0 ? 1 : size);
  if (!block) throw std::bad_alloc();
  const std::int64_t now = gAllocated += std::int64_t(malloc_usable_size(block));
  for (std::int64_t peak = gPeakAllocated; now > peak && !gPeakAllocated.compare_exchange_weak(peak, now);) {
  }
  return block;
}

void countedFree(void* block) {
  if (!block) return;
  gAllocated -= std::int64_t(malloc_usable_size(block));
  std::free(block);
}

// The most held since the last call, beyond what was held then.
class AllocationPeak {
 public:
  AllocationPeak() : start_(gAllocated) { gPeakAllocated = start_; }
  std::int64_t bytes() const { return gPeakAllocated - start_; }

 private:
  std::int64_t start_;
};
}  // namespace

void* operator new(std::size_t size) { return countedAllocation(size); }
void* operator new[](std::size_t size) { return countedAllocation(size); }
void operator delete(void* block) noexcept { countedFree(block); }
void operator delete[](void* block) noexcept { countedFree(block); }
void operator delete(void* block, std::size_t) noexcept { countedFree(block); }
void operator delete[](void* block, std::size_t) noexcept { countedFree(block); }

namespace {

namespace fs = std::filesystem;
using namespace bounce;

const fs::path kRepoPairs = fs::path(BOUNCE_TEST_DATA_DIR) / "flip";
const fs::path kSharedPairs = fs::path(BOUNCE_SOURCE_DIR "/../shared/fixtures/flip");

// The acceptance tolerances of the fixtures (their README.md).
constexpr double kLdrTolerance = 1e-3;
constexpr double kHdrTolerance = 2e-3;

// FLIP v1.6's values for a pair (values.json): mean at the default ppd and at
// -ppd 67, and the error-weighted median the tool prints.
struct FlipFixture {
  const char* reference;
  const char* test;
  metrics::FlipMode mode;
  double mean;
  double meanAtPpd67;
  double weightedMedian;
};

const FlipFixture kAllFixtures[] = {
    {"a_gradient_ref.png", "a_gradient_noise.png", metrics::FlipMode::Ldr, 0.106651, 0.106673, 0.11862},
    {"b_checker_ref.png", "b_checker_shift1.png", metrics::FlipMode::Ldr, 0.317231, 0.317253, 0.480847},
    {"c_spheres_ref.png", "c_spheres_blur.png", metrics::FlipMode::Ldr, 0.0639001, 0.0639058, 0.181434},
    {"d_rings_ref.png", "d_rings_same.png", metrics::FlipMode::Ldr, 0.0, 0.0, 0.0},
    {"e_sky_ref.exr", "e_sky_mulnoise.exr", metrics::FlipMode::Hdr, 0.0659743, 0.0659885, 0.0742344},
    {"e_sky_ref.exr", "f_sky_x1.5.exr", metrics::FlipMode::Hdr, 0.366507, 0.366503, 0.366787},
};

metrics::Comparison compareFiles(const fs::path& directory, const FlipFixture& pair, float ppd) {
  metrics::ComparisonOptions options;
  options.flipMode = pair.mode;
  options.pixelsPerDegree = ppd;
  return metrics::compareImages(io::readImage(directory / pair.reference), io::readImage(directory / pair.test),
                                options);
}

double toleranceOf(const FlipFixture& pair) {
  return pair.mode == metrics::FlipMode::Hdr ? kHdrTolerance : kLdrTolerance;
}

void expectMatchesTool(const fs::path& directory, const FlipFixture& pair) {
  SCOPED_TRACE(std::string(pair.reference) + " vs " + pair.test);
  const metrics::Comparison atDefault = compareFiles(directory, pair, metrics::defaultPixelsPerDegree());
  EXPECT_NEAR(atDefault.flip.mean, pair.mean, toleranceOf(pair));
  // The tool's weighted percentiles are a guide, not an acceptance limit.
  EXPECT_NEAR(atDefault.flip.weightedMedian, pair.weightedMedian, 2e-3);
  const metrics::Comparison at67 = compareFiles(directory, pair, 67.0f);
  EXPECT_NEAR(at67.flip.mean, pair.meanAtPpd67, toleranceOf(pair));
}

// --- FLIP against the reference implementation

TEST(Flip, DefaultPixelsPerDegreeIsTheToolsFloat32Value) {
  EXPECT_EQ(metrics::defaultPixelsPerDegree(), 67.0206451f);
  EXPECT_FLOAT_EQ(metrics::pixelsPerDegree(1.0f, 1000.0f, 1.0f), 1000.0f * 3.14159265f / 180.0f);
}

TEST(Flip, RepositoryPairsMatchTheFlipTool) {
  expectMatchesTool(kRepoPairs, kAllFixtures[1]);  // LDR: shifted checkerboard
  expectMatchesTool(kRepoPairs, kAllFixtures[5]);  // HDR: radiance scaled by 1.5
}

TEST(Flip, AllSharedFixturesMatchTheFlipTool) {
  if (!fs::exists(kSharedPairs / "values.json")) {
    GTEST_SKIP() << "shared FLIP fixtures not found at " << kSharedPairs << "; the repository pairs still ran";
  }
  for (const FlipFixture& pair : kAllFixtures) expectMatchesTool(kSharedPairs, pair);
  // Identical files: exactly zero, not merely small.
  const metrics::Comparison identical = compareFiles(kSharedPairs, kAllFixtures[3], metrics::defaultPixelsPerDegree());
  EXPECT_EQ(identical.flip.max, 0.0);
  EXPECT_EQ(identical.flip.mean, 0.0);
}

TEST(Flip, RepositoryCopiesHoldTheSharedPixels) {
  if (!fs::exists(kSharedPairs / "values.json")) GTEST_SKIP() << "shared FLIP fixtures not found at " << kSharedPairs;
  for (const char* name : {"b_checker_ref.png", "b_checker_shift1.png", "e_sky_ref.exr", "f_sky_x1.5.exr"}) {
    const io::ImageF repo = io::readImage(kRepoPairs / name);
    const io::ImageF shared = io::readImage(kSharedPairs / name);
    EXPECT_EQ(repo.channels, shared.channels) << name;
    EXPECT_EQ(repo.pixels, shared.pixels) << name;
  }
}

TEST(Flip, HdrExposureRangeMatchesTheTool) {
  const metrics::RgbImage sky = metrics::toRgb(io::readImage(kRepoPairs / "e_sky_ref.exr"));
  const metrics::ExposureRange range = metrics::hdrFlipExposureRange(sky);
  EXPECT_NEAR(range.start, -4.47976, 1e-5);
  EXPECT_NEAR(range.stop, 0.301467, 1e-5);
  EXPECT_EQ(range.count, 5);
}

TEST(Flip, HdrExposureRangeOfABlackReferenceIsAnError) {
  const metrics::RgbImage black(8, 8);
  EXPECT_THROW(metrics::hdrFlipExposureRange(black), std::invalid_argument);
}

// A smooth colour gradient: the kind of image where noise is easy to see.
metrics::RgbImage gradient(int width, int height) {
  metrics::RgbImage image(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const float u = float(x) / float(width - 1);
      const float v = float(y) / float(height - 1);
      image.at(x, y) = glm::vec3(0.1f + 0.6f * u, 0.2f + 0.5f * v, 0.5f - 0.3f * u * v);
    }
  }
  return image;
}

TEST(Flip, IdenticalImagesGiveExactlyZero) {
  const metrics::RgbImage image = gradient(40, 30);
  for (float value : metrics::ldrFlip(image, image, metrics::defaultPixelsPerDegree()).values) {
    ASSERT_EQ(value, 0.0f);
  }
  metrics::RgbImage radiance = image;
  for (glm::vec3& p : radiance.pixels) p *= 20.0f;
  for (float value : metrics::hdrFlip(radiance, radiance, metrics::defaultPixelsPerDegree()).error.values) {
    ASSERT_EQ(value, 0.0f);
  }
}

TEST(Flip, LargerNoiseGivesLargerFlip) {
  const metrics::RgbImage reference = gradient(64, 48);
  std::mt19937 random(7);
  std::normal_distribution<float> normal;
  std::vector<glm::vec3> pattern(reference.pixels.size());
  for (glm::vec3& n : pattern) n = glm::vec3(normal(random), normal(random), normal(random));

  double previous = 0.0;
  for (float amplitude : {0.005f, 0.01f, 0.02f, 0.04f, 0.08f, 0.16f}) {
    metrics::RgbImage test = reference;
    for (std::size_t i = 0; i < test.pixels.size(); ++i) test.pixels[i] += amplitude * pattern[i];
    const metrics::ScalarImage flip = metrics::ldrFlip(reference, test, metrics::defaultPixelsPerDegree());
    const double mean = metrics::errorStatistics(flip.values).mean;
    EXPECT_GT(mean, previous) << "noise amplitude " << amplitude;
    previous = mean;
  }
  EXPECT_GT(previous, 0.2) << "strong noise is clearly visible";
}

TEST(Flip, LargerExposureErrorGivesLargerHdrFlip) {
  const metrics::RgbImage reference = metrics::toRgb(io::readImage(kRepoPairs / "e_sky_ref.exr"));
  double previous = 0.0;
  for (float scale : {1.02f, 1.05f, 1.1f, 1.25f, 1.5f, 2.0f, 4.0f}) {
    metrics::RgbImage test = reference;
    for (glm::vec3& p : test.pixels) p *= scale;
    const double mean =
        metrics::errorStatistics(metrics::hdrFlip(reference, test, metrics::defaultPixelsPerDegree()).error.values)
            .mean;
    EXPECT_GT(mean, previous) << "radiance scale " << scale;
    previous = mean;
  }
}

TEST(Flip, HdrFlipIsTheMaximumOverItsExposures) {
  const metrics::RgbImage reference = metrics::toRgb(io::readImage(kRepoPairs / "e_sky_ref.exr"));
  const metrics::RgbImage test = metrics::toRgb(io::readImage(kRepoPairs / "f_sky_x1.5.exr"));
  const float ppd = metrics::defaultPixelsPerDegree();
  const metrics::HdrFlipResult hdr = metrics::hdrFlip(reference, test, ppd);
  const float step = (hdr.exposures.stop - hdr.exposures.start) / float(hdr.exposures.count - 1);
  std::vector<float> maximum(reference.pixels.size(), 0.0f);
  for (int i = 0; i < hdr.exposures.count; ++i) {
    metrics::RgbImage exposedReference = reference, exposedTest = test;
    const float multiplier = std::pow(2.0f, hdr.exposures.start + float(i) * step);
    for (glm::vec3& p : exposedReference.pixels) p = metrics::flipToneMap(p * multiplier);
    for (glm::vec3& p : exposedTest.pixels) p = metrics::flipToneMap(p * multiplier);
    const metrics::ScalarImage ldr = metrics::ldrFlip(exposedReference, exposedTest, ppd);
    for (std::size_t p = 0; p < maximum.size(); ++p) maximum[p] = std::max(maximum[p], ldr.values[p]);
  }
  EXPECT_EQ(hdr.error.values, maximum);
  for (float position : hdr.exposureOfMaximum.values) {
    ASSERT_GE(position, 0.0f);
    ASSERT_LE(position, 1.0f);
  }
}

// Two images with edges, dots and noise at every scale FLIP looks at.
std::pair<metrics::RgbImage, metrics::RgbImage> busyPair(int width, int height, float scale) {
  metrics::RgbImage reference = gradient(width, height), test = reference;
  std::mt19937 random(11);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  for (std::size_t p = 0; p < test.pixels.size(); ++p) {
    if (uniform(random) < 0.1f) reference.pixels[p] = glm::vec3(uniform(random), uniform(random), uniform(random));
    test.pixels[p] = reference.pixels[p] * (0.8f + 0.4f * uniform(random));
    reference.pixels[p] *= scale;
    test.pixels[p] *= scale;
  }
  return {reference, test};
}

// FLIP is computed a band of rows at a time (flip.h); every band size must
// give the bits the whole image in one band gives, at the FLIP tool's ppd
// and at one whose filters are wider than a band.
TEST(Flip, BandsOfAnySizeGiveTheBitsOfTheWholeImage) {
  const auto [reference, test] = busyPair(37, 53, 1.0f);
  const auto [radiance, radianceTest] = busyPair(37, 53, 40.0f);
  for (const float ppd : {metrics::defaultPixelsPerDegree(), 150.0f}) {
    SCOPED_TRACE("ppd " + std::to_string(ppd));
    const metrics::ScalarImage whole = metrics::ldrFlip(reference, test, ppd, 53);
    const metrics::HdrFlipResult wholeHdr = metrics::hdrFlip(radiance, radianceTest, ppd, std::nullopt, 53);
    ASSERT_GT(metrics::errorStatistics(whole.values).mean, 0.02);
    for (const int rows : {1, 2, 7, 52, 0}) {
      SCOPED_TRACE(std::to_string(rows) + " rows a band");
      EXPECT_EQ(metrics::ldrFlip(reference, test, ppd, rows).values, whole.values);
      const metrics::HdrFlipResult hdr = metrics::hdrFlip(radiance, radianceTest, ppd, std::nullopt, rows);
      EXPECT_EQ(hdr.error.values, wholeHdr.error.values);
      EXPECT_EQ(hdr.exposureOfMaximum.values, wholeHdr.exposureOfMaximum.values);
    }
  }
}

// The whole image's YCxCz and filter sums took about 100 bytes a pixel
// (7 GB for an 8192 x 8192 pair); now FLIP holds its result and a ring of
// rows, whatever the height. A million pixels, two bands of the default size.
TEST(Flip, HoldsOnlyItsResultAndARingOfRows) {
  const int width = 64, height = 16384;
  const float ppd = metrics::defaultPixelsPerDegree();
  const auto [reference, test] = busyPair(width, height, 1.0f);
  const std::int64_t map = std::int64_t(width) * height * std::int64_t(sizeof(float));
  const std::int64_t working = std::int64_t(metrics::flipWorkingBytes(width, height, ppd));
  const std::int64_t slack = 1 << 20;  // filters, thread objects
  EXPECT_EQ(working, std::int64_t(metrics::flipWorkingBytes(width, 4 * height, ppd))) << "the rows do not grow";
  {
    const AllocationPeak peak;
    const metrics::ScalarImage flip = metrics::ldrFlip(reference, test, ppd);
    EXPECT_LE(peak.bytes(), map + working + slack);
  }
  {
    const AllocationPeak peak;
    const metrics::HdrFlipResult flip = metrics::hdrFlip(reference, test, ppd);
    EXPECT_LE(peak.bytes(), 2 * map + working + slack) << "the error and the exposure of its maximum";
  }
}

// compare reads FLIP's inputs in place: an image's R, G and B (alpha left
// out), or its one channel as grey, give the bits their copies give.
TEST(Flip, ImagesAreReadInPlaceAsTheirCopiesAre) {
  const float ppd = metrics::defaultPixelsPerDegree();
  const auto [reference, test] = busyPair(29, 17, 1.0f);
  io::ImageF rgba(29, 17, {"A", "B", "G", "R"}), rgbaTest(29, 17, {"A", "B", "G", "R"});
  io::ImageF grey(29, 17, {"Y"}), greyTest(29, 17, {"Y"});
  for (int y = 0; y < 17; ++y)
    for (int x = 0; x < 29; ++x) {
      for (int c = 0; c < 3; ++c) {
        rgba.at(x, y, 3 - c) = reference.at(x, y)[c];
        rgbaTest.at(x, y, 3 - c) = test.at(x, y)[c];
      }
      rgba.at(x, y, 0) = rgbaTest.at(x, y, 0) = 0.5f;
      grey.at(x, y, 0) = reference.at(x, y).y;
      greyTest.at(x, y, 0) = test.at(x, y).y;
    }
  EXPECT_EQ(metrics::ldrFlip(metrics::rgbView(rgba), metrics::rgbView(rgbaTest), ppd).values,
            metrics::ldrFlip(metrics::toRgb(rgba), metrics::toRgb(rgbaTest), ppd).values);
  EXPECT_EQ(metrics::hdrFlip(metrics::rgbView(grey), metrics::rgbView(greyTest), ppd).error.values,
            metrics::hdrFlip(metrics::toRgb(grey), metrics::toRgb(greyTest), ppd).error.values);
  EXPECT_THROW(metrics::rgbView(io::ImageF(4, 4, {"X", "Y"})), std::invalid_argument);
}

// Radiance times exposure beyond 1.8e19 overflowed the tone mapper's square
// and made its pixel, and through the filters its neighbours, NaN, which
// HDR-FLIP's maximum skipped: a test image of 3e38 scored 0, identical to
// its reference. The tone mapper saturates instead.
TEST(Flip, HugeRadianceIsAVisibleDifferenceNotNaN) {
  metrics::RgbImage reference(24, 16), spike(24, 16), huge(24, 16);
  for (glm::vec3& p : reference.pixels) p = glm::vec3(1.0f);
  spike = reference;
  spike.at(12, 8) = glm::vec3(3.4e38f);
  for (glm::vec3& p : huge.pixels) p = glm::vec3(3.0e38f);
  EXPECT_EQ(metrics::flipToneMap(glm::vec3(3.0e38f)), glm::vec3(1.0f));
  EXPECT_EQ(metrics::flipToneMap(glm::vec3(-3.0e38f)), glm::vec3(1.0f)) << "as the curve gives for any large value";
  const float ppd = metrics::defaultPixelsPerDegree();
  const metrics::HdrFlipResult one = metrics::hdrFlip(reference, spike, ppd);
  for (float v : one.error.values) ASSERT_TRUE(std::isfinite(v));
  // The reference exposed to 0.85 of white against white: what a viewer sees.
  EXPECT_GT(one.error.at(12, 8), 0.05f);
  EXPECT_EQ(one.error.at(0, 0), 0.0f) << "far from the spike";
  const metrics::HdrFlipResult all = metrics::hdrFlip(reference, huge, ppd);
  EXPECT_GT(metrics::errorStatistics(all.error.values).min, 0.1);
}

// Below about 1.7 pixels per degree (compare --ppd takes 0.01) the feature
// filters' lobes underflowed to 0 and were normalised 0 / 0: LDR-FLIP was
// NaN everywhere and HDR-FLIP 0. Their limit, the central difference, is
// used instead.
TEST(Flip, TinyPixelsPerDegreeGiveFiniteFlip) {
  const auto [reference, test] = busyPair(20, 12, 1.0f);
  for (const float ppd : {0.01f, 0.5f, 1.5f}) {
    SCOPED_TRACE("ppd " + std::to_string(ppd));
    const metrics::ScalarImage ldr = metrics::ldrFlip(reference, test, ppd);
    for (float v : ldr.values) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f) << v;
    EXPECT_GT(metrics::errorStatistics(ldr.values).mean, 0.01);
    for (float v : metrics::ldrFlip(reference, reference, ppd).values) ASSERT_EQ(v, 0.0f);
    EXPECT_GT(metrics::errorStatistics(metrics::hdrFlip(reference, test, ppd).error.values).mean, 0.01);
  }
}

TEST(Flip, MismatchedSizesAreRefused) {
  EXPECT_THROW(metrics::ldrFlip(gradient(8, 8), gradient(8, 9), 67.0f), std::invalid_argument);
  EXPECT_THROW(metrics::ldrFlip(gradient(8, 8), gradient(8, 8), 0.0f), std::invalid_argument);
}

TEST(Flip, ToneMapAndMagmaEndpoints) {
  EXPECT_EQ(metrics::flipToneMap(glm::vec3(0.0f)), glm::vec3(0.0f));
  EXPECT_EQ(metrics::flipToneMap(glm::vec3(1.0e6f)), glm::vec3(1.0f)) << "saturates to white";
  EXPECT_EQ(io::magma(0.0f), (std::array<std::uint8_t, 3>{0, 0, 4}));
  EXPECT_EQ(io::magma(1.0f), (std::array<std::uint8_t, 3>{252, 253, 191}));
  EXPECT_EQ(io::magma(7.0f), io::magma(1.0f)) << "clamped";
}

// --- value errors, statistics, temporal stability

io::ImageF constantImage(int width, int height, float value) {
  io::ImageF image(width, height, {"R", "G", "B"});
  std::fill(image.pixels.begin(), image.pixels.end(), value);
  return image;
}

TEST(ValueErrors, ConstantOffsetHasKnownErrors) {
  const io::ImageF reference = constantImage(16, 8, 0.5f);
  const io::ImageF test = constantImage(16, 8, 0.6f);
  const metrics::ValueErrors e =
      metrics::valueErrors(metrics::comparedValues(reference), metrics::comparedValues(test));
  const double offset = double(0.6f) - double(0.5f);
  EXPECT_NEAR(e.mse, offset * offset, 1e-12);
  EXPECT_NEAR(e.rmse, offset, 1e-9);
  EXPECT_NEAR(e.psnrDb, 20.0, 1e-5) << "offset 0.1 against peak 1";
  EXPECT_NEAR(e.relMse, offset * offset / (0.25 + metrics::kRelMseEpsilon), 1e-12);
  EXPECT_EQ(e.valueCount, 16u * 8u * 3u);
}

TEST(ValueErrors, RelMseWeighsDarkPixelsByTheEpsilon) {
  const std::vector<float> reference = {0.0f, 1.0f};
  const std::vector<float> test = {0.1f, 1.1f};
  const double d0 = double(0.1f), d1 = double(1.1f) - 1.0;
  const metrics::ValueErrors e = metrics::valueErrors(reference, test);
  EXPECT_NEAR(e.relMse, 0.5 * (d0 * d0 / metrics::kRelMseEpsilon + d1 * d1 / (1.0 + metrics::kRelMseEpsilon)), 1e-12);
}

TEST(ValueErrors, IdenticalImagesGiveZeroErrorsAndInfinitePsnr) {
  const io::ImageF image = io::readImage(kRepoPairs / "b_checker_ref.png");
  metrics::ComparisonOptions options;
  const metrics::Comparison c = metrics::compareImages(image, image, options);
  EXPECT_EQ(c.values.mse, 0.0);
  EXPECT_EQ(c.values.rmse, 0.0);
  EXPECT_EQ(c.values.relMse, 0.0);
  EXPECT_TRUE(std::isinf(c.values.psnrDb) && c.values.psnrDb > 0.0);
  EXPECT_EQ(c.flip.mean, 0.0);
  EXPECT_EQ(c.flip.max, 0.0);
  EXPECT_EQ(c.flip.median, 0.0);
  EXPECT_EQ(c.flip.weightedMedian, 0.0);
}

TEST(ValueErrors, AlphaIsNotCompared) {
  io::ImageF reference(2, 1, {"R", "G", "B", "A"});
  reference.pixels = {0.2f, 0.3f, 0.4f, 1.0f, 0.5f, 0.6f, 0.7f, 0.0f};
  io::ImageF test(2, 1, {"R", "G", "B"});
  test.pixels = {0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f};
  EXPECT_EQ(metrics::incompatibility(reference, test), "");
  EXPECT_EQ(metrics::valueErrors(metrics::comparedValues(reference), metrics::comparedValues(test)).mse, 0.0);
}

io::ImageF noisyImage(int width, int height, std::vector<std::string> channels, unsigned seed) {
  io::ImageF image(width, height, std::move(channels));
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 2.0f);
  for (float& v : image.pixels) v = uniform(random);
  return image;
}

// compare sums the errors and the mean luminance pixel by pixel rather than
// over copies of the values: the same sums in the same order, to the bit.
TEST(ValueErrors, ImagesGiveTheBitsOfTheirComparedValues) {
  for (const auto& channels : {std::vector<std::string>{"R", "G", "B", "A"}, std::vector<std::string>{"viewZ"}}) {
    const io::ImageF reference = noisyImage(23, 11, channels, 3), test = noisyImage(23, 11, channels, 4);
    const metrics::ValueErrors copied =
        metrics::valueErrors(metrics::comparedValues(reference), metrics::comparedValues(test));
    const metrics::ValueErrors inPlace = metrics::valueErrors(reference, test);
    EXPECT_EQ(inPlace.mse, copied.mse);
    EXPECT_EQ(inPlace.relMse, copied.relMse);
    EXPECT_EQ(inPlace.psnrDb, copied.psnrDb);
    EXPECT_EQ(inPlace.valueCount, copied.valueCount);
    const std::vector<float> luminance = metrics::luminance(reference);
    double sum = 0.0;
    for (float l : luminance) sum += l;
    EXPECT_EQ(metrics::meanLuminance(reference), sum / double(luminance.size()));
  }
  EXPECT_THROW(metrics::valueErrors(constantImage(4, 4, 0.0f), constantImage(4, 3, 0.0f)), std::invalid_argument);
}

// A comparison used to copy both images' values (for the errors) and
// pixels (for FLIP) beside them; now nothing image-sized but the FLIP map
// and FLIP's rows is added to the images, which it frees before the
// statistics sort a copy of the map.
TEST(ValueErrors, ComparingHoldsOnlyTheImagesTheMapAndFlipsRows) {
  const int width = 256, height = 1024;
  io::ImageF reference = noisyImage(width, height, {"R", "G", "B"}, 5);
  io::ImageF test = noisyImage(width, height, {"R", "G", "B"}, 6);
  const std::int64_t map = std::int64_t(width) * height * std::int64_t(sizeof(float));
  const std::int64_t working = std::int64_t(metrics::flipWorkingBytes(width, height, 67.0f));
  for (const metrics::FlipMode mode : {metrics::FlipMode::Ldr, metrics::FlipMode::Hdr}) {
    metrics::ComparisonOptions options;
    options.flipMode = mode;
    options.pixelsPerDegree = 67.0f;
    io::ImageF r = reference, t = test;
    const AllocationPeak peak;
    const metrics::Comparison comparison = metrics::compareImages(std::move(r), std::move(t), options);
    EXPECT_LE(peak.bytes(), (mode == metrics::FlipMode::Hdr ? 2 : 1) * map + working + (1 << 20));
    EXPECT_GT(comparison.flip.mean, 0.0);
  }
}

TEST(ValueErrors, IncompatibleImagesAreDescribed) {
  EXPECT_EQ(metrics::incompatibility(constantImage(4, 4, 0.0f), constantImage(4, 3, 0.0f)),
            "is 4x3 but the reference is 4x4");
  io::ImageF grey(4, 4, {"Y"});
  EXPECT_EQ(metrics::incompatibility(constantImage(4, 4, 0.0f), grey), "has channels Y but the reference has R,G,B");
  metrics::ComparisonOptions options;
  EXPECT_THROW(metrics::compareImages(constantImage(4, 4, 0.0f), grey, options), std::invalid_argument);
}

TEST(ErrorStatistics, PercentilesInterpolateAndWeightedOnesFollowTheErrorMass) {
  const std::vector<float> values = {4.0f, 0.0f, 3.0f, 1.0f, 2.0f};
  const metrics::ErrorStatistics s = metrics::errorStatistics(values);
  EXPECT_DOUBLE_EQ(s.mean, 2.0);
  EXPECT_DOUBLE_EQ(s.min, 0.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_DOUBLE_EQ(s.median, 2.0);
  EXPECT_DOUBLE_EQ(s.firstQuartile, 1.0);
  EXPECT_DOUBLE_EQ(s.thirdQuartile, 3.0);
  EXPECT_DOUBLE_EQ(s.percentile95, 3.8);
  const std::vector<float> sorted = {0.0f, 1.0f, 2.0f};
  EXPECT_DOUBLE_EQ(metrics::percentileOfSorted(sorted, 0.25), 0.5);
  // Error mass 1+1+1+1+4 = 8: the first four pixels hold exactly half, so the
  // weighted median (strictly more than half) is the pixel with error 4.
  const std::vector<float> mass = {1.0f, 1.0f, 1.0f, 1.0f, 4.0f};
  EXPECT_DOUBLE_EQ(metrics::weightedPercentileOfSorted(mass, 0.5), 4.0);
  EXPECT_DOUBLE_EQ(metrics::weightedPercentileOfSorted(mass, 0.25), 1.0);
  const std::vector<float> zeros = {0.0f, 0.0f};
  EXPECT_DOUBLE_EQ(metrics::weightedPercentileOfSorted(zeros, 0.5), 0.0);
  EXPECT_THROW(metrics::errorStatistics(std::vector<float>{}), std::invalid_argument);
}

TEST(TemporalStability, StaticFramesAreStableAndChangesAreRelative) {
  const std::vector<float> one(100, 1.0f), brighter(100, 1.1f), black(100, 0.0f);
  EXPECT_EQ(metrics::temporalStability({one, one, one}).meanChange, 0.0);
  const metrics::TemporalStability s = metrics::temporalStability({one, brighter, brighter});
  const double step = (double(1.1f) - 1.0) / (0.5 * (1.0 + double(1.1f)) + metrics::kTemporalEpsilon);
  ASSERT_EQ(s.changePerFrame.size(), 2u);
  EXPECT_NEAR(s.changePerFrame[0], step, 1e-12);
  EXPECT_EQ(s.changePerFrame[1], 0.0);
  EXPECT_NEAR(s.meanChange, step / 2.0, 1e-12);
  EXPECT_NEAR(s.maxChange, step, 1e-12);
  // The same absolute change counts for more in the dark.
  const std::vector<float> dim(100, 0.1f), dimmer(100, 0.2f);
  EXPECT_GT(metrics::relativeChange(dim, dimmer), metrics::relativeChange(one, brighter));
  EXPECT_THROW(metrics::temporalStability({one}), std::invalid_argument);
  EXPECT_THROW(metrics::relativeChange(one, std::vector<float>(99, 1.0f)), std::invalid_argument);
  EXPECT_EQ(metrics::relativeChange(black, black), 0.0);
}

// --- bounce compare, run as a user runs it

struct CommandResult {
  int exitCode;
  std::string out;
  std::string err;
};

std::string readFile(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

CommandResult runCompare(const std::string& arguments) {
  const fs::path errFile = fs::temp_directory_path() / ("bounce_metrics_stderr_" + std::to_string(::getpid()));
  const std::string command = std::string(BOUNCE_BINARY) + " compare " + arguments + " 2>" + errFile.string();
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, "", "popen failed"};
  std::string out;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), int(buffer.size()), pipe)) out += buffer.data();
  const int status = pclose(pipe);
  CommandResult result{WIFEXITED(status) ? WEXITSTATUS(status) : -1, out, readFile(errFile)};
  fs::remove(errFile);
  return result;
}

std::size_t lineCount(const std::string& text) { return std::size_t(std::count(text.begin(), text.end(), '\n')); }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The number after "key": in flat JSON text, NaN when the key is absent.
double jsonValue(const std::string& json, const std::string& key) {
  const std::string quotedKey = "\"" + key + "\": ";
  const std::size_t at = json.find(quotedKey);
  if (at == std::string::npos) return std::numeric_limits<double>::quiet_NaN();
  return std::stod(json.substr(at + quotedKey.size()));
}

class CompareCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() / ("bounce_compare_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }

  static std::string quoted(const fs::path& path) { return "'" + path.string() + "'"; }
  std::string ldrPair() const {
    return quoted(kRepoPairs / "b_checker_ref.png") + " " + quoted(kRepoPairs / "b_checker_shift1.png");
  }

  fs::path dir;
};

TEST_F(CompareCommand, ReportsEveryMetricAndPassesWithinThresholds) {
  const CommandResult r = runCompare(ldrPair() + " --max-flip 0.5 --max-relmse 100 --max-rmse 1 --min-psnr 0");
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_EQ(r.err, "");
  for (const char* metric : {"relMSE", "RMSE", "PSNR", "FLIP", "LDR-FLIP", "median", "quartiles"}) {
    EXPECT_TRUE(contains(r.out, metric)) << metric << " in: " << r.out;
  }
  EXPECT_TRUE(contains(r.out, "mean 0.317")) << r.out;
}

TEST_F(CompareCommand, ExceededThresholdIsExitOneWithOneLineNamingMetricValueAndLimit) {
  const CommandResult flip = runCompare(ldrPair() + " --max-flip 0.1");
  EXPECT_EQ(flip.exitCode, 1) << flip.out << flip.err;
  EXPECT_EQ(lineCount(flip.err), 1u) << flip.err;
  EXPECT_TRUE(contains(flip.err, "FLIP mean 0.317")) << flip.err;
  EXPECT_TRUE(contains(flip.err, "--max-flip 0.1")) << flip.err;

  const CommandResult psnr = runCompare(ldrPair() + " --min-psnr 60");
  EXPECT_EQ(psnr.exitCode, 1);
  EXPECT_EQ(lineCount(psnr.err), 1u) << psnr.err;
  EXPECT_TRUE(contains(psnr.err, "PSNR")) << psnr.err;
  EXPECT_TRUE(contains(psnr.err, "--min-psnr 60")) << psnr.err;

  const CommandResult two = runCompare(ldrPair() + " --max-relmse 0.001 --max-rmse 0.01");
  EXPECT_EQ(two.exitCode, 1);
  EXPECT_EQ(lineCount(two.err), 1u) << two.err;
  EXPECT_TRUE(contains(two.err, "relMSE") && contains(two.err, "--max-relmse 0.001")) << two.err;
  EXPECT_TRUE(contains(two.err, "RMSE") && contains(two.err, "--max-rmse 0.01")) << two.err;
}

TEST_F(CompareCommand, IdenticalImagesPassZeroThresholds) {
  const std::string image = quoted(kRepoPairs / "e_sky_ref.exr");
  const CommandResult r = runCompare(image + " " + image + " --max-flip 0 --max-relmse 0 --max-rmse 0 --min-psnr 1000");
  EXPECT_EQ(r.exitCode, 0) << r.out << r.err;
  EXPECT_TRUE(contains(r.out, "HDR-FLIP")) << "EXR inputs get HDR-FLIP: " << r.out;
}

TEST_F(CompareCommand, HdrPairMatchesTheToolAndWritesJson) {
  const fs::path json = dir / "values.json";
  const CommandResult r = runCompare(quoted(kRepoPairs / "e_sky_ref.exr") + " " +
                                     quoted(kRepoPairs / "f_sky_x1.5.exr") + " --json " + quoted(json));
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const std::string text = readFile(json);
  EXPECT_TRUE(contains(text, "\"mode\": \"hdr\"")) << text;
  EXPECT_NEAR(jsonValue(text, "mean"), 0.366507, kHdrTolerance) << text;
  EXPECT_TRUE(contains(text, "\"exposure_count\": 5")) << text;
  EXPECT_TRUE(contains(text, "\"passed\": true")) << text;

  const CommandResult ldr =
      runCompare(quoted(kRepoPairs / "e_sky_ref.exr") + " " + quoted(kRepoPairs / "f_sky_x1.5.exr") + " --flip ldr");
  EXPECT_TRUE(contains(ldr.out, "LDR-FLIP")) << "--flip overrides the choice: " << ldr.out;
}

TEST_F(CompareCommand, ErrorMapIsAMagmaPngOfTheImageSize) {
  const fs::path map = dir / "flip.png";
  const CommandResult r = runCompare(ldrPair() + " --error-map " + quoted(map));
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const io::ImageF image = io::readImage(map);
  EXPECT_EQ(image.width, 128);
  EXPECT_EQ(image.height, 96);
  // Every pixel is a magma colour; error 0 (e.g. where the shift leaves the
  // checkerboard unchanged) is magma's near-black.
  const std::array<std::uint8_t, 3> zero = io::magma(0.0f);
  bool anyZero = false, anyBright = false;
  for (std::size_t p = 0; p < std::size_t(image.width * image.height); ++p) {
    std::array<int, 3> bytes{};
    for (std::size_t c = 0; c < 3; ++c) {
      bytes[c] = int(std::lround(shared::srgbEncode(image.pixels[p * image.channelCount() + c]) * 255.0f));
    }
    anyZero = anyZero || (bytes[0] == zero[0] && bytes[1] == zero[1] && bytes[2] == zero[2]);
    anyBright = anyBright || bytes[0] > 200;
  }
  EXPECT_TRUE(anyZero);
  EXPECT_TRUE(anyBright) << "a 1-pixel shift of a checkerboard has strong errors";
}

TEST_F(CompareCommand, OutputsNeverReplaceAnInput) {
  const fs::path reference = dir / "reference.png";
  fs::copy_file(kRepoPairs / "b_checker_ref.png", reference);
  const std::string before = readFile(reference);
  const CommandResult map = runCompare(quoted(reference) + " " + quoted(kRepoPairs / "b_checker_shift1.png") +
                                       " --error-map " + quoted(reference));
  EXPECT_EQ(map.exitCode, 2) << map.out << map.err;
  EXPECT_EQ(lineCount(map.err), 1u) << map.err;
  EXPECT_TRUE(contains(map.err, "refusing")) << map.err;
  EXPECT_TRUE(contains(map.err, reference.string())) << map.err;
  // The same file reached by another spelling is still refused.
  const CommandResult spelt = runCompare(quoted(reference) + " " + quoted(kRepoPairs / "b_checker_shift1.png") +
                                         " --error-map " + quoted(dir / "." / "reference.png"));
  EXPECT_EQ(spelt.exitCode, 2) << spelt.out << spelt.err;
  EXPECT_TRUE(contains(spelt.err, "refusing")) << spelt.err;
  // A JSON file is never written over an image: its name must end in .json.
  const CommandResult json = runCompare(quoted(reference) + " " + quoted(kRepoPairs / "b_checker_shift1.png") +
                                        " --json " + quoted(reference));
  EXPECT_EQ(json.exitCode, 2) << json.out << json.err;
  EXPECT_EQ(readFile(reference), before) << "the input is untouched";
}

TEST_F(CompareCommand, MismatchedOrBadImagesAreOneLineNamingTheFile) {
  const fs::path small = dir / "small.png";
  io::writePng(small, constantImage(64, 48, 0.5f), io::PngEncoding::Srgb);
  const CommandResult size = runCompare(quoted(kRepoPairs / "b_checker_ref.png") + " " + quoted(small));
  EXPECT_EQ(size.exitCode, 2);
  EXPECT_EQ(lineCount(size.err), 1u) << size.err;
  EXPECT_TRUE(contains(size.err, small.string())) << size.err;
  EXPECT_TRUE(contains(size.err, "64x48")) << size.err;

  const fs::path grey = dir / "depth.exr";
  io::ImageF greyImage(128, 96, {"viewZ"});  // a "Y" EXR would be read as grey RGB
  io::writeExr(grey, greyImage);
  const CommandResult channels = runCompare(quoted(kRepoPairs / "b_checker_ref.png") + " " + quoted(grey));
  EXPECT_EQ(channels.exitCode, 2);
  EXPECT_EQ(lineCount(channels.err), 1u) << channels.err;
  EXPECT_TRUE(contains(channels.err, grey.string()) && contains(channels.err, "channels")) << channels.err;

  const fs::path nan = dir / "nan.exr";
  io::ImageF nanImage = constantImage(128, 96, 0.5f);
  nanImage.at(3, 2, 1) = std::numeric_limits<float>::quiet_NaN();
  io::writeExr(nan, nanImage);
  const CommandResult nonFinite = runCompare(quoted(kRepoPairs / "e_sky_ref.exr") + " " + quoted(nan));
  EXPECT_EQ(nonFinite.exitCode, 2);
  EXPECT_EQ(lineCount(nonFinite.err), 1u) << nonFinite.err;
  EXPECT_TRUE(contains(nonFinite.err, nan.string()) && contains(nonFinite.err, "NaN")) << nonFinite.err;

  const CommandResult missing = runCompare(quoted(dir / "missing.png") + " " + quoted(small));
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_TRUE(contains(missing.err, "missing.png")) << missing.err;
}

// A PNG of a few hundred bytes can declare 16384 x 16384 pixels: compare
// worked out from the headers that it would need gigabytes and refuses it
// with the numbers, before decoding (this file's data ends after one row,
// so a decoder would have said so instead). It used to decode such images,
// 24 GB for a real one, until the kernel killed it.
TEST_F(CompareCommand, ImagesTooLargeToCompareAreRefusedFromTheirHeaders) {
  const fs::path huge = dir / "huge.png";
  const std::vector<std::uint8_t> bytes = bounce::testing::zeroPng(16384, 16384, 1);
  std::ofstream(huge, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  ASSERT_LT(fs::file_size(huge), 1000u);
  for (const std::string& arguments :
       {quoted(huge) + " " + quoted(huge), "--sequence " + quoted(huge) + " " + quoted(huge)}) {
    const CommandResult r = runCompare(arguments);
    EXPECT_EQ(r.exitCode, 2) << arguments << ": " << r.err;
    EXPECT_EQ(lineCount(r.err), 1u) << r.err;
    EXPECT_TRUE(contains(r.err, "bounce: error: " + huge.string() + ": ")) << r.err;
    EXPECT_TRUE(contains(r.err, "16384x16384")) << r.err;
    EXPECT_TRUE(contains(r.err, "needs about")) << r.err;
    EXPECT_TRUE(contains(r.err, "more than the limit of 2.0 GiB")) << r.err;
  }
  // A size within the limit is decoded, and the short data found.
  const fs::path small = dir / "short.png";
  const std::vector<std::uint8_t> shortBytes = bounce::testing::zeroPng(64, 64, 1);
  std::ofstream(small, std::ios::binary)
      .write(reinterpret_cast<const char*>(shortBytes.data()), std::streamsize(shortBytes.size()));
  const CommandResult decoded = runCompare(quoted(small) + " " + quoted(small));
  EXPECT_EQ(decoded.exitCode, 2);
  EXPECT_TRUE(contains(decoded.err, "cannot decode")) << decoded.err;
}

// A black reference: relMSE is defined (0 against 0, by its epsilon), and
// the mean luminance ratio is undefined, not 0 as it used to print (as if
// the test were black too).
TEST_F(CompareCommand, ABlackReferenceHasDefinedErrorsAndAnUndefinedRatio) {
  const fs::path black = dir / "black.png", grey = dir / "grey.png";
  io::writePng(black, constantImage(16, 8, 0.0f), io::PngEncoding::Srgb);
  io::writePng(grey, constantImage(16, 8, 0.5f), io::PngEncoding::Srgb);
  const CommandResult same = runCompare(quoted(black) + " " + quoted(black) + " --max-relmse 0 --max-flip 0");
  EXPECT_EQ(same.exitCode, 0) << same.out << same.err;
  EXPECT_TRUE(contains(same.out, "relMSE     0  ")) << same.out;
  EXPECT_TRUE(contains(same.out, "ratio undefined (the reference's mean luminance is 0)")) << same.out;
  const CommandResult brighter = runCompare(quoted(black) + " " + quoted(grey));
  EXPECT_EQ(brighter.exitCode, 0) << brighter.err;
  EXPECT_TRUE(contains(brighter.out, "ratio undefined")) << brighter.out;
  EXPECT_FALSE(contains(brighter.out + same.out, " nan") || contains(brighter.out + same.out, "-nan")) << brighter.out;
}

TEST_F(CompareCommand, UsageErrorsExitTwo) {
  for (const std::string& arguments :
       {quoted(kRepoPairs / "b_checker_ref.png"), ldrPair() + " " + quoted(kRepoPairs / "b_checker_ref.png"),
        ldrPair() + " --flip medium", ldrPair() + " --max-temporal 0.1", "--sequence " + ldrPair() + " --max-flip 0.1",
        ldrPair() + " --ppd 0"}) {
    const CommandResult r = runCompare(arguments);
    EXPECT_EQ(r.exitCode, 2) << arguments << ": " << r.err;
    EXPECT_EQ(lineCount(r.err), 1u) << arguments << ": " << r.err;
  }
}

TEST_F(CompareCommand, SequenceMeasuresTemporalStability) {
  const fs::path frames = dir / "frames";
  fs::create_directories(frames);
  // frame0001 flickers brighter; PNGs beside the EXRs are ignored, as bounce
  // render writes both, and so are the frames' parts it writes with --hdr
  // (frameNNNN.indirect-diffuse.exr: another picture every frame).
  const float levels[] = {0.5f, 0.6f, 0.5f, 0.5f};
  for (int i = 0; i < 4; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame%04d", i);
    io::writeExr(frames / (std::string(name) + ".exr"), constantImage(16, 8, levels[i]));
    io::writePng(frames / (std::string(name) + ".png"), constantImage(16, 8, 0.0f), io::PngEncoding::Srgb);
    io::writeExr(frames / (std::string(name) + ".indirect-diffuse.exr"), constantImage(16, 8, 5.0f));
  }
  const fs::path json = dir / "temporal.json";
  const CommandResult r = runCompare("--sequence " + quoted(frames) + " --json " + quoted(json));
  ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
  const double step = (double(0.6f) - double(0.5f)) / (0.5 * (double(0.6f) + double(0.5f)) + 0.01);
  const double mean = 2.0 * step / 3.0;
  EXPECT_NEAR(jsonValue(readFile(json), "mean_change"), mean, 1e-6) << readFile(json);
  EXPECT_TRUE(contains(r.out, "frame0000.exr to frame0001.exr")) << r.out;

  const CommandResult strict = runCompare("--sequence " + quoted(frames) + " --max-temporal 0.01");
  EXPECT_EQ(strict.exitCode, 1);
  EXPECT_EQ(lineCount(strict.err), 1u) << strict.err;
  EXPECT_TRUE(contains(strict.err, "--max-temporal 0.01")) << strict.err;

  const CommandResult files = runCompare("--sequence " + quoted(frames / "frame0002.exr") + " " +
                                         quoted(frames / "frame0003.exr") + " --max-temporal 0");
  EXPECT_EQ(files.exitCode, 0) << "identical frames: " << files.out << files.err;

  const CommandResult one = runCompare("--sequence " + quoted(frames / "frame0002.exr"));
  EXPECT_EQ(one.exitCode, 2);
  EXPECT_TRUE(contains(one.err, "frame0002.exr")) << one.err;

  io::writeExr(frames / "frame0004.exr", constantImage(8, 8, 0.5f));
  const CommandResult resized = runCompare("--sequence " + quoted(frames));
  EXPECT_EQ(resized.exitCode, 2);
  EXPECT_EQ(lineCount(resized.err), 1u) << resized.err;
  EXPECT_TRUE(contains(resized.err, "frame0004.exr: is 8x8 but the first frame is 16x8")) << resized.err;
}

}  // namespace
