#include "metrics/image_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "shared/color.glsl"

namespace bounce::metrics {
namespace {

std::string sizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ",") + name;
  return text;
}

// Index of each of R, G, B in the image's channels, or nullopt if one is missing.
std::optional<std::array<std::size_t, 3>> rgbChannelIndices(const io::ImageF& image) {
  std::array<std::size_t, 3> indices{};
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    const auto found = std::find(image.channels.begin(), image.channels.end(), names[c]);
    if (found == image.channels.end()) return std::nullopt;
    indices[std::size_t(c)] = std::size_t(found - image.channels.begin());
  }
  return indices;
}

std::size_t pixelCount(const io::ImageF& image) { return std::size_t(image.width) * std::size_t(image.height); }

}  // namespace

ValueErrors ValueErrorSums::errors() const {
  if (count_ == 0) throw std::invalid_argument("value errors: no values to compare");
  ValueErrors errors;
  errors.valueCount = count_;
  errors.mse = squared_ / double(count_);
  errors.rmse = std::sqrt(errors.mse);
  errors.relMse = relative_ / double(count_);
  errors.psnrDb = psnrDecibels(errors.mse);
  return errors;
}

ValueErrors valueErrors(std::span<const float> reference, std::span<const float> test) {
  if (reference.size() != test.size()) {
    throw std::invalid_argument("value errors: " + std::to_string(test.size()) + " test values against " +
                                std::to_string(reference.size()) + " reference values");
  }
  ValueErrorSums sums;
  for (std::size_t i = 0; i < reference.size(); ++i) sums.add(reference[i], test[i]);
  return sums.errors();
}

