// LDR-FLIP and HDR-FLIP. The arithmetic is float32 throughout, in the order
// the FLIP tool uses, so that results agree with it to its printed digits
// rather than merely to the tolerance of the fixtures (docs/metrics.md).
#include "metrics/flip.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>

#include <glm/common.hpp>

#include "shared/color.glsl"

namespace bounce::metrics {
namespace {

constexpr float kPi = 3.14159265358979f;

// --- constants of the FLIP paper (HPG 2020, sections 3 and 4)

// Colour pipeline: the HyAB difference is raised to kColourExponent (q_c);
// differences below kColourCutoff * cmax (p_c) are mapped linearly onto
// [0, kColourCutoffTarget] (p_t) and the rest compressed onto [p_t, 1].
constexpr float kColourExponent = 0.7f;
constexpr float kColourCutoff = 0.4f;
constexpr float kColourCutoffTarget = 0.95f;
// Feature pipeline: the edge/point detectors are derivatives of a Gaussian
// whose standard deviation is half of kFeatureWidthDegrees (w) of visual
// angle; the feature difference is raised to kFeatureExponent (q_f).
constexpr float kFeatureWidthDegrees = 0.082f;
constexpr float kFeatureExponent = 0.5f;

// The contrast sensitivity functions of the opponent channels, as sums of two
// Gaussians in the spatial domain: g(x) = a1 sqrt(pi/b1) exp(-pi^2 x^2 / b1)
// + a2 sqrt(pi/b2) exp(-pi^2 x^2 / b2), x in degrees. The achromatic and
// red-green channels have a single Gaussian (a2 = 0; b2 only keeps the
// expression finite).
struct GaussianSum {
  float a1, b1, a2, b2;
};
constexpr GaussianSum kCsfAchromatic{1.0f, 0.0047f, 0.0f, 1.0e-5f};
constexpr GaussianSum kCsfRedGreen{1.0f, 0.0053f, 0.0f, 1.0e-5f};
constexpr GaussianSum kCsfBlueYellow{34.1f, 0.04f, 13.5f, 0.025f};

// --- colour spaces (sRGB primaries, D65 white)

// The exact rational sRGB-to-XYZ matrix (its row sums are the D65 white below).
glm::vec3 linearRgbToXyz(glm::vec3 rgb) {
  const float a11 = 10135552.0f / 24577794.0f, a12 = 8788810.0f / 24577794.0f, a13 = 4435075.0f / 24577794.0f;
  const float a21 = 2613072.0f / 12288897.0f, a22 = 8788810.0f / 12288897.0f, a23 = 887015.0f / 12288897.0f;
  const float a31 = 1425312.0f / 73733382.0f, a32 = 8788810.0f / 73733382.0f, a33 = 70074185.0f / 73733382.0f;
  return {a11 * rgb.x + a12 * rgb.y + a13 * rgb.z, a21 * rgb.x + a22 * rgb.y + a23 * rgb.z,
          a31 * rgb.x + a32 * rgb.y + a33 * rgb.z};
}

glm::vec3 xyzToLinearRgb(glm::vec3 xyz) {
  return {3.241003275f * xyz.x - 1.537398934f * xyz.y - 0.498615861f * xyz.z,
          -0.969224334f * xyz.x + 1.875930071f * xyz.y + 0.041554224f * xyz.z,
          0.055639423f * xyz.x - 0.204011202f * xyz.y + 1.057148933f * xyz.z};
}

constexpr glm::vec3 kD65White{0.950428545f, 1.0f, 1.088900371f};
constexpr glm::vec3 kInverseD65White{1.052156925f, 1.0f, 0.918357670f};

// YCxCz (Flohr et al.): the linearised CIELAB the spatial filters work in, so
// that filtering is a linear operation on colour.
glm::vec3 xyzToYCxCz(glm::vec3 xyz) {
  const glm::vec3 n = xyz * kInverseD65White;
  return {116.0f * n.y - 16.0f, 500.0f * (n.x - n.y), 200.0f * (n.y - n.z)};
}

glm::vec3 yCxCzToXyz(glm::vec3 yCxCz) {
  const float y = (yCxCz.x + 16.0f) / 116.0f;
  const float cx = yCxCz.y / 500.0f;
  const float cz = yCxCz.z / 200.0f;
  return glm::vec3(y + cx, y, y - cz) * kD65White;
}

glm::vec3 xyzToCieLab(glm::vec3 xyz) {
  const float delta = 6.0f / 29.0f;
  const float deltaSquare = delta * delta;
  const float deltaCube = delta * deltaSquare;
  const float factor = 1.0f / (3.0f * deltaSquare);
  const float term = 4.0f / 29.0f;
  const glm::vec3 n = xyz * kInverseD65White;
  const auto f = [&](float t) { return t > deltaCube ? std::pow(t, 1.0f / 3.0f) : factor * t + term; };
  const float fx = f(n.x), fy = f(n.y), fz = f(n.z);
  return {116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz)};
}

// The Hunt effect: chroma is perceived weaker at low luminance, so a and b are
// scaled by L/100 before the difference is taken.
glm::vec3 huntAdjust(glm::vec3 lab) { return {lab.x, 0.01f * lab.x * lab.y, 0.01f * lab.x * lab.z}; }

// HyAB: city-block distance in lightness plus Euclidean distance in chroma,
// which behaves better than CIEDE2000 for large differences.
float hyab(glm::vec3 a, glm::vec3 b) {
  const float da = a.y - b.y;
  const float db = a.z - b.z;
  return std::fabs(a.x - b.x) + std::sqrt(da * da + db * db);
}

// The largest colour difference FLIP expects (pure green against pure blue),
// raised to the colour exponent: the normaliser of the colour error.
float maximumColourDifference() {
  const glm::vec3 green = huntAdjust(xyzToCieLab(linearRgbToXyz({0.0f, 1.0f, 0.0f})));
  const glm::vec3 blue = huntAdjust(xyzToCieLab(linearRgbToXyz({0.0f, 0.0f, 1.0f})));
  return std::pow(hyab(green, blue), kColourExponent);
}

// --- filters (separable: each 2D kernel is the outer product of 1D ones)

// Radius of the CSF filters: three standard deviations of the widest Gaussian.
int spatialFilterRadius(float ppd) {
  const float widestScale = std::max(
      {kCsfAchromatic.b1, kCsfAchromatic.b2, kCsfRedGreen.b1, kCsfRedGreen.b2, kCsfBlueYellow.b1, kCsfBlueYellow.b2});
  return int(std::ceil(3.0f * std::sqrt(widestScale / (2.0f * kPi * kPi)) * ppd));
}

float csfGaussian(float x2, float a, float b) { return a * std::sqrt(kPi / b) * std::exp(-kPi * kPi * x2 / b); }

// One factor of a separable 2D Gaussian a sqrt(pi/b) exp(-pi^2 (x^2+y^2) / b):
// sqrt of the amplitude times the 1D exponential.
float csfGaussianFactor(float x2, float a, float b) {
  return std::sqrt(a * std::sqrt(kPi / b)) * std::exp(-kPi * kPi * x2 / b);
}

// The 1D CSF weights. The blue-yellow CSF is a sum of two Gaussians, which is
// not separable as a whole, so it is filtered as two separable Gaussians
// (blueYellow1, blueYellow2) whose results are added.
struct SpatialFilters {
  int radius = 0;
  std::vector<float> achromatic, redGreen, blueYellow1, blueYellow2;
};

SpatialFilters makeSpatialFilters(float ppd) {
  SpatialFilters f;
  f.radius = spatialFilterRadius(ppd);
  const int width = 2 * f.radius + 1;
  const float degreesPerPixel = 1.0f / ppd;
  float sumAchromatic = 0.0f, sumRedGreen = 0.0f, sumBlueYellow1 = 0.0f, sumBlueYellow2 = 0.0f;
  for (int i = 0; i < width; ++i) {
    const float x = float(i - f.radius) * degreesPerPixel;
    const float x2 = x * x;
    f.achromatic.push_back(csfGaussian(x2, kCsfAchromatic.a1, kCsfAchromatic.b1));
    f.redGreen.push_back(csfGaussian(x2, kCsfRedGreen.a1, kCsfRedGreen.b1));
    f.blueYellow1.push_back(csfGaussianFactor(x2, kCsfBlueYellow.a1, kCsfBlueYellow.b1));
    f.blueYellow2.push_back(csfGaussianFactor(x2, kCsfBlueYellow.a2, kCsfBlueYellow.b2));
    sumAchromatic += f.achromatic.back();
    sumRedGreen += f.redGreen.back();
    sumBlueYellow1 += f.blueYellow1.back();
    sumBlueYellow2 += f.blueYellow2.back();
  }
  // Each 2D kernel must sum to 1. For the blue-yellow pair the 2D sum is
  // S1^2 + S2^2, so both factors are divided by its square root.
  const float blueYellowNorm = 1.0f / std::sqrt(sumBlueYellow1 * sumBlueYellow1 + sumBlueYellow2 * sumBlueYellow2);
  for (int i = 0; i < width; ++i) {
    f.achromatic[std::size_t(i)] *= 1.0f / sumAchromatic;
    f.redGreen[std::size_t(i)] *= 1.0f / sumRedGreen;
    f.blueYellow1[std::size_t(i)] *= blueYellowNorm;
    f.blueYellow2[std::size_t(i)] *= blueYellowNorm;
  }
  return f;
}

// The feature detectors: a Gaussian and its first and second derivatives,
// sigma = w/2 degrees. The Gaussian is normalised to sum 1; the positive and
// negative lobes of each derivative to +1 and -1, so that a full-contrast
// step or dot gives a response near 1 whatever the ppd.
struct FeatureFilters {
  int radius = 0;
  std::vector<float> gaussian, firstDerivative, secondDerivative;
};

FeatureFilters makeFeatureFilters(float ppd) {
  FeatureFilters f;
  const float sigma = 0.5f * kFeatureWidthDegrees * ppd;
  f.radius = int(std::ceil(3.0f * sigma));
  const int width = 2 * f.radius + 1;
  float gaussianSum = 0.0f;
  float firstPositive = 0.0f, firstNegative = 0.0f, secondPositive = 0.0f, secondNegative = 0.0f;
  for (int i = 0; i < width; ++i) {
    const float x = float(i - f.radius);
    const float g = std::exp(-(x * x) / (2.0f * sigma * sigma));
    const float dg = -x * g;
    const float ddg = (x * x / (sigma * sigma) - 1.0f) * g;
    gaussianSum += g;
    (dg > 0.0f ? firstPositive : firstNegative) += std::fabs(dg);
    (ddg > 0.0f ? secondPositive : secondNegative) += std::fabs(ddg);
    f.gaussian.push_back(g);
    f.firstDerivative.push_back(dg);
    f.secondDerivative.push_back(ddg);
  }
  for (int i = 0; i < width; ++i) {
    const std::size_t k = std::size_t(i);
    f.gaussian[k] /= gaussianSum;
    f.firstDerivative[k] /= f.firstDerivative[k] > 0.0f ? firstPositive : firstNegative;
    f.secondDerivative[k] /= f.secondDerivative[k] > 0.0f ? secondPositive : secondNegative;
  }
  // Below about 1.7 pixels per degree the Gaussian is so narrow that its
  // taps beside the centre underflow to 0: the lobes above summed to 0 and
  // the kernels were 0 / 0, NaN, which made every FLIP value NaN (and
  // HDR-FLIP, whose maximum skips NaN, 0). The kernels' limit as the
  // Gaussian narrows is the central difference and its second difference.
  if (!(firstPositive > 0.0f && firstNegative > 0.0f && secondPositive > 0.0f)) {
    std::fill(f.firstDerivative.begin(), f.firstDerivative.end(), 0.0f);
    std::fill(f.secondDerivative.begin(), f.secondDerivative.end(), 0.0f);
    const std::size_t centre = std::size_t(f.radius);
    f.firstDerivative[centre - 1] = 1.0f;
    f.firstDerivative[centre + 1] = -1.0f;
    f.secondDerivative[centre - 1] = 0.5f;
    f.secondDerivative[centre] = -1.0f;
    f.secondDerivative[centre + 1] = 0.5f;
  }
  return f;
}

// Clamp-to-edge addressing: the image is extended by repeating its border.
int clampIndex(int i, int size) { return std::min(std::max(i, 0), size - 1); }

// Runs row(y) for every y in [first, last), rows interleaved over the
// hardware threads; one thread when the rows hold too few pixels to repay
// starting more. Every output pixel is computed by one thread from inputs no
// thread writes, so the result is the same bits whatever the thread count.
template <typename RowFunction>
void forEachRow(int first, int last, int width, const RowFunction& row) {
  constexpr std::size_t kMinimumPixelsPerThread = 16384;
  const std::size_t pixels = std::size_t(std::max(0, last - first)) * std::size_t(width);
  const int threads = std::clamp(int(std::thread::hardware_concurrency()), 1,
                                 int(std::max<std::size_t>(1, pixels / kMinimumPixelsPerThread)));
  if (threads == 1) {
    for (int y = first; y < last; ++y) row(y);
    return;
  }
  std::vector<std::jthread> workers;
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([&row, first, last, threads, t] {
      for (int y = first + t; y < last; y += threads) row(y);
    });
  }
}

