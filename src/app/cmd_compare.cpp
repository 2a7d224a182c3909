// bounce compare: how far a test image is from a reference (relMSE, RMSE,
// PSNR, FLIP), or how stable a static camera's frames are over time. Made for
// scripts as much as for people: thresholds turn a comparison into exit code
// 1 with one line saying which metric failed, and --json writes every value.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/option_checks.h"
#include "app/output_files.h"
#include "io/colormap.h"
#include "io/image_io.h"
#include "metrics/flip.h"
#include "metrics/image_metrics.h"

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const fs::path& path, const std::string& reason) {
  throw std::runtime_error(path.string() + ": " + reason);
}

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return text;
}

// --- output: numbers as people and JSON read them

std::string number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

// test / reference, or `undefined` when the reference's mean is 0 (a black
// reference): it used to print 0, as if the test were black.
std::string luminanceRatio(double referenceMean, double testMean,
                           const std::string& undefined = "undefined (the reference's mean luminance is 0)") {
  return referenceMean != 0.0 ? number(testMean / referenceMean) : undefined;
}

// JSON has no infinity or NaN; those become null (PSNR of identical images).
std::string jsonNumber(double value) {
  if (!std::isfinite(value)) return "null";
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (unsigned char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += char(c);
    } else if (c < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
      out += escaped;
    } else {
      out += char(c);
    }
  }
  return out + "\"";
}

void checkMax(std::vector<std::string>& failures, const char* metric, double value, const std::optional<double>& limit,
              const char* flag) {
  if (limit && !(value <= *limit))
    failures.push_back(std::string(metric) + " " + number(value) + " > " + flag + " " + number(*limit));
}

void checkMin(std::vector<std::string>& failures, const char* metric, double value, const std::optional<double>& limit,
              const char* flag) {
  if (limit && !(value >= *limit))
    failures.push_back(std::string(metric) + " " + number(value) + " < " + flag + " " + number(*limit));
}

// One line on stderr for all failed thresholds, exit code 1; 0 when none failed.
int thresholdExitCode(const std::vector<std::string>& failures) {
  if (failures.empty()) return 0;
  std::string line = "bounce: compare failed: ";
  for (std::size_t i = 0; i < failures.size(); ++i) line += (i ? "; " : "") + failures[i];
  std::fprintf(stderr, "%s\n", line.c_str());
  return 1;
}

// --- image pairs

// The magma picture as bytes, written as they are: no float copy of it.
void writeErrorMap(const fs::path& path, const metrics::ScalarImage& flipMap) {
  std::vector<std::uint8_t> rgb(flipMap.values.size() * 3);
  for (std::size_t p = 0; p < flipMap.values.size(); ++p) {
    const std::array<std::uint8_t, 3> colour = io::magma(flipMap.values[p]);
    std::copy(colour.begin(), colour.end(), rgb.begin() + std::ptrdiff_t(p * 3));
  }
  io::writePngBytes(path, flipMap.width, flipMap.height, 3, rgb);
}

