// FLIP: a perceptual difference between a reference and a test image, per
// pixel in [0,1], approximating what a viewer notices when flipping between
// the two at a given viewing distance.
//
//   LDR-FLIP: Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild,
//             "FLIP: A Difference Evaluator for Alternating Images", HPG 2020.
//   HDR-FLIP: Andersson, Nilsson, Shirley, Akenine-Möller, "Visualizing Errors
//             in Rendered High Dynamic Range Images", EG 2021, and Andersson,
//             Nilsson, Akenine-Möller, "Visualizing and Communicating Errors in
//             Rendered Images", Ray Tracing Gems II, ch. 19, 2021.
//
// Written from the papers; constants, filter construction, exposure range and
// float32 arithmetic follow NVIDIA's FLIP v1.6 tool so that values agree with
// it (docs/metrics.md lists the pipeline and the measured agreement).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

namespace bounce::metrics {

// Linear Rec.709 RGB, row 0 at the top.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<glm::vec3> pixels;  // width * height

  RgbImage() = default;
  RgbImage(int w, int h) : width(w), height(h), pixels(std::size_t(w) * std::size_t(h)) {}
  glm::vec3& at(int x, int y) { return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
  const glm::vec3& at(int x, int y) const { return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
};

// Linear RGB read where it lies, without a copy: pixel p's channel c is
// data[p * stride + offsets[c]]. Every RgbImage is one; metrics::rgbView
// (image_metrics.h) makes one of an io::ImageF's R, G and B, or of its
// single channel as grey.
struct RgbView {
  int width = 0;
  int height = 0;
  const float* data = nullptr;
  std::size_t pixelCount = 0;  // pixels data holds: width * height for a consistent view
  std::size_t stride = 3;
  std::array<std::size_t, 3> offsets{0, 1, 2};

  RgbView() = default;
  RgbView(const RgbImage& image)  // implicit: an RgbImage is a view of itself
      : width(image.width),
        height(image.height),
        data(image.pixels.empty() ? nullptr : &image.pixels[0].x),
        pixelCount(image.pixels.size()) {}
  glm::vec3 operator[](std::size_t p) const {
    const float* pixel = data + p * stride;
    return {pixel[offsets[0]], pixel[offsets[1]], pixel[offsets[2]]};
  }
};

// One value per pixel, row 0 at the top.
struct ScalarImage {
  int width = 0;
  int height = 0;
  std::vector<float> values;  // width * height

  ScalarImage() = default;
  ScalarImage(int w, int h, float fill = 0.0f) : width(w), height(h), values(std::size_t(w) * std::size_t(h), fill) {}
  float& at(int x, int y) { return values[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
  float at(int x, int y) const { return values[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
};

// Pixels per degree of visual angle for a viewer distanceMeters from a display
// displayWidthMeters wide that shows displayWidthPixels across. Evaluated in
// float32 exactly as the FLIP tool does, so that the default below matches it.
float pixelsPerDegree(float distanceMeters, float displayWidthPixels, float displayWidthMeters);

// The FLIP tool's default viewing condition: 0.7 m from a 0.7 m wide monitor
// with 3840 pixels across, 67.0206451 pixels per degree (printed as "67").
float defaultPixelsPerDegree();

// LDR-FLIP of two display images of the same size, given as linear RGB
// (an sRGB-encoded PNG decoded to linear). Values outside [0,1] are clamped,
// as a display would. Identical inputs give exactly 0 everywhere. Throws
// std::invalid_argument for empty or differently sized images or a
// non-positive pixelsPerDegree.
//
// Memory: the result (4 bytes a pixel) and a few rows of filter sums,
// whatever the image size: the image is filtered bandRows rows at a time (0:
// as many as make half a million pixels). The result does not depend on
// bandRows, to the bit; it is a parameter so that tests can show that.
ScalarImage ldrFlip(const RgbView& reference, const RgbView& test, float pixelsPerDegree, int bandRows = 0);

// The memory ldrFlip and hdrFlip need beside their inputs and result maps
// for images of this size at this ppd: the ring of filtered rows and each
// thread's rows, in bytes.
std::uint64_t flipWorkingBytes(int width, int height, float pixelsPerDegree);

// The exposures (log2 multipliers of the radiance) at which HDR-FLIP compares.
struct ExposureRange {
  float start = 0.0f;  // exposes the reference's brightest pixel to 0.85 of the tone mapper's white
  float stop = 0.0f;   // exposes the reference's median luminance to the same display value
  int count = 2;       // exposures from start to stop inclusive, evenly spaced
};

// HDR-FLIP's automatic exposure range, chosen from the reference's luminance:
// count = max(2, ceil(stop - start)), about one exposure per stop. Throws
// std::invalid_argument when the reference has no positive luminance (no
// exposure can make a black image visible).
ExposureRange hdrFlipExposureRange(const RgbView& reference);

struct HdrFlipResult {
  ScalarImage error;              // per pixel, the largest LDR-FLIP value over the exposures
  ScalarImage exposureOfMaximum;  // the exposure that gave it, as i / (count - 1) in [0,1]
  ExposureRange exposures;        // the exposures used
};

// HDR-FLIP of two linear radiance images of the same size: each is exposed,
// tone mapped with flipToneMap and compared with LDR-FLIP at every exposure
// of the range (the automatic one unless given); the per-pixel maximum is the
// error. Throws std::invalid_argument as ldrFlip, or for a range with
// start > stop or count < 2. Memory: the two result maps (8 bytes a pixel),
// the exposure range's luminances (4 bytes a pixel, before the maps exist)
// and ldrFlip's rows; bandRows as for ldrFlip.
HdrFlipResult hdrFlip(const RgbView& reference, const RgbView& test, float pixelsPerDegree,
                      std::optional<ExposureRange> exposures = std::nullopt, int bandRows = 0);

// HDR-FLIP's tone mapper: Narkowicz's fit of ACES with the 0.6 pre-exposure
// taken out, per channel, clamped to [0,1] (its input to +-1e6, where it is
// long saturated, so that no radiance overflows it). It is not the renderer's
// tonemapAcesFitted (Hill's fit): HDR-FLIP's values depend on this curve.
glm::vec3 flipToneMap(glm::vec3 exposedRadiance);

}  // namespace bounce::metrics