// --- LDR-FLIP, a band of rows at a time
//
// Both halves of LDR-FLIP filter separably: a horizontal pass within each
// row, then a vertical pass over the rows within the filter's radius. Only
// the horizontal pass's results (the partial sums below) of the rows a band
// and its radius cover are ever needed at once, so they are kept in a ring
// of rows: each row is filtered horizontally once, each band reads its
// rows and its neighbours', and the image-sized intermediates (YCxCz and
// partial sums of both images, about 100 bytes a pixel) never exist. Every
// value is computed from the same inputs in the same order as a whole-image
// pass would, so the result is the same bits whatever the band size.

// Colour pipeline, horizontal pass: Y, Cx, Cz through blue-yellow Gaussian 1,
// Cz through Gaussian 2. Each opponent channel has its own filter (the
// blue-yellow one two, summed after the vertical pass).
struct ColourPartial {
  float y, cx, cz1, cz2;
};

// Feature pipeline, horizontal pass: d/dx, d2/dx2 and the plain Gaussian, the
// latter for the vertical derivatives of the second pass.
struct FeaturePartial {
  float dx, ddx, g;
};

// Output pixels a band computes: enough that starting threads for it pays,
// few enough that the ring stays small (about 30 MB) whatever the width.
constexpr std::size_t kBandPixels = std::size_t(1) << 19;