std::string sizeText(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

// Colour and radiance are never negative, and FLIP's tone curve clamps a
// negative value to black: a test image of -1 everywhere scored an HDR-FLIP
// of 0.29 without a word. An image whose R, G or B holds one is refused,
// naming its first such pixel, as readImage names the first NaN. (Images
// without R, G, B, such as a one-channel viewZ, are data, not colour, and
// are compared as they are.)
void refuseNegativeColour(const fs::path& path, const io::ImageF& image) {
  const char* const names[3] = {"R", "G", "B"};
  std::size_t rgb[3];
  for (std::size_t c = 0; c < 3; ++c) {
    const auto at = std::find(image.channels.begin(), image.channels.end(), names[c]);
    if (at == image.channels.end()) return;
    rgb[c] = std::size_t(at - image.channels.begin());
  }
  const std::size_t channels = image.channelCount(), pixels = std::size_t(image.width) * std::size_t(image.height);
  for (std::size_t p = 0; p < pixels; ++p)
    for (std::size_t c = 0; c < 3; ++c)
      if (const float value = image.pixels[p * channels + rgb[c]]; value < 0.0f)
        fail(path, "holds a negative " + std::string(names[c]) + " value (" + number(value) + ") at pixel (" +
                       std::to_string(p % std::size_t(image.width)) + ", " +
                       std::to_string(p / std::size_t(image.width)) +
                       "): colour and radiance are never negative, and FLIP would see black there (a signed image, "
                       "such as a normal or motion map, is not one compare measures)");
}

// --- regions: the numbers per label of a label image

struct Region {
  double label = 0.0;
  std::size_t pixels = 0;
  double referenceMean = 0.0;  // luminance
  double testMean = 0.0;
  metrics::ValueErrors errors;
};

// A label image's largest number of distinct labels: more is not a label
// image (a radiance image given by mistake) and would print a page a pixel.
constexpr std::size_t kMaxRegions = 256;

// The label image's numbers, summed pixel by pixel as they are read (no
// copies of the images' values per region).
std::vector<Region> regionsOf(const fs::path& labelsPath, const io::ImageF& reference, const io::ImageF& test) {
  const io::ImageF labels = io::readImage(labelsPath);
  if (labels.width != reference.width || labels.height != reference.height)
    fail(labelsPath, "is " + sizeText(labels.width, labels.height) + ", the images compared are " +
                         sizeText(reference.width, reference.height));
  const std::size_t pixelCount = std::size_t(reference.width) * std::size_t(reference.height);
  // The compared channels (comparedValues' order): R, G, B, or all of them.
  const auto compared = [](const io::ImageF& image) {
    std::vector<std::size_t> indices;
    for (const std::string& name : metrics::comparedChannels(image))
      indices.push_back(
          std::size_t(std::find(image.channels.begin(), image.channels.end(), name) - image.channels.begin()));
    return indices;
  };
  const std::vector<std::size_t> referenceChannels = compared(reference), testChannels = compared(test);
  const metrics::LuminanceOf referenceLuminance(reference), testLuminance(test);
  struct Gathered {
    metrics::ValueErrorSums errors;
    double referenceSum = 0.0, testSum = 0.0;
    std::size_t pixels = 0;
  };
  std::map<double, Gathered> byLabel;
  for (std::size_t p = 0; p < pixelCount; ++p) {
    const float label = labels.pixels[p * labels.channelCount()];  // the first channel
    if (!std::isfinite(label))
      fail(labelsPath, "holds a non-finite label at pixel " + std::to_string(p % std::size_t(labels.width)) + ", " +
                           std::to_string(p / std::size_t(labels.width)));
    Gathered& region = byLabel[double(label)];
    if (byLabel.size() > kMaxRegions)
      fail(labelsPath, "has more than " + std::to_string(kMaxRegions) + " distinct values: not a label image");
    for (std::size_t c = 0; c < referenceChannels.size(); ++c)
      region.errors.add(reference.pixels[p * reference.channelCount() + referenceChannels[c]],
                        test.pixels[p * test.channelCount() + testChannels[c]]);
    region.referenceSum += referenceLuminance(p);
    region.testSum += testLuminance(p);
    ++region.pixels;
  }
  std::vector<Region> regions;
  for (const auto& [label, gathered] : byLabel) {
    Region region;
    region.label = label;
    region.pixels = gathered.pixels;
    region.referenceMean = gathered.referenceSum / double(gathered.pixels);
    region.testMean = gathered.testSum / double(gathered.pixels);
    region.errors = gathered.errors.errors();
    regions.push_back(region);
  }
  return regions;
}

// The most comparePair holds at once (bytes), from the files' headers: the
// images and FLIP's map and rows while FLIP runs (and the label image while
// the regions are counted), the map and its sorted copy for the statistics
// (the images are freed by then), the map and the error map's bytes as it is
// written.
std::uint64_t pairMemory(const io::ImageInfo& reference, const io::ImageInfo& test, const io::ImageInfo* labels,
                         bool hdr, bool errorMap, float ppd) {
  const std::uint64_t pixels = reference.pixels();
  const std::uint64_t images = reference.imageBytes() + test.imageBytes();
  const std::uint64_t map = pixels * sizeof(float);
  std::uint64_t peak = std::max(reference.readBytes(), reference.imageBytes() + test.readBytes());
  if (labels) peak = std::max(peak, images + labels->readBytes());
  // HDR-FLIP keeps the exposure of each pixel's maximum beside the map.
  peak =
      std::max(peak, images + (hdr ? 2 : 1) * map + metrics::flipWorkingBytes(reference.width, reference.height, ppd));
  peak = std::max(peak, 2 * map);
  if (errorMap) peak = std::max(peak, map + 3 * pixels + io::pngWriteBytes(pixels, 3));
  return peak;
}

std::string pairJson(const CompareOptions& options, int width, int height, double referenceMean, double testMean,
                     const metrics::Comparison& c, const std::vector<Region>& regions, bool passed) {
  const metrics::ErrorStatistics& f = c.flip;
  std::ostringstream json;
  json << "{\n";
  json << "  \"reference\": " << jsonString(options.images[0]) << ",\n";
  json << "  \"test\": " << jsonString(options.images[1]) << ",\n";
  json << "  \"width\": " << width << ",\n  \"height\": " << height << ",\n";
  json << "  \"reference_mean_luminance\": " << jsonNumber(referenceMean) << ",\n";
  json << "  \"test_mean_luminance\": " << jsonNumber(testMean) << ",\n";
  json << "  \"relmse\": " << jsonNumber(c.values.relMse) << ",\n";
  json << "  \"relmse_epsilon\": " << jsonNumber(metrics::kRelMseEpsilon) << ",\n";
  json << "  \"mse\": " << jsonNumber(c.values.mse) << ",\n";
  json << "  \"rmse\": " << jsonNumber(c.values.rmse) << ",\n";
  json << "  \"psnr_db\": " << jsonNumber(c.values.psnrDb) << ",\n";
  json << "  \"psnr_peak\": " << jsonNumber(metrics::kPsnrPeak) << ",\n";
  json << "  \"flip\": {\n";
  json << "    \"mode\": \"" << (c.flipMode == metrics::FlipMode::Hdr ? "hdr" : "ldr") << "\",\n";
  json << "    \"ppd\": " << jsonNumber(c.pixelsPerDegree) << ",\n";
  json << "    \"mean\": " << jsonNumber(f.mean) << ",\n";
  json << "    \"median\": " << jsonNumber(f.median) << ",\n";
  json << "    \"first_quartile\": " << jsonNumber(f.firstQuartile) << ",\n";
  json << "    \"third_quartile\": " << jsonNumber(f.thirdQuartile) << ",\n";
  json << "    \"percentile_95\": " << jsonNumber(f.percentile95) << ",\n";
  json << "    \"percentile_99\": " << jsonNumber(f.percentile99) << ",\n";
  json << "    \"min\": " << jsonNumber(f.min) << ",\n";
  json << "    \"max\": " << jsonNumber(f.max) << ",\n";
  json << "    \"weighted_median\": " << jsonNumber(f.weightedMedian) << ",\n";
  json << "    \"weighted_first_quartile\": " << jsonNumber(f.weightedFirstQuartile) << ",\n";
  json << "    \"weighted_third_quartile\": " << jsonNumber(f.weightedThirdQuartile);
  if (c.exposures) {
    json << ",\n    \"start_exposure\": " << jsonNumber(c.exposures->start) << ",\n";
    json << "    \"stop_exposure\": " << jsonNumber(c.exposures->stop) << ",\n";
    json << "    \"exposure_count\": " << c.exposures->count;
  }
  json << "\n  },\n";
  if (!options.regions.empty()) {
    json << "  \"regions_image\": " << jsonString(options.regions) << ",\n  \"regions\": [";
    for (std::size_t i = 0; i < regions.size(); ++i) {
      const Region& r = regions[i];
      json << (i ? ",\n    " : "\n    ") << "{\"label\": " << jsonNumber(r.label) << ", \"pixels\": " << r.pixels
           << ", \"reference_mean_luminance\": " << jsonNumber(r.referenceMean)
           << ", \"test_mean_luminance\": " << jsonNumber(r.testMean)
           << ", \"relmse\": " << jsonNumber(r.errors.relMse) << "}";
    }
    json << "\n  ],\n";
  }
  json << "  \"passed\": " << (passed ? "true" : "false") << "\n}\n";
  return json.str();
}

int comparePair(const CompareOptions& options) {
  const fs::path referencePath = options.images[0];
  const fs::path testPath = options.images[1];
  std::vector<fs::path> inputs = {referencePath, testPath};
  if (!options.regions.empty()) inputs.push_back(options.regions);
  if (!options.errorMap.empty()) {
    refuseToOverwriteInputs(options.errorMap, "--error-map", inputs);
    checkWritableFile(options.errorMap, "--error-map");
  }
  if (!options.json.empty()) {
    refuseToOverwriteInputs(options.json, "--json", inputs);
    if (!options.errorMap.empty() && sameFile(options.json, options.errorMap)) {
      fail(options.json, "--json and --error-map name the same file");
    }
    checkWritableFile(options.json, "--json");
  }

  metrics::ComparisonOptions comparisonOptions;
  const bool hdr = options.flip == "hdr" ||
                   (options.flip == "auto" && (io::holdsRadiance(referencePath) || io::holdsRadiance(testPath)));
  comparisonOptions.flipMode = hdr ? metrics::FlipMode::Hdr : metrics::FlipMode::Ldr;
  comparisonOptions.pixelsPerDegree = options.ppd.value_or(metrics::defaultPixelsPerDegree());

  // The headers first: sizes that differ, or images too large to compare,
  // are refused before a pixel is decoded.
  const io::ImageInfo referenceInfo = io::readImageInfo(referencePath);
  const io::ImageInfo testInfo = io::readImageInfo(testPath);
  const int width = referenceInfo.width, height = referenceInfo.height;
  if (testInfo.width != width || testInfo.height != height)
    fail(testPath, "is " + sizeText(testInfo.width, testInfo.height) + " but the reference is " +
                       sizeText(width, height) + " (" + referencePath.string() + ")");
  std::optional<io::ImageInfo> labelsInfo;
  if (!options.regions.empty()) {
    labelsInfo = io::readImageInfo(options.regions);
    if (labelsInfo->width != width || labelsInfo->height != height)
      fail(options.regions, "is " + sizeText(labelsInfo->width, labelsInfo->height) + ", the images compared are " +
                                sizeText(width, height));
  }
  io::refuseOverMemoryLimit(referencePath,
                            pairMemory(referenceInfo, testInfo, labelsInfo ? &*labelsInfo : nullptr, hdr,
                                       !options.errorMap.empty(), comparisonOptions.pixelsPerDegree),
                            "comparing two " + sizeText(width, height) + " images");

  io::ImageF reference = io::readImage(referencePath);
  io::ImageF test = io::readImage(testPath);
  if (const std::string reason = metrics::incompatibility(reference, test); !reason.empty()) {
    fail(testPath, reason + " (" + referencePath.string() + ")");
  }
  refuseNegativeColour(referencePath, reference);
  refuseNegativeColour(testPath, test);

  double referenceMean = 0.0, testMean = 0.0;
  std::vector<Region> regions;
  metrics::Comparison comparison;
  try {
    referenceMean = metrics::meanLuminance(reference);
    testMean = metrics::meanLuminance(test);
    // HDR-FLIP's exposures span the reference's luminance; a black
    // reference has none, while LDR-FLIP needs no range (black against
    // black is 0). Said here, where the option that helps is known.
    if (hdr && !(referenceMean > 0.0))
      fail(referencePath,
           "is black (no pixel has a positive luminance), so HDR-FLIP has no exposure range to measure over; "
           "compare with --flip ldr");
    if (!options.regions.empty()) regions = regionsOf(options.regions, reference, test);
    // The images go in and are freed there, once FLIP has read them.
    comparison = metrics::compareImages(std::move(reference), std::move(test), comparisonOptions);
  } catch (const std::invalid_argument& e) {
    // What remains are properties of the reference (channel layout for FLIP,
    // a black reference for the HDR exposure range).
    fail(referencePath, e.what());
  }

  const metrics::ErrorStatistics& f = comparison.flip;
  std::printf("reference  %s (%dx%d)\n", referencePath.c_str(), width, height);
  std::printf("test       %s\n", testPath.c_str());
  std::printf("mean       luminance %s (reference) %s (test), ratio %s\n", number(referenceMean).c_str(),
              number(testMean).c_str(), luminanceRatio(referenceMean, testMean).c_str());
  std::printf("relMSE     %s  (epsilon %s)\n", number(comparison.values.relMse).c_str(),
              number(metrics::kRelMseEpsilon).c_str());
  std::printf("RMSE       %s\n", number(comparison.values.rmse).c_str());
  std::printf("PSNR       %s dB  (peak %s)\n", number(comparison.values.psnrDb).c_str(),
              number(metrics::kPsnrPeak).c_str());
  std::printf("FLIP       mean %s  median %s  quartiles %s %s  max %s\n", number(f.mean).c_str(),
              number(f.median).c_str(), number(f.firstQuartile).c_str(), number(f.thirdQuartile).c_str(),
              number(f.max).c_str());
  std::printf("           %s at %s pixels per degree", hdr ? "HDR-FLIP" : "LDR-FLIP",
              number(comparison.pixelsPerDegree).c_str());
  if (comparison.exposures) {
    std::printf(", exposures %s to %s in %d steps", number(comparison.exposures->start).c_str(),
                number(comparison.exposures->stop).c_str(), comparison.exposures->count);
  }
  std::printf("\n           weighted median %s, weighted quartiles %s %s (as the FLIP tool reports)\n",
              number(f.weightedMedian).c_str(), number(f.weightedFirstQuartile).c_str(),
              number(f.weightedThirdQuartile).c_str());

  if (!options.regions.empty()) {
    std::printf("regions    of %s: label, pixels, mean luminance ratio, relMSE\n", options.regions.c_str());
    for (const Region& r : regions)
      std::printf("region     %s %zu %s %s\n", number(r.label).c_str(), r.pixels,
                  luminanceRatio(r.referenceMean, r.testMean, "undefined").c_str(), number(r.errors.relMse).c_str());
  }

  std::vector<std::string> failures;  // thresholds given and not met, as the failure line names them
  checkMax(failures, "relMSE", comparison.values.relMse, options.maxRelMse, "--max-relmse");
  checkMax(failures, "RMSE", comparison.values.rmse, options.maxRmse, "--max-rmse");
  checkMin(failures, "PSNR", comparison.values.psnrDb, options.minPsnr, "--min-psnr");
  checkMax(failures, "FLIP mean", f.mean, options.maxFlip, "--max-flip");

  if (!options.errorMap.empty()) {
    writeErrorMap(options.errorMap, comparison.flipMap);
    std::printf("wrote %s\n", options.errorMap.c_str());
  }
  if (!options.json.empty()) {
    writeTextFile(options.json,
                  pairJson(options, width, height, referenceMean, testMean, comparison, regions, failures.empty()));
    std::printf("wrote %s\n", options.json.c_str());
  }
  std::fflush(stdout);
  return thresholdExitCode(failures);
}

// --- sequences

// The frames of a directory: its images of one kind, sorted by name. bounce
// render writes frameNNNN.png and, with --hdr, frameNNNN.exr side by side, so
// the most precise kind present is taken: EXR, then HDR, PNG, JPEG. The
// frames' parts it writes beside them (frameNNNN.indirect-diffuse.exr: a
// second dot in the name) are not frames: taken with them, every step of
// the sequence would compare a frame with another picture.
std::vector<fs::path> framesInDirectory(const fs::path& directory) {
  const std::vector<std::vector<std::string>> kinds = {{".exr"}, {".hdr"}, {".png"}, {".jpg", ".jpeg"}};
  std::vector<fs::path> all;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory, ec)) {
    if (entry.is_regular_file() && !entry.path().stem().has_extension()) all.push_back(entry.path());
  }
  if (ec) fail(directory, "cannot list (" + ec.message() + ")");
  for (const std::vector<std::string>& extensions : kinds) {
    std::vector<fs::path> frames;
    for (const fs::path& path : all) {
      const std::string extension = lowercase(path.extension().string());
      if (std::find(extensions.begin(), extensions.end(), extension) != extensions.end()) frames.push_back(path);
    }
    if (!frames.empty()) {
      std::sort(frames.begin(), frames.end());
      return frames;
    }
  }
  fail(directory, "holds no .exr, .hdr, .png or .jpg frames");
}

