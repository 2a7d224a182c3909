// Image comparison metrics: value errors (relMSE, RMSE, PSNR), statistics of
// a per-pixel error map (mean, percentiles), FLIP of an image pair (flip.h),
// and the temporal stability of a frame sequence from a static camera.
// docs/metrics.md says what each number means and how to read it.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "io/image_io.h"
#include "metrics/flip.h"

namespace bounce::metrics {

// relMSE divides each squared error by reference^2 + kRelMseEpsilon, so that
// dark pixels (reference near 0) do not dominate; 0.01 is a common choice in
// the rendering and denoising literature. Compare relMSE values only when
// they were computed with the same epsilon.
inline constexpr double kRelMseEpsilon = 0.01;
// PSNR is taken over a peak of 1, the display white: for PNG/JPEG inputs the
// values are linear light in [0,1]; for HDR radiance 1 is the white of an
// unexposed display, and values above it make PSNR less meaningful (prefer
// relMSE there).
inline constexpr double kPsnrPeak = 1.0;

// Errors of the test values against the reference values, value by value.
struct ValueErrors {
  double mse = 0.0;     // mean of (test - reference)^2
  double rmse = 0.0;    // sqrt(mse)
  double relMse = 0.0;  // mean of (test - reference)^2 / (reference^2 + kRelMseEpsilon)
  double psnrDb = 0.0;  // 10 log10(kPsnrPeak^2 / mse); +infinity when mse is 0
  std::size_t valueCount = 0;
};

// The sums behind ValueErrors, added to value by value: for errors over a
// part of an image (a region) without copying its values out.
class ValueErrorSums {
 public:
  void add(float reference, float test) {
    const double r = reference;
    const double difference = double(test) - r;
    squared_ += difference * difference;
    relative_ += difference * difference / (r * r + kRelMseEpsilon);
    ++count_;
  }
  std::size_t count() const { return count_; }
  // Throws std::invalid_argument when nothing was added.
  ValueErrors errors() const;

 private:
  double squared_ = 0.0;
  double relative_ = 0.0;
  std::size_t count_ = 0;
};

// Both spans hold the same number of values (else std::invalid_argument).
ValueErrors valueErrors(std::span<const float> reference, std::span<const float> test);

// 10 log10(peak^2 / mse) in decibels; +infinity for mse == 0.
double psnrDecibels(double mse, double peak = kPsnrPeak);

// Statistics of a per-pixel error such as a FLIP map.
struct ErrorStatistics {
  double mean = 0.0;
  double min = 0.0;
  double max = 0.0;
  // Ordinary percentiles: linear interpolation between the two nearest
  // order statistics (position p * (n - 1) in the sorted values).
  double firstQuartile = 0.0;
  double median = 0.0;
  double thirdQuartile = 0.0;
  double percentile95 = 0.0;
  double percentile99 = 0.0;
  // The FLIP tool's error-weighted percentiles: the smallest value v such
  // that pixels with error <= v carry more than p of the summed error. They
  // describe where the error mass lies and are what the tool prints.
  double weightedFirstQuartile = 0.0;
  double weightedMedian = 0.0;
  double weightedThirdQuartile = 0.0;
};

// Throws std::invalid_argument for an empty span.
ErrorStatistics errorStatistics(std::span<const float> perPixel);

// The p-th percentile (p in [0,1]) of values sorted ascending, as above.
double percentileOfSorted(std::span<const float> sorted, double p);
// The error-weighted percentile of non-negative values sorted ascending.
double weightedPercentileOfSorted(std::span<const float> sorted, double p);

// --- images (io::ImageF) as the metrics see them

// The channels compared: R, G and B when the image has them (alpha is
// ignored: it is not something a viewer sees), otherwise all its channels
// (e.g. a single "viewZ" or "Y").
std::vector<std::string> comparedChannels(const io::ImageF& image);

// The compared channels' values, pixel by pixel.
std::vector<float> comparedValues(const io::ImageF& image);

// The values of the compared channels of two images incompatibility()
// passes, compared as valueErrors(comparedValues(reference),
// comparedValues(test)) would, to the bit, without copying them.
ValueErrors valueErrors(const io::ImageF& reference, const io::ImageF& test);

// Linear RGB for FLIP: R, G, B, or a single channel as grey. Throws
// std::invalid_argument for any other channel layout.
RgbImage toRgb(const io::ImageF& image);

// The same pixels as toRgb's, read in place (the image must outlive the
// view): FLIP of a large image without a copy of it.
RgbView rgbView(const io::ImageF& image);

// Rec.709 luminance of RGB, or the single channel's value, pixel by pixel.
// Throws std::invalid_argument for any other channel layout.
class LuminanceOf {
 public:
  explicit LuminanceOf(const io::ImageF& image);
  float operator()(std::size_t pixel) const;

 private:
  const io::ImageF& image_;
  std::optional<std::array<std::size_t, 3>> rgb_;
};

// Rec.709 luminance of RGB, or the single channel's value.
std::vector<float> luminance(const io::ImageF& image);

// The mean of luminance(image), to the bit, without the vector.
double meanLuminance(const io::ImageF& image);

// Why test cannot be compared with reference (different size or compared
// channels), phrased about the test image ("is 64x48 but the reference is
// 128x96", with referenceName in place of "the reference"); empty when they
// can be compared.
std::string incompatibility(const io::ImageF& reference, const io::ImageF& test,
                            std::string_view referenceName = "the reference");

// --- a whole comparison, as `bounce compare` reports it

enum class FlipMode { Ldr, Hdr };

struct ComparisonOptions {
  FlipMode flipMode = FlipMode::Ldr;
  float pixelsPerDegree = defaultPixelsPerDegree();
  std::optional<ExposureRange> exposures;  // HDR only; automatic when empty
};

struct Comparison {
  ValueErrors values;
  FlipMode flipMode = FlipMode::Ldr;
  float pixelsPerDegree = 0.0f;
  ScalarImage flipMap;                     // per-pixel FLIP in [0,1]
  ErrorStatistics flip;                    // statistics of flipMap
  std::optional<ExposureRange> exposures;  // the exposures used by HDR-FLIP
};

// Throws std::invalid_argument when incompatibility() is not empty or the
// options are invalid. The images are moved in and freed once FLIP has read
// them, so that the statistics' sorted copy of the FLIP map is never held
// beside them: the most the comparison holds is the two images, the map (two
// for HDR-FLIP) and FLIP's rows (flip.h).
Comparison compareImages(io::ImageF reference, io::ImageF test, const ComparisonOptions& options);

// --- temporal stability of a static camera's frames

// Relative change counts |a - b| / ((a + b) / 2 + kTemporalEpsilon) per pixel,
// on luminance; the epsilon keeps near-black noise from dominating, as in
// relMSE.
inline constexpr double kTemporalEpsilon = 0.01;

struct TemporalStability {
  std::vector<double> changePerFrame;  // entry t: mean relative change from frame t to frame t+1
  double meanChange = 0.0;             // mean of changePerFrame: 0 for a perfectly stable sequence
  double maxChange = 0.0;              // the worst step
};

// Mean relative change from one frame's luminance to the next's (same length,
// else std::invalid_argument), for measuring long sequences one step at a time.
double relativeChange(std::span<const float> before, std::span<const float> after);

// frames: per-frame luminance (see luminance()), all the same length; at
// least two frames (else std::invalid_argument). With a static camera and
// static scene every change is flicker, noise or temporal lag settling.
TemporalStability temporalStability(const std::vector<std::vector<float>>& frames);

}  // namespace bounce::metrics