int bandRowsFor(int width, int height) {
  return std::min(std::max(height, 1), std::max(8, int(kBandPixels / std::size_t(std::max(width, 1)))));
}

class BandedLdrFlip {
 public:
  // bandRows: output rows per band (0: the default for the size).
  BandedLdrFlip(int width, int height, float ppd, int bandRows)
      : width_(width),
        height_(height),
        spatial_(makeSpatialFilters(ppd)),
        features_(makeFeatureFilters(ppd)),
        bandRows_(bandRows > 0 ? std::min(bandRows, height) : bandRowsFor(width, height)),
        cmax_(maximumColourDifference()),
        halo_(std::max(spatial_.radius, features_.radius)),
        ringRows_(std::min(height, bandRows_ + 2 * halo_)),
        colourReference_(ringSize()),
        colourTest_(ringSize()),
        featureReference_(ringSize()),
        featureTest_(ringSize()) {}

  // displayRow(y, reference, test) fills the two rows' linear display RGB
  // (width values each; clamped to [0,1] here, as a display would);
  // useRow(y, errors) takes row y's LDR-FLIP values. Both are called from
  // several threads at once, for different rows.
  template <typename DisplayRow, typename UseRow>
  void run(const DisplayRow& displayRow, const UseRow& useRow) {
    int filteredUpTo = 0;  // rows [0, filteredUpTo) have been through the horizontal pass
    for (int y0 = 0; y0 < height_; y0 += bandRows_) {
      const int y1 = std::min(height_, y0 + bandRows_);
      const int needed = std::min(height_, y1 + halo_);
      forEachRow(filteredUpTo, needed, width_, [&](int y) { filterRow(y, displayRow); });
      filteredUpTo = needed;
      forEachRow(y0, y1, width_, [&](int y) {
        std::vector<float> errors(static_cast<std::size_t>(width_));
        finishRow(y, errors.data());
        useRow(y, errors.data());
      });
    }
  }