std::vector<fs::path> sequenceFrames(const CompareOptions& options) {
  std::vector<fs::path> frames;
  if (options.images.size() == 1) {
    const fs::path only = options.images[0];
    std::error_code ec;
    if (!fs::is_directory(only, ec)) {
      fail(only, "--sequence needs a directory of frames or at least two frame files");
    }
    frames = framesInDirectory(only);
  } else {
    frames.assign(options.images.begin(), options.images.end());
  }
  if (frames.size() < 2) {
    fail(options.images[0], "--sequence needs at least two frames, found " + std::to_string(frames.size()));
  }
  return frames;
}

int compareSequence(const CompareOptions& options) {
  const std::vector<fs::path> frames = sequenceFrames(options);
  if (!options.json.empty()) {
    refuseToOverwriteInputs(options.json, "--json", frames);
    checkWritableFile(options.json, "--json");
  }

  // One frame at a time: the frame being read and two frames' luminance,
  // checked from each frame's header before it is decoded.
  const auto read = [](const fs::path& path, const io::ImageInfo& info) {
    io::refuseOverMemoryLimit(path, 2 * info.pixels() * sizeof(float) + info.readBytes(),
                              "measuring a sequence of " + sizeText(info.width, info.height) + " frames");
    return io::readImage(path);
  };
  const io::ImageInfo firstInfo = io::readImageInfo(frames[0]);
  io::ImageF first = read(frames[0], firstInfo);
  std::vector<float> previous;
  try {
    previous = metrics::luminance(first);
  } catch (const std::invalid_argument& e) {
    fail(frames[0], e.what());
  }
  // Only its size and channels are needed from here on.
  first.pixels = std::vector<float>();
  std::vector<double> changes;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const io::ImageInfo info = io::readImageInfo(frames[i]);
    if (info.width != first.width || info.height != first.height)
      fail(frames[i], "is " + sizeText(info.width, info.height) + " but the first frame is " +
                          sizeText(first.width, first.height) + " (" + frames[0].string() + ")");
    const io::ImageF frame = read(frames[i], info);
    if (const std::string reason = metrics::incompatibility(first, frame, "the first frame"); !reason.empty()) {
      fail(frames[i], reason + " (" + frames[0].string() + ")");
    }
    std::vector<float> current = metrics::luminance(frame);
    changes.push_back(metrics::relativeChange(previous, current));
    previous = std::move(current);
  }

  double mean = 0.0;
  for (double change : changes) mean += change;
  mean /= double(changes.size());
  const auto worst = std::max_element(changes.begin(), changes.end());
  const std::size_t worstIndex = std::size_t(worst - changes.begin());
  std::printf("frames     %zu (%s ... %s)\n", frames.size(), frames.front().c_str(), frames.back().c_str());
  std::printf("temporal   mean relative change %s per frame  (epsilon %s)\n", number(mean).c_str(),
              number(metrics::kTemporalEpsilon).c_str());
  std::printf("           largest %s, from %s to %s\n", number(*worst).c_str(), frames[worstIndex].filename().c_str(),
              frames[worstIndex + 1].filename().c_str());

  std::vector<std::string> failures;  // thresholds given and not met, as the failure line names them
  checkMax(failures, "temporal change", mean, options.maxTemporal, "--max-temporal");

  if (!options.json.empty()) {
    std::ostringstream json;
    json << "{\n  \"frames\": [";
    for (std::size_t i = 0; i < frames.size(); ++i) json << (i ? ", " : "") << jsonString(frames[i].string());
    json << "],\n  \"temporal_epsilon\": " << jsonNumber(metrics::kTemporalEpsilon) << ",\n";
    json << "  \"change_per_frame\": [";
    for (std::size_t i = 0; i < changes.size(); ++i) json << (i ? ", " : "") << jsonNumber(changes[i]);
    json << "],\n  \"mean_change\": " << jsonNumber(mean) << ",\n";
    json << "  \"max_change\": " << jsonNumber(*worst) << ",\n";
    json << "  \"passed\": " << (failures.empty() ? "true" : "false") << "\n}\n";
    writeTextFile(options.json, json.str());
    std::printf("wrote %s\n", options.json.c_str());
  }
  std::fflush(stdout);
  return thresholdExitCode(failures);
}

}  // namespace