double psnrDecibels(double mse, double peak) {
  if (mse == 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(peak * peak / mse);
}

double percentileOfSorted(std::span<const float> sorted, double p) {
  if (sorted.empty()) throw std::invalid_argument("percentile of no values");
  const double position = std::clamp(p, 0.0, 1.0) * double(sorted.size() - 1);
  const std::size_t below = std::size_t(std::floor(position));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  const double t = position - double(below);
  return double(sorted[below]) + t * (double(sorted[above]) - double(sorted[below]));
}

double weightedPercentileOfSorted(std::span<const float> sorted, double p) {
  if (sorted.empty()) throw std::invalid_argument("weighted percentile of no values");
  const double total = std::accumulate(sorted.begin(), sorted.end(), 0.0);
  const double target = p * total;
  double runningSum = 0.0;
  for (float value : sorted) {
    runningSum += value;
    if (runningSum > target) return value;
  }
  // Only reached when no value carries any error (all zero), or for p >= 1.
  return total > 0.0 ? double(sorted.back()) : 0.0;
}

ErrorStatistics errorStatistics(std::span<const float> perPixel) {
  if (perPixel.empty()) throw std::invalid_argument("error statistics of an empty error map");
  std::vector<float> sorted(perPixel.begin(), perPixel.end());
  std::sort(sorted.begin(), sorted.end());
  ErrorStatistics s;
  s.mean = std::accumulate(sorted.begin(), sorted.end(), 0.0) / double(sorted.size());
  s.min = sorted.front();
  s.max = sorted.back();
  s.firstQuartile = percentileOfSorted(sorted, 0.25);
  s.median = percentileOfSorted(sorted, 0.5);
  s.thirdQuartile = percentileOfSorted(sorted, 0.75);
  s.percentile95 = percentileOfSorted(sorted, 0.95);
  s.percentile99 = percentileOfSorted(sorted, 0.99);
  s.weightedFirstQuartile = weightedPercentileOfSorted(sorted, 0.25);
  s.weightedMedian = weightedPercentileOfSorted(sorted, 0.5);
  s.weightedThirdQuartile = weightedPercentileOfSorted(sorted, 0.75);
  return s;
}

std::vector<std::string> comparedChannels(const io::ImageF& image) {
  if (rgbChannelIndices(image)) return {"R", "G", "B"};
  return image.channels;
}

std::vector<float> comparedValues(const io::ImageF& image) {
  const std::optional<std::array<std::size_t, 3>> rgb = rgbChannelIndices(image);
  if (!rgb) return image.pixels;
  const std::size_t channelCount = image.channelCount();
  std::vector<float> values;
  values.reserve(pixelCount(image) * 3);
  for (std::size_t p = 0; p < pixelCount(image); ++p) {
    for (std::size_t c : *rgb) values.push_back(image.pixels[p * channelCount + c]);
  }
  return values;
}

ValueErrors valueErrors(const io::ImageF& reference, const io::ImageF& test) {
  if (const std::string reason = incompatibility(reference, test); !reason.empty()) {
    throw std::invalid_argument("the test image " + reason);
  }
  // Channel indices of the compared values, in comparedValues' order.
  const auto indices = [](const io::ImageF& image) {
    std::vector<std::size_t> list;
    if (const std::optional<std::array<std::size_t, 3>> rgb = rgbChannelIndices(image)) {
      list.assign(rgb->begin(), rgb->end());
    } else {
      for (std::size_t c = 0; c < image.channelCount(); ++c) list.push_back(c);
    }
    return list;
  };
  const std::vector<std::size_t> referenceChannels = indices(reference), testChannels = indices(test);
  const std::size_t referenceStride = reference.channelCount(), testStride = test.channelCount();
  ValueErrorSums sums;
  for (std::size_t p = 0; p < pixelCount(reference); ++p) {
    for (std::size_t c = 0; c < referenceChannels.size(); ++c) {
      sums.add(reference.pixels[p * referenceStride + referenceChannels[c]],
               test.pixels[p * testStride + testChannels[c]]);
    }
  }
  return sums.errors();
}

RgbView rgbView(const io::ImageF& image) {
  const std::optional<std::array<std::size_t, 3>> rgb = rgbChannelIndices(image);
  if (!rgb && image.channelCount() != 1) {
    throw std::invalid_argument("FLIP needs R, G and B channels or a single channel, not " + joined(image.channels));
  }
  RgbView view;
  view.width = image.width;
  view.height = image.height;
  view.data = image.pixels.empty() ? nullptr : image.pixels.data();
  view.pixelCount = image.channelCount() == 0 ? 0 : image.pixels.size() / image.channelCount();
  view.stride = image.channelCount();
  view.offsets = rgb ? *rgb : std::array<std::size_t, 3>{0, 0, 0};
  return view;
}

RgbImage toRgb(const io::ImageF& image) {
  const std::optional<std::array<std::size_t, 3>> rgb = rgbChannelIndices(image);
  if (!rgb && image.channelCount() != 1) {
    throw std::invalid_argument("FLIP needs R, G and B channels or a single channel, not " + joined(image.channels));
  }
  RgbImage out(image.width, image.height);
  const std::size_t channelCount = image.channelCount();
  for (std::size_t p = 0; p < out.pixels.size(); ++p) {
    const float* pixel = image.pixels.data() + p * channelCount;
    out.pixels[p] = rgb ? glm::vec3(pixel[(*rgb)[0]], pixel[(*rgb)[1]], pixel[(*rgb)[2]]) : glm::vec3(pixel[0]);
  }
  return out;
}

LuminanceOf::LuminanceOf(const io::ImageF& image) : image_(image), rgb_(rgbChannelIndices(image)) {
  if (!rgb_ && image.channelCount() != 1) {
    throw std::invalid_argument("luminance needs R, G and B channels or a single channel, not " +
                                joined(image.channels));
  }
}

float LuminanceOf::operator()(std::size_t p) const {
  const float* pixel = image_.pixels.data() + p * image_.channelCount();
  return rgb_ ? shared::luminance(glm::vec3(pixel[(*rgb_)[0]], pixel[(*rgb_)[1]], pixel[(*rgb_)[2]])) : pixel[0];
}

std::vector<float> luminance(const io::ImageF& image) {
  const LuminanceOf luminanceOf(image);
  std::vector<float> out(pixelCount(image));
  for (std::size_t p = 0; p < out.size(); ++p) out[p] = luminanceOf(p);
  return out;
}

double meanLuminance(const io::ImageF& image) {
  const LuminanceOf luminanceOf(image);
  double sum = 0.0;
  for (std::size_t p = 0; p < pixelCount(image); ++p) sum += luminanceOf(p);
  return pixelCount(image) == 0 ? 0.0 : sum / double(pixelCount(image));
}

std::string incompatibility(const io::ImageF& reference, const io::ImageF& test, std::string_view referenceName) {
  const std::string name(referenceName);
  if (test.width != reference.width || test.height != reference.height) {
    return "is " + sizeText(test.width, test.height) + " but " + name + " is " +
           sizeText(reference.width, reference.height);
  }
  const std::vector<std::string> referenceChannels = comparedChannels(reference);
  const std::vector<std::string> testChannels = comparedChannels(test);
  if (testChannels != referenceChannels) {
    return "has channels " + joined(testChannels) + " but " + name + " has " + joined(referenceChannels);
  }
  return {};
}

Comparison compareImages(io::ImageF reference, io::ImageF test, const ComparisonOptions& options) {
  Comparison result;
  result.values = valueErrors(reference, test);
  result.flipMode = options.flipMode;
  result.pixelsPerDegree = options.pixelsPerDegree;
  const RgbView referenceRgb = rgbView(reference);
  const RgbView testRgb = rgbView(test);
  if (options.flipMode == FlipMode::Hdr) {
    HdrFlipResult hdr = hdrFlip(referenceRgb, testRgb, options.pixelsPerDegree, options.exposures);
    result.flipMap = std::move(hdr.error);
    result.exposures = hdr.exposures;
  } else {
    result.flipMap = ldrFlip(referenceRgb, testRgb, options.pixelsPerDegree);
  }
  // Freed before the statistics copy the map to sort it.
  reference = io::ImageF();
  test = io::ImageF();
  result.flip = errorStatistics(result.flipMap.values);
  return result;
}

double relativeChange(std::span<const float> before, std::span<const float> after) {
  if (before.size() != after.size()) {
    throw std::invalid_argument("relative change between frames of " + std::to_string(before.size()) + " and " +
                                std::to_string(after.size()) + " pixels");
  }
  if (before.empty()) throw std::invalid_argument("relative change between empty frames");
  double sum = 0.0;
  for (std::size_t p = 0; p < before.size(); ++p) {
    const double a = before[p];
    const double b = after[p];
    sum += std::fabs(b - a) / (0.5 * (std::fabs(a) + std::fabs(b)) + kTemporalEpsilon);
  }
  return sum / double(before.size());
}

TemporalStability temporalStability(const std::vector<std::vector<float>>& frames) {
  if (frames.size() < 2) {
    throw std::invalid_argument("temporal stability needs at least 2 frames, got " + std::to_string(frames.size()));
  }
  TemporalStability result;
  for (std::size_t t = 0; t + 1 < frames.size(); ++t) {
    result.changePerFrame.push_back(relativeChange(frames[t], frames[t + 1]));
  }
  result.meanChange = std::accumulate(result.changePerFrame.begin(), result.changePerFrame.end(), 0.0) /
                      double(result.changePerFrame.size());
  result.maxChange = *std::max_element(result.changePerFrame.begin(), result.changePerFrame.end());
  return result;
}

}  // namespace bounce::metrics