 private:
  std::size_t ringSize() const { return std::size_t(ringRows_) * std::size_t(width_); }
  std::size_t at(int x, int y) const { return std::size_t(y % ringRows_) * std::size_t(width_) + std::size_t(x); }

  // Row y through YCxCz and both horizontal passes, into the ring.
  template <typename DisplayRow>
  void filterRow(int y, const DisplayRow& displayRow) {
    const auto width = static_cast<std::size_t>(width_);
    std::vector<glm::vec3> reference(width), test(width);
    displayRow(y, reference.data(), test.data());
    for (std::size_t x = 0; x < reference.size(); ++x) {
      reference[x] = xyzToYCxCz(linearRgbToXyz(glm::clamp(reference[x], 0.0f, 1.0f)));
      test[x] = xyzToYCxCz(linearRgbToXyz(glm::clamp(test[x], 0.0f, 1.0f)));
    }
    const SpatialFilters& s = spatial_;
    const auto addTap = [&s](ColourPartial& sum, std::size_t tap, float y, float cx, float cz1, float cz2) {
      sum.y += s.achromatic[tap] * y;
      sum.cx += s.redGreen[tap] * cx;
      sum.cz1 += s.blueYellow1[tap] * cz1;
      sum.cz2 += s.blueYellow2[tap] * cz2;
    };
    const int r = s.radius;
    for (int x = 0; x < width_; ++x) {
      ColourPartial ref{0.0f, 0.0f, 0.0f, 0.0f}, tst{0.0f, 0.0f, 0.0f, 0.0f};
      for (int k = -r; k <= r; ++k) {
        const std::size_t source = std::size_t(clampIndex(x + k, width_));
        const std::size_t tap = std::size_t(k + r);
        const glm::vec3 a = reference[source];
        const glm::vec3 b = test[source];
        addTap(ref, tap, a.x, a.y, a.z, a.z);
        addTap(tst, tap, b.x, b.y, b.z, b.z);
      }
      colourReference_[at(x, y)] = ref;
      colourTest_[at(x, y)] = tst;
    }

    // Luminance normalised to [0,1]: (Y + 16) / 116 of YCxCz, i.e. Y / Y_white.
    const auto normalisedLuminance = [](const glm::vec3& yCxCz) { return yCxCz.x * (1.0f / 116.0f) + 16.0f / 116.0f; };
    const FeatureFilters& f = features_;
    const int rf = f.radius;
    for (int x = 0; x < width_; ++x) {
      FeaturePartial ref{0.0f, 0.0f, 0.0f}, tst{0.0f, 0.0f, 0.0f};
      for (int k = -rf; k <= rf; ++k) {
        const std::size_t source = std::size_t(clampIndex(x + k, width_));
        const std::size_t tap = std::size_t(k + rf);
        const float a = normalisedLuminance(reference[source]);
        const float b = normalisedLuminance(test[source]);
        ref.dx += f.firstDerivative[tap] * a;
        ref.ddx += f.secondDerivative[tap] * a;
        ref.g += f.gaussian[tap] * a;
        tst.dx += f.firstDerivative[tap] * b;
        tst.ddx += f.secondDerivative[tap] * b;
        tst.g += f.gaussian[tap] * b;
      }
      featureReference_[at(x, y)] = ref;
      featureTest_[at(x, y)] = tst;
    }
  }