CLI::App* addCompareCommand(CLI::App& app, CompareOptions& options) {
  CLI::App* command = app.add_subcommand(
      "compare",
      "Compare a test image with a reference (relMSE, RMSE, PSNR, FLIP), or measure the temporal stability of "
      "a static camera's frames (--sequence)");
  command
      ->add_option("images", options.images,
                   "REFERENCE TEST (EXR, HDR, PNG or JPEG); with --sequence, a directory of frames or the frame "
                   "files in order")
      ->required();
  CLI::Option* sequence = command->add_flag(
      "--sequence", options.sequence,
      "Measure temporal stability instead: mean relative luminance change between consecutive frames");
  std::vector<CLI::Option*> pairOnly = {
      command
          ->add_option("--flip", options.flip,
                       "FLIP variant: auto (HDR-FLIP for EXR/HDR inputs, LDR-FLIP for PNG/JPEG), ldr or hdr")
          ->check(CLI::IsMember({"auto", "ldr", "hdr"})),
      command
          ->add_option("--ppd", options.ppd,
                       "Pixels per degree of visual angle for FLIP (default 67.02: 0.7 m from a 0.7 m wide 4K "
                       "monitor, as the FLIP tool)")
          ->check(finiteRange(0.01, 10000.0)),
      command
          ->add_option("--error-map", options.errorMap,
                       "Write the FLIP error map to this PNG (magma colour map); never over an input")
          ->check(outputExtension(".png", "PNG")),
      command->add_option("--max-relmse", options.maxRelMse, "Exit 1 if relMSE is above this")
          ->check(finiteAtLeast(0.0)),
      command->add_option("--max-rmse", options.maxRmse, "Exit 1 if RMSE is above this")->check(finiteAtLeast(0.0)),
      command->add_option("--min-psnr", options.minPsnr, "Exit 1 if PSNR (dB, peak 1) is below this")
          ->check(finiteNumber()),
      command->add_option("--max-flip", options.maxFlip, "Exit 1 if the mean FLIP is above this")
          ->check(finiteRange(0.0, 1.0))};
  pairOnly.push_back(command->add_option(
      "--regions", options.regions,
      "Also report the mean ratio and relMSE per label of this image (same size; its first channel's values are "
      "the labels, e.g. the ids.exr of bounce reference's G-buffer: object << 16 | material)"));
  for (CLI::Option* option : pairOnly) sequence->excludes(option);
  command
      ->add_option("--max-temporal", options.maxTemporal,
                   "With --sequence: exit 1 if the mean relative frame-to-frame change is above this")
      ->check(finiteAtLeast(0.0))
      ->needs(sequence);
  command->add_option("--json", options.json, "Also write every value to this JSON file; never over an input")
      ->check(outputExtension(".json", "JSON"));
  // The image count depends on --sequence, so it is checked once parsing is
  // done; a ValidationError here is a usage error like any other (exit 2).
  command->callback([&options] {
    if (!options.sequence && options.images.size() != 2) {
      throw CLI::ValidationError("compare needs two images, REFERENCE and TEST (got " +
                                 std::to_string(options.images.size()) + "); use --sequence for frames");
    }
  });
  return command;
}

int runCompare(const CompareOptions& options) {
  return options.sequence ? compareSequence(options) : comparePair(options);
}

}  // namespace bounce::app