  // Row y's vertical passes and the two differences combined.
  void finishRow(int y, float* errors) const {
    const SpatialFilters& s = spatial_;
    const int r = s.radius;
    const float cmax = cmax_;
    const float cutoff = kColourCutoff * cmax;
    const auto addTap = [&s](ColourPartial& sum, std::size_t tap, float y, float cx, float cz1, float cz2) {
      sum.y += s.achromatic[tap] * y;
      sum.cx += s.redGreen[tap] * cx;
      sum.cz1 += s.blueYellow1[tap] * cz1;
      sum.cz2 += s.blueYellow2[tap] * cz2;
    };
    // Filtered YCxCz -> displayable linear RGB -> Hunt-adjusted CIELAB.
    const auto toPerceptual = [](const ColourPartial& p) {
      const glm::vec3 rgb = glm::clamp(xyzToLinearRgb(yCxCzToXyz({p.y, p.cx, p.cz1 + p.cz2})), 0.0f, 1.0f);
      return huntAdjust(xyzToCieLab(linearRgbToXyz(rgb)));
    };
    const FeatureFilters& f = features_;
    const int rf = f.radius;
    // Edge and point responses are gradient-magnitude-like, each in [0, sqrt(2)].
    const float normalisation = 1.0f / std::sqrt(2.0f);
    // Where in the ring each tap's row starts (a division per row, not per tap).
    const auto ringRowStarts = [&](int radius) {
      std::vector<std::size_t> starts;
      for (int k = -radius; k <= radius; ++k) starts.push_back(at(0, clampIndex(y + k, height_)));
      return starts;
    };
    const std::vector<std::size_t> colourRows = ringRowStarts(r), featureRows = ringRowStarts(rf);
    for (int x = 0; x < width_; ++x) {
      // Colour difference in [0,1]: HyAB of the filtered colours, then the
      // compressing remap (small differences use most of [0,1], large ones
      // are compressed into the top).
      ColourPartial ref{0.0f, 0.0f, 0.0f, 0.0f}, tst{0.0f, 0.0f, 0.0f, 0.0f};
      for (int k = -r; k <= r; ++k) {
        const std::size_t tap = std::size_t(k + r);
        const std::size_t source = colourRows[tap] + std::size_t(x);
        const ColourPartial& a = colourReference_[source];
        const ColourPartial& b = colourTest_[source];
        addTap(ref, tap, a.y, a.cx, a.cz1, a.cz2);
        addTap(tst, tap, b.y, b.cx, b.cz1, b.cz2);
      }
      const float perceived = std::pow(hyab(toPerceptual(ref), toPerceptual(tst)), kColourExponent);
      const float colour = perceived < cutoff ? perceived * (kColourCutoffTarget / cutoff)
                                              : kColourCutoffTarget + ((perceived - cutoff) / (cmax - cutoff)) *
                                                                          (1.0f - kColourCutoffTarget);

      // Feature difference in [0,1]: the larger of the differences in edge
      // strength and in point strength.
      float dxRef = 0.0f, ddxRef = 0.0f, dyRef = 0.0f, ddyRef = 0.0f;
      float dxTest = 0.0f, ddxTest = 0.0f, dyTest = 0.0f, ddyTest = 0.0f;
      for (int k = -rf; k <= rf; ++k) {
        const std::size_t tap = std::size_t(k + rf);
        const std::size_t source = featureRows[tap] + std::size_t(x);
        const FeaturePartial& a = featureReference_[source];
        const FeaturePartial& b = featureTest_[source];
        dxRef += f.gaussian[tap] * a.dx;
        ddxRef += f.gaussian[tap] * a.ddx;
        dyRef += f.firstDerivative[tap] * a.g;
        ddyRef += f.secondDerivative[tap] * a.g;
        dxTest += f.gaussian[tap] * b.dx;
        ddxTest += f.gaussian[tap] * b.ddx;
        dyTest += f.firstDerivative[tap] * b.g;
        ddyTest += f.secondDerivative[tap] * b.g;
      }
      const float edgeDifference =
          std::fabs(std::sqrt(dxRef * dxRef + dyRef * dyRef) - std::sqrt(dxTest * dxTest + dyTest * dyTest));
      const float pointDifference =
          std::fabs(std::sqrt(ddxRef * ddxRef + ddyRef * ddyRef) - std::sqrt(ddxTest * ddxTest + ddyTest * ddyTest));
      const float feature = std::pow(normalisation * std::max(edgeDifference, pointDifference), kFeatureExponent);

      // Features sharpen the colour error: where edges or points differ, the
      // exponent drops below 1 and lifts the error towards 1.
      errors[x] = std::pow(colour, 1.0f - feature);
    }
  }

  int width_, height_;
  SpatialFilters spatial_;
  FeatureFilters features_;
  int bandRows_;
  float cmax_;  // the largest colour difference, the normaliser of the colour error
  int halo_, ringRows_;
  // Row y of the image is ring row y % ringRows_.
  std::vector<ColourPartial> colourReference_, colourTest_;
  std::vector<FeaturePartial> featureReference_, featureTest_;
};

void checkPair(const RgbView& reference, const RgbView& test, float ppd) {
  if (reference.width <= 0 || reference.height <= 0) throw std::invalid_argument("FLIP: the reference image is empty");
  if (reference.pixelCount != std::size_t(reference.width) * std::size_t(reference.height) ||
      test.pixelCount != std::size_t(test.width) * std::size_t(test.height) || !reference.data || !test.data) {
    throw std::invalid_argument("FLIP: image pixel count does not match its size");
  }
  if (test.width != reference.width || test.height != reference.height) {
    throw std::invalid_argument("FLIP: the test image is " + std::to_string(test.width) + "x" +
                                std::to_string(test.height) + " but the reference is " +
                                std::to_string(reference.width) + "x" + std::to_string(reference.height));
  }
  if (!(ppd > 0.0f) || !std::isfinite(ppd)) {
    throw std::invalid_argument("FLIP: pixels per degree must be positive and finite (got " + std::to_string(ppd) +
                                ")");
  }
}

// The tone mapper's curve, (k0 x^2 + k1 x + k2) / (k3 x^2 + k4 x + k5).
struct ToneCurve {
  float k0, k1, k2, k3, k4, k5;
};
constexpr ToneCurve kAces{0.6f * 0.6f * 2.51f, 0.6f * 0.03f, 0.0f, 0.6f * 0.6f * 2.43f, 0.6f * 0.59f, 0.14f};
// Far beyond the exposed radiance at which flipToneMap saturates (12.1), far
// below the one at which its square overflows float (1.8e19).
constexpr float kToneMapInputLimit = 1.0e6f;
// HDR-FLIP's exposure range aims the chosen luminances at this display value.
constexpr float kExposureTarget = 0.85f;

}  // namespace

float pixelsPerDegree(float distanceMeters, float displayWidthPixels, float displayWidthMeters) {
  return distanceMeters * (displayWidthPixels / displayWidthMeters) * (kPi / 180.0f);
}

float defaultPixelsPerDegree() { return pixelsPerDegree(0.7f, 3840.0f, 0.7f); }

ScalarImage ldrFlip(const RgbView& reference, const RgbView& test, float ppd, int bandRows) {
  checkPair(reference, test, ppd);
  ScalarImage error(reference.width, reference.height);
  const std::size_t width = std::size_t(reference.width);
  BandedLdrFlip(reference.width, reference.height, ppd, bandRows)
      .run(
          [&](int y, glm::vec3* referenceRow, glm::vec3* testRow) {
            for (std::size_t x = 0, p = std::size_t(y) * width; x < width; ++x, ++p) {
              referenceRow[x] = reference[p];
              testRow[x] = test[p];
            }
          },
          [&](int y, const float* errors) {
            std::copy_n(errors, width, error.values.begin() + long(std::size_t(y) * width));
          });
  return error;
}

std::uint64_t flipWorkingBytes(int width, int height, float ppd) {
  if (width <= 0 || height <= 0 || !(ppd > 0.0f) || !std::isfinite(ppd)) return 0;
  const std::uint64_t halo = std::uint64_t(std::max(spatialFilterRadius(ppd), makeFeatureFilters(ppd).radius));
  const std::uint64_t ringRows = std::min<std::uint64_t>(std::uint64_t(height), bandRowsFor(width, height) + 2 * halo);
  const std::uint64_t ring = ringRows * std::uint64_t(width) * 2 * (sizeof(ColourPartial) + sizeof(FeaturePartial));
  // Each thread's two rows of colour and one of errors.
  const std::uint64_t threads = std::max(1u, std::thread::hardware_concurrency());
  return ring + threads * std::uint64_t(width) * (2 * sizeof(glm::vec3) + sizeof(float));
}

glm::vec3 flipToneMap(glm::vec3 c) {
  // The curve squares its input, so radiance times exposure beyond about
  // 1.8e19 overflowed to infinity and made it inf / inf, NaN: a test image
  // of 3e38 read as identical to its reference (HDR-FLIP's maximum skips
  // NaN). The curve is at 1 from 12.1 on, so this clamp changes no value
  // that was not NaN.
  c = glm::clamp(c, -kToneMapInputLimit, kToneMapInputLimit);
  const glm::vec3 numerator = c * c * kAces.k0 + c * kAces.k1 + kAces.k2;
  const glm::vec3 denominator = c * c * kAces.k3 + c * kAces.k4 + kAces.k5;
  return glm::clamp(numerator / denominator, 0.0f, 1.0f);
}

ExposureRange hdrFlipExposureRange(const RgbView& reference) {
  if (reference.pixelCount == 0 || !reference.data)
    throw std::invalid_argument("HDR-FLIP: the reference image is empty");
  // The radiance x the tone mapper maps to the target: the larger root of
  // (k0 - t k3) x^2 + (k1 - t k4) x + (k2 - t k5) = 0.
  const float a = kAces.k0 - kExposureTarget * kAces.k3;
  const float b = kAces.k1 - kExposureTarget * kAces.k4;
  const float c = kAces.k2 - kExposureTarget * kAces.k5;
  const float halfB = -0.5f * (b / a);
  const float targetRadiance = halfB + std::sqrt(halfB * halfB - c / a);

  std::vector<float> luminances(reference.pixelCount);
  for (std::size_t i = 0; i < luminances.size(); ++i) luminances[i] = shared::luminance(reference[i]);
  const float maximum = *std::max_element(luminances.begin(), luminances.end());
  // The upper median (element n/2 of the sorted values), as the FLIP tool takes it.
  const auto middle = luminances.begin() + std::ptrdiff_t(luminances.size() / 2);
  std::nth_element(luminances.begin(), middle, luminances.end());
  const float median = *middle;
  if (!(maximum > 0.0f)) {
    throw std::invalid_argument("HDR-FLIP: the reference has no positive luminance, so no exposure range exists");
  }

  ExposureRange range;
  range.start = std::log2(targetRadiance / maximum);
  // A mostly black reference has median 0; then the darkest lit pixel stands in.
  float stopLuminance = median;
  if (!(stopLuminance > 0.0f)) {
    stopLuminance = maximum;
    for (float l : luminances) {
      if (l > 0.0f) stopLuminance = std::min(stopLuminance, l);
    }
  }
  range.stop = std::log2(targetRadiance / stopLuminance);
  range.count = int(std::max(2.0f, std::ceil(range.stop - range.start)));
  return range;
}

HdrFlipResult hdrFlip(const RgbView& reference, const RgbView& test, float ppd, std::optional<ExposureRange> exposures,
                      int bandRows) {
  checkPair(reference, test, ppd);
  HdrFlipResult result;
  result.exposures = exposures ? *exposures : hdrFlipExposureRange(reference);
  const ExposureRange& range = result.exposures;
  if (!(range.start <= range.stop) || range.count < 2 || !std::isfinite(range.start) || !std::isfinite(range.stop)) {
    throw std::invalid_argument("HDR-FLIP: exposure range needs finite start <= stop and at least 2 exposures (got " +
                                std::to_string(range.start) + " to " + std::to_string(range.stop) + ", " +
                                std::to_string(range.count) + ")");
  }

  result.error = ScalarImage(reference.width, reference.height, 0.0f);
  result.exposureOfMaximum = ScalarImage(reference.width, reference.height, 0.0f);
  const float step = (range.stop - range.start) / float(range.count - 1);
  const std::size_t width = std::size_t(reference.width);
  // One exposure after the other, each pixel keeping its largest error: the
  // tone-mapped images exist a row at a time, inside the LDR-FLIP bands.
  for (int i = 0; i < range.count; ++i) {
    const float multiplier = std::pow(2.0f, range.start + float(i) * step);
    const float exposurePosition = float(i) / float(range.count - 1);
    BandedLdrFlip(reference.width, reference.height, ppd, bandRows)
        .run(
            [&](int y, glm::vec3* referenceRow, glm::vec3* testRow) {
              for (std::size_t x = 0, p = std::size_t(y) * width; x < width; ++x, ++p) {
                referenceRow[x] = flipToneMap(reference[p] * multiplier);
                testRow[x] = flipToneMap(test[p] * multiplier);
              }
            },
            [&](int y, const float* errors) {
              for (std::size_t x = 0, p = std::size_t(y) * width; x < width; ++x, ++p) {
                if (errors[x] > result.error.values[p]) {
                  result.error.values[p] = errors[x];
                  result.exposureOfMaximum.values[p] = exposurePosition;
                }
              }
            });
  }
  return result;
}

}  // namespace bounce::metrics
