// CPU tests of shaders/shared/sampling.glsl and of the material model it
// samples (brdf.glsl): every sampler against its pdf by a chi-square test
// (after pbrt-v4's bsdfs_test.cpp), pdf normalisation, white furnace,
// reciprocity, robustness at the edges of the valid inputs, and the sample
// sequences. docs/material-model.md reports the numbers these print.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <initializer_list>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "shared/brdf.glsl"
#include "shared/rng.glsl"
#include "shared/sampling.glsl"

namespace {

using namespace bounce::shared;

// --- Statistics

// Regularised upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a):
// the series for P = 1 - Q below x = a + 1, where it converges fast, and
// Lentz's continued fraction for Q above (Numerical Recipes, section 6.2).
double upperIncompleteGammaQ(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double logPrefactor = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a;
    double sum = term;
    for (int n = 1; n < 100000 && std::abs(term) > std::abs(sum) * 1e-16; ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return std::max(0.0, 1.0 - sum * std::exp(logPrefactor));
  }
  constexpr double kTiny = 1e-300;
  double b = x + 1.0 - a;
  double c = 1.0 / kTiny;
  double d = 1.0 / b;
  double fraction = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    fraction *= delta;
    if (std::abs(delta - 1.0) < 1e-16) break;
  }
  return std::exp(logPrefactor) * fraction;
}

// P(X >= chiSquare) for X chi-square distributed with `dof` degrees of freedom.
double chiSquarePValue(double chiSquare, int dof) { return upperIncompleteGammaQ(0.5 * dof, 0.5 * chiSquare); }

// The test grid: roughness from the smoothest lobe float evaluation keeps
// (perceptual 0.05, the ggxAlpha clamp) to 1, views from normal to grazing.
constexpr std::array<float, 6> kRoughnesses = {0.05f, 0.1f, 0.25f, 0.5f, 0.75f, 1.0f};
constexpr std::array<float, 4> kViewCosines = {1.0f, 0.7f, 0.3f, 0.05f};
constexpr int kMaterialCount = 3;
constexpr std::array<float, 2> kLobeAxisViewCosines = {0.7f, 0.05f};

// Every chi-square test the binary runs; the Sidak correction below keeps the
// chance that any of them fails by bad luck at 1 % for the whole binary.
constexpr int kChiSquareTestCount = 2                                                     // cosine, uniform
                                    + 2 * int(kRoughnesses.size() * kViewCosines.size())  // VNDF normals, reflections
                                    + kMaterialCount * int(kRoughnesses.size() * kViewCosines.size())  // material
                                    + int(kRoughnesses.size() * kLobeAxisViewCosines.size());          // uniform lobe
constexpr double kFamilySignificance = 0.01;
const double kPerTestSignificance = 1.0 - std::pow(1.0 - kFamilySignificance, 1.0 / kChiSquareTestCount);

// --- Directions on a (theta, phi) grid

// Cell edges on [lo, hi]: uniform steps, plus edges at center +- width *
// 2^k (k from -3 up), so that a lobe of angular size `width` gets cells of
// its own size and smaller, whatever its size; a lobe narrower than the
// uniform cells would otherwise sit inside one cell, testing nothing, and
// its integral would be inaccurate.
std::vector<double> cellEdges(double lo, double hi, int uniformSteps, double center, double width) {
  std::vector<double> edges;
  for (int i = 0; i <= uniformSteps; ++i) edges.push_back(lo + (hi - lo) * i / uniformSteps);
  if (width > 0.0)
    for (double offset = width / 8.0; offset < hi - lo; offset *= 2.0)
      for (double edge : {center - offset, center + offset})
        if (edge > lo && edge < hi) edges.push_back(edge);
  std::sort(edges.begin(), edges.end());
  edges.erase(
      std::unique(edges.begin(), edges.end(), [&](double a, double b) { return std::abs(a - b) < 1e-9 * (hi - lo); }),
      edges.end());
  return edges;
}

struct DirectionGrid {
  glm::dvec3 axisX{1, 0, 0}, axisY{0, 1, 0}, axisZ{0, 0, 1};  // theta from z, phi from x towards y
  std::vector<double> thetaEdges;                             // 0 .. pi/2 (hemisphere) or pi (sphere)
  std::vector<double> phiEdges;                               // 0 .. 2 pi

  int thetaCells() const { return int(thetaEdges.size()) - 1; }
  int phiCells() const { return int(phiEdges.size()) - 1; }
  int cellCount() const { return thetaCells() * phiCells(); }

  glm::dvec3 direction(double theta, double phi) const {
    return std::sin(theta) * (std::cos(phi) * axisX + std::sin(phi) * axisY) + std::cos(theta) * axisZ;
  }

  // The cell holding direction, or -1 outside the grid (below the horizon of
  // a hemisphere grid). atan2 rather than acos keeps tiny angles exact.
  int cellOf(glm::vec3 direction) const {
    const glm::dvec3 d(direction);
    const double x = glm::dot(d, axisX), y = glm::dot(d, axisY), z = glm::dot(d, axisZ);
    const double theta = std::atan2(std::sqrt(x * x + y * y), z);
    double phi = std::atan2(y, x);
    if (phi < 0.0) phi += 2.0 * std::numbers::pi;
    if (theta >= thetaEdges.back()) return -1;
    const int i = int(std::upper_bound(thetaEdges.begin(), thetaEdges.end(), theta) - thetaEdges.begin()) - 1;
    const int j = std::clamp(int(std::upper_bound(phiEdges.begin(), phiEdges.end(), phi) - phiEdges.begin()) - 1, 0,
                             phiCells() - 1);
    return i * phiCells() + j;
  }
};

// A hemisphere grid around n, with phi measured from the tangential part of
// v, refined around the mirror direction (theta_v, phi = pi) at the scales
// of a lobe of angular widths thetaWidth, phiWidth.
DirectionGrid hemisphereGrid(glm::vec3 n, glm::vec3 v, double lobeTheta, double thetaWidth, double phiWidth) {
  DirectionGrid grid;
  grid.axisZ = glm::dvec3(n);
  glm::dvec3 tangential = glm::dvec3(v) - glm::dot(glm::dvec3(v), grid.axisZ) * grid.axisZ;
  if (glm::length(tangential) < 1e-6) {
    vec3 t, b;
    buildOrthonormalBasis(n, t, b);
    tangential = glm::dvec3(t);
  }
  grid.axisX = glm::normalize(tangential);
  grid.axisY = glm::cross(grid.axisZ, grid.axisX);
  grid.thetaEdges = cellEdges(0.0, 0.5 * std::numbers::pi, 16, lobeTheta, thetaWidth);
  grid.phiEdges = cellEdges(0.0, 2.0 * std::numbers::pi, 32, std::numbers::pi, std::min(phiWidth, std::numbers::pi));
  return grid;
}

// The widths of a GGX reflection lobe around the mirror direction: the
// reflection doubles the normal's deviation (alpha) in the plane of
// incidence; across it, the deviation is scaled by v.h, about cos(theta_v),
// and phi stretches by 1 / sin(theta_r).
DirectionGrid reflectionGrid(glm::vec3 n, glm::vec3 v, float alpha) {
  const double cosThetaV = glm::dot(n, v);
  const double sinThetaV = std::sqrt(std::max(0.0, 1.0 - cosThetaV * cosThetaV));
  return hemisphereGrid(n, v, std::acos(cosThetaV), 2.0 * alpha, 2.0 * alpha * cosThetaV / std::max(sinThetaV, 1e-3));
}

constexpr std::array<double, 5> kGaussNodes = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                               0.9061798459386640};
constexpr std::array<double, 5> kGaussWeights = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                                 0.4786286704993665, 0.2369268850561891};

// The integral of f over each cell (d omega = sin(theta) d theta d phi), by
// 5 x 5 Gauss-Legendre points. Gauss points never lie on a cell's edge, so
// a pdf that jumps at an edge (the uniform cone) is integrated exactly.
std::vector<double> integrateCells(const DirectionGrid& grid, const std::function<double(glm::vec3)>& f) {
  std::vector<double> integrals(grid.cellCount(), 0.0);
  for (int i = 0; i < grid.thetaCells(); ++i)
    for (int j = 0; j < grid.phiCells(); ++j) {
      const double theta0 = grid.thetaEdges[i], theta1 = grid.thetaEdges[i + 1];
      const double phi0 = grid.phiEdges[j], phi1 = grid.phiEdges[j + 1];
      double sum = 0.0;
      for (int a = 0; a < 5; ++a) {
        const double theta = 0.5 * (theta0 + theta1) + 0.5 * (theta1 - theta0) * kGaussNodes[a];
        for (int b = 0; b < 5; ++b) {
          const double phi = 0.5 * (phi0 + phi1) + 0.5 * (phi1 - phi0) * kGaussNodes[b];
          sum += kGaussWeights[a] * kGaussWeights[b] * f(glm::vec3(grid.direction(theta, phi))) * std::sin(theta);
        }
      }
      integrals[i * grid.phiCells() + j] = sum * 0.25 * (theta1 - theta0) * (phi1 - phi0);
    }
  return integrals;
}

double integrate(const DirectionGrid& grid, const std::function<double(glm::vec3)>& f) {
  double total = 0.0;
  for (double cell : integrateCells(grid, f)) total += cell;
  return total;
}

// Draws one direction from three uniform numbers; false for a rejected sample.
using Sampler = std::function<bool(glm::vec3 u, glm::vec3& direction)>;
using Pdf = std::function<double(glm::vec3 direction)>;

struct ChiSquareOutcome {
  double chiSquare = 0.0;
  int dof = 0;
  double pValue = 0.0;
  double invalidShare = 0.0;
};

// Pearson's chi-square test of sample counts per grid cell against the
// counts the pdf predicts, pbrt-style: cells expecting fewer than 5 samples
// are pooled into one, so the chi-square approximation holds. Rejected
// samples (and samples outside the grid) form one more cell, expecting the
// probability the pdf leaves outside the grid.
ChiSquareOutcome chiSquareTest(const DirectionGrid& grid, const Sampler& sample, const Pdf& pdf, int sampleCount,
                               uint seed) {
  std::vector<double> expected = integrateCells(grid, pdf);
  double inside = 0.0;
  for (double& cell : expected) {
    inside += cell;
    cell *= sampleCount;
  }
  expected.push_back(std::max(0.0, 1.0 - inside) * sampleCount);

  std::vector<double> observed(expected.size(), 0.0);
  uint state = seed;
  for (int s = 0; s < sampleCount; ++s) {
    const glm::vec3 u(rngUniform(state), rngUniform(state), rngUniform(state));
    glm::vec3 direction;
    const int cell = sample(u, direction) ? grid.cellOf(direction) : -1;
    observed[cell >= 0 ? cell : expected.size() - 1] += 1.0;
  }

  ChiSquareOutcome outcome;
  outcome.invalidShare = observed.back() / sampleCount;
  constexpr double kMinExpected = 5.0;
  std::vector<std::pair<double, double>> bins;  // (expected, observed), each expecting >= kMinExpected
  double pooledExpected = 0.0, pooledObserved = 0.0;
  for (size_t i = 0; i < expected.size(); ++i) {
    if (expected[i] < kMinExpected) {
      pooledExpected += expected[i];
      pooledObserved += observed[i];
    } else {
      bins.push_back({expected[i], observed[i]});
    }
  }
  if (pooledExpected == 0.0 && pooledObserved > 0.0) {
    outcome.chiSquare = INFINITY;  // samples where the pdf says none can be
  } else if (pooledExpected > 0.0) {
    // A pool still short of kMinExpected joins the smallest bin.
    if (pooledExpected < kMinExpected && !bins.empty()) {
      auto smallest = std::min_element(bins.begin(), bins.end());
      smallest->first += pooledExpected;
      smallest->second += pooledObserved;
    } else {
      bins.push_back({pooledExpected, pooledObserved});
    }
  }
  for (const auto& [binExpected, binObserved] : bins)
    outcome.chiSquare += (binObserved - binExpected) * (binObserved - binExpected) / binExpected;
  const int cells = int(bins.size());
  outcome.dof = std::max(cells - 1, 1);
  outcome.pValue = std::isfinite(outcome.chiSquare) ? chiSquarePValue(outcome.chiSquare, outcome.dof) : 0.0;
  return outcome;
}

// Collects a family's p-values, checks each against the corrected threshold,
// and prints the family's weakest result for docs/material-model.md.
class ChiSquareFamily {
 public:
  explicit ChiSquareFamily(std::string name) : name_(std::move(name)) {}
  ~ChiSquareFamily() {
    std::printf("[chi-square] %-28s %3d tests, smallest p = %.3g (%s), threshold %.2g\n", name_.c_str(), count_, minP_,
                minLabel_.c_str(), kPerTestSignificance);
  }
  void check(const ChiSquareOutcome& outcome, const std::string& label) {
    ++count_;
    if (outcome.pValue < minP_) {
      minP_ = outcome.pValue;
      minLabel_ = label;
    }
    EXPECT_GT(outcome.pValue, kPerTestSignificance)
        << name_ << " " << label << ": chi2 " << outcome.chiSquare << " dof " << outcome.dof;
  }

 private:
  std::string name_;
  int count_ = 0;
  double minP_ = 1.0;
  std::string minLabel_;
};

std::string label(float roughness, float cosThetaV) {
  char text[64];
  std::snprintf(text, sizeof text, "roughness %.2f cos %.2f", roughness, cosThetaV);
  return text;
}

// A view at cos(theta) = cosThetaV off n, at an azimuth that lines up with no axis.
glm::vec3 viewAt(float cosThetaV, glm::vec3 n = glm::vec3(0, 0, 1)) {
  vec3 t, b;
  buildOrthonormalBasis(n, t, b);
  const float sinThetaV = std::sqrt(std::max(0.0f, 1.0f - cosThetaV * cosThetaV));
  return glm::normalize(sinThetaV * (std::cos(0.6f) * t + std::sin(0.6f) * b) + cosThetaV * n);
}

struct TestMaterial {
  glm::vec3 baseColor;
  float metallic;
  const char* name;
};
constexpr std::array<TestMaterial, kMaterialCount> kMaterials = {{
    {glm::vec3(0.9f, 0.6f, 0.3f), 0.0f, "dielectric"},
    {glm::vec3(0.9f, 0.6f, 0.3f), 0.5f, "half-metal"},
    {glm::vec3(0.95f, 0.64f, 0.54f), 1.0f, "metal"},
}};

// A normal that is no coordinate axis, so that sampleMaterial's world <->
// local frame is exercised.
const glm::vec3 kTiltedNormal = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));

// --- Statistics helpers are themselves tested: a wrong p-value would make
// every chi-square test meaningless.

TEST(Statistics, ChiSquarePValueMatchesClosedForms) {
  // For even dof = 2k, Q(k, x) = exp(-x) sum_{i<k} x^i / i!.
  for (int k : {1, 2, 5, 30})
    for (double x : {0.3, 2.0, 9.0, 40.0, 80.0}) {
      double sum = 0.0, term = 1.0;
      for (int i = 0; i < k; ++i) {
        sum += term;
        term *= x / (i + 1);
      }
      EXPECT_NEAR(upperIncompleteGammaQ(k, x), std::exp(-x) * sum, 1e-12 + 1e-9 * std::exp(-x) * sum) << k << " " << x;
    }
  // Half-integer a: Q(1/2, x) = erfc(sqrt(x)).
  for (double x : {0.01, 0.5, 3.0, 20.0}) EXPECT_NEAR(upperIncompleteGammaQ(0.5, x), std::erfc(std::sqrt(x)), 1e-12);
  EXPECT_NEAR(chiSquarePValue(103.4, 63), 1e-3, 1e-4);  // the 99.9th percentile of chi2(63)
}

// --- Frames

TEST(Frames, OrthonormalBasisIsRightHandedForEveryNormal) {
  std::vector<glm::vec3> normals = {
      {0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, glm::normalize(glm::vec3(1e-4f, 0, -1))};
  uint state = 99u;
  for (int i = 0; i < 10000; ++i) {
    const float cosTheta = 2.0f * rngUniform(state) - 1.0f, phi = 2.0f * kPi * rngUniform(state);
    const float sinTheta = std::sqrt(1.0f - cosTheta * cosTheta);
    normals.push_back(glm::vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta));
  }
  for (const glm::vec3& n : normals) {
    vec3 t, b;
    buildOrthonormalBasis(n, t, b);
    EXPECT_NEAR(glm::length(t), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::length(b), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(t, b), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(t, n), 0.0f, 1e-5f);
    EXPECT_LT(glm::length(glm::cross(t, b) - n), 1e-5f) << n.x << " " << n.y << " " << n.z;
  }
}

// --- Hemisphere samplers

TEST(Hemisphere, CosineAndUniformSamplersMatchTheirPdfs) {
  ChiSquareFamily family("cosine/uniform hemisphere");
  DirectionGrid grid;
  grid.thetaEdges = cellEdges(0.0, 0.5 * std::numbers::pi, 20, 0.0, 0.0);
  grid.phiEdges = cellEdges(0.0, 2.0 * std::numbers::pi, 40, 0.0, 0.0);
  const Sampler cosine = [](glm::vec3 u, glm::vec3& d) {
    d = sampleCosineHemisphere(vec2(u.x, u.y));
    return true;
  };
  const Sampler uniform = [](glm::vec3 u, glm::vec3& d) {
    d = sampleUniformHemisphere(vec2(u.x, u.y));
    return true;
  };
  family.check(chiSquareTest(
                   grid, cosine, [](glm::vec3 d) { return pdfCosineHemisphere(d.z); }, 400000, 1u),
               "cosine");
  family.check(chiSquareTest(
                   grid, uniform, [](glm::vec3) { return pdfUniformHemisphere(); }, 400000, 2u),
               "uniform");
  EXPECT_NEAR(integrate(grid, [](glm::vec3 d) { return pdfCosineHemisphere(d.z); }), 1.0, 1e-6);
  EXPECT_NEAR(integrate(grid, [](glm::vec3) { return pdfUniformHemisphere(); }), 1.0, 1e-6);
  // Unit length and upper hemisphere, corners of the square included.
  for (glm::vec2 u : {glm::vec2(0, 0), glm::vec2(0.99999994f, 0.99999994f), glm::vec2(0.5f, 0.5f), glm::vec2(0, 1)}) {
    EXPECT_NEAR(glm::length(sampleCosineHemisphere(u)), 1.0f, 1e-6f);
    EXPECT_GE(sampleCosineHemisphere(u).z, 0.0f);
    EXPECT_NEAR(glm::length(sampleUniformHemisphere(u)), 1.0f, 1e-6f);
  }
}

// --- GGX visible normals and their reflections

TEST(GgxVisibleNormals, NormalsMatchTheVisibleNormalDistribution) {
  ChiSquareFamily family("GGX visible normals");
  for (float roughness : kRoughnesses)
    for (float cosThetaV : kViewCosines) {
      const float alpha = ggxAlpha(roughness);
      const glm::vec3 n(0, 0, 1), v = viewAt(cosThetaV);
      const DirectionGrid grid = hemisphereGrid(n, v, 0.0, alpha, 0.0);
      const Sampler sampler = [&](glm::vec3 u, glm::vec3& m) {
        m = sampleGgxVisibleNormal(v, alpha, vec2(u.x, u.y));
        return true;
      };
      const Pdf pdf = [&](glm::vec3 m) { return pdfGgxVisibleNormal(v, m, alpha); };
      // D_v is a distribution over the hemisphere whatever the view: this
      // checks G1 against D (a G1 of the wrong Smith model would miss 1).
      EXPECT_NEAR(integrate(grid, pdf), 1.0, 1e-4) << label(roughness, cosThetaV);
      family.check(chiSquareTest(grid, sampler, pdf, 300000, 10u), label(roughness, cosThetaV));
    }
}

TEST(GgxVisibleNormals, ReflectionsMatchPdfGgxReflection) {
  ChiSquareFamily family("GGX VNDF reflections");
  for (float roughness : kRoughnesses)
    for (float cosThetaV : kViewCosines) {
      const float alpha = ggxAlpha(roughness);
      const glm::vec3 n(0, 0, 1), v = viewAt(cosThetaV);
      const DirectionGrid grid = reflectionGrid(n, v, alpha);
      const Sampler sampler = [&](glm::vec3 u, glm::vec3& l) {
        l = reflect(-v, sampleGgxVisibleNormal(v, alpha, vec2(u.x, u.y)));
        return l.z > 0.0f;
      };
      const Pdf pdf = [&](glm::vec3 l) { return pdfGgxReflection(v, l, alpha); };
      const ChiSquareOutcome outcome = chiSquareTest(grid, sampler, pdf, 300000, 20u);
      family.check(outcome, label(roughness, cosThetaV));
      // The pdf's mass over the hemisphere is the share of valid samples.
      const double validMass = integrate(grid, pdf);
      EXPECT_LE(validMass, 1.0 + 1e-4);
      EXPECT_NEAR(validMass, 1.0 - outcome.invalidShare, 5.0 * std::sqrt(0.25 / 300000) + 1e-4)
          << label(roughness, cosThetaV);
      // At normal incidence, l = reflect(-n, m) stays up iff theta_m < 45
      // degrees, which has GGX probability 1 / (1 + alpha^2).
      if (cosThetaV == 1.0f) {
        EXPECT_NEAR(validMass, 1.0 / (1.0 + double(alpha) * alpha), 1e-4) << label(roughness, cosThetaV);
      }
    }
}

// The relative error of ggxD (which ggxSpecularCosine uses) against the exact
// ggxDSinCos (which the pdfs use): float rounding of 1 - nDotH^2, largest at
// the peak of the smoothest lobe with world-space dot products: a few ulp of
// 1, up to ~5e-7, against alpha^2 = 6.25e-6 moves D by up to ~16 %.
// Tolerances on f cos / pdf allow for it (the tests print what they meet).
float ggxDRoundingTolerance(float alpha) { return alpha < 0.04f ? 0.25f : 1e-3f; }

// the Jitter gi pass's specular estimator: f cos / pdf of a VNDF reflection is F G2 / G1.
TEST(GgxVisibleNormals, ReflectionWeightIsBrdfCosineOverPdf) {
  uint state = 5u;
  const glm::vec3 n(0, 0, 1);
  float worstSmooth = 0.0f, worstRough = 0.0f;
  for (int i = 0; i < 20000; ++i) {
    const float alpha = ggxAlpha(0.05f + 0.95f * rngUniform(state));
    const glm::vec3 v = viewAt(0.02f + 0.98f * rngUniform(state));
    const glm::vec3 f0(0.04f + 0.96f * rngUniform(state));
    const glm::vec3 m = sampleGgxVisibleNormal(v, alpha, vec2(rngUniform(state), rngUniform(state)));
    const glm::vec3 l = reflect(-v, m);
    if (l.z <= 1e-3f) continue;
    const glm::vec3 h = glm::normalize(v + l);
    const glm::vec3 weight = ggxReflectionWeight(f0, glm::dot(v, h), l.z, v.z, alpha);
    const float expected = ggxSpecularCosine(n, v, l, f0, alpha).x / pdfGgxReflection(v, l, alpha);
    const float relativeError = std::abs(weight.x - expected) / expected;
    ASSERT_LE(relativeError, ggxDRoundingTolerance(alpha)) << i << " alpha " << alpha;
    ASSERT_LE(weight.x, 1.0f + 1e-6f);
    (alpha < 0.04f ? worstSmooth : worstRough) = std::max(alpha < 0.04f ? worstSmooth : worstRough, relativeError);
  }
  std::printf("[weight] F G2 / G1 against f cos / pdf: worst relative error %.2g (alpha < 0.04), %.2g (rougher)\n",
              worstSmooth, worstRough);
}

// --- The whole material

TEST(Material, SampleMaterialMatchesPdfMaterial) {
  ChiSquareFamily family("sampleMaterial");
  for (const TestMaterial& material : kMaterials)
    for (float roughness : kRoughnesses)
      for (float cosThetaV : kViewCosines) {
        const float alpha = ggxAlpha(roughness);
        const glm::vec3 n = kTiltedNormal, v = viewAt(cosThetaV, n);
        const DirectionGrid grid = reflectionGrid(n, v, alpha);
        const Sampler sampler = [&](glm::vec3 u, glm::vec3& l) {
          float pdf;
          if (!sampleMaterial(n, v, material.baseColor, material.metallic, roughness, u, l, pdf)) return false;
          // The combined pdf it returns is pdfMaterial's, bit for bit.
          EXPECT_EQ(pdf, pdfMaterial(n, v, l, material.baseColor, material.metallic, roughness));
          return true;
        };
        const Pdf pdf = [&](glm::vec3 l) {
          return pdfMaterial(n, v, l, material.baseColor, material.metallic, roughness);
        };
        const ChiSquareOutcome outcome = chiSquareTest(grid, sampler, pdf, 250000, 30u);
        family.check(outcome, std::string(material.name) + " " + label(roughness, cosThetaV));
        // Mass: the diffuse lobe's (1 - p_s), all valid, plus p_s times the
        // valid share of the specular lobe, which the sampler measures.
        const double specularProbability =
            specularSelectionProbability(material.baseColor, material.metallic, cosThetaV);
        const double mass = integrate(grid, pdf);
        EXPECT_GE(mass, 1.0 - specularProbability - 1e-4);
        EXPECT_LE(mass, 1.0 + 1e-4);
        EXPECT_NEAR(mass, 1.0 - outcome.invalidShare, 5.0 * std::sqrt(0.25 / 250000) + 1e-4);
      }
}

TEST(Material, LobeSelectionFollowsEnergyWithinItsClamp) {
  // No diffuse lobe (metal, black dielectric): always specular.
  EXPECT_EQ(specularSelectionProbability(glm::vec3(0.9f), 1.0f, 0.5f), 1.0f);
  EXPECT_EQ(specularSelectionProbability(glm::vec3(0.0f), 0.0f, 0.5f), 1.0f);
  EXPECT_EQ(specularSelectionProbability(glm::vec3(0.0f), 1.0f, 1.0f), 1.0f);
  // White dielectric at normal incidence: F = 0.04 against albedo 1, clamped up.
  EXPECT_FLOAT_EQ(specularSelectionProbability(glm::vec3(1.0f), 0.0f, 1.0f), kMinLobeProbability);
  // Grazing: Fresnel grows, so does the specular share.
  const float normal = specularSelectionProbability(glm::vec3(0.2f), 0.0f, 1.0f);
  const float grazing = specularSelectionProbability(glm::vec3(0.2f), 0.0f, 0.05f);
  EXPECT_GT(grazing, normal);
  EXPECT_LE(grazing, 1.0f - kMinLobeProbability);
  // In between, the energy ratio itself.
  const glm::vec3 base(0.5f);
  const float f = luminance(fresnelSchlick(specularF0(base, 0.5f), 0.8f));
  EXPECT_NEAR(specularSelectionProbability(base, 0.5f, 0.8f), f / (f + 0.25f), 1e-6f);
}

// The importance-sampled albedo of a material: the mean of f cos / pdf.
double sampledAlbedo(glm::vec3 n, glm::vec3 v, glm::vec3 baseColor, float metallic, float roughness, int count,
                     uint seed, double* standardError) {
  uint state = seed;
  double sum = 0.0, sumSquares = 0.0;
  for (int i = 0; i < count; ++i) {
    const glm::vec3 u(rngUniform(state), rngUniform(state), rngUniform(state));
    glm::vec3 l;
    float pdf;
    if (!sampleMaterial(n, v, baseColor, metallic, roughness, u, l, pdf)) continue;
    const double weight = materialBrdfCosine(n, v, l, baseColor, metallic, roughness).x / pdf;
    sum += weight;
    sumSquares += weight * weight;
  }
  const double mean = sum / count;
  *standardError = std::sqrt(std::max(0.0, sumSquares / count - mean * mean) / count);
  return mean;
}

// White furnace: a metal of F0 = 1 under uniform unit radiance returns its
// directional albedo, at most 1 (single-scattering GGX loses the energy of
// multiple bounces, more when rough and grazing). The importance-sampled
// estimate must agree with quadrature of materialBrdfCosine on the grid.
TEST(Material, WhiteFurnaceSampledMatchesQuadratureAndStaysBelowOne) {
  const glm::vec3 n = kTiltedNormal;
  std::printf("[furnace] metal F0 = 1: roughness cos(theta_v): quadrature  sampled +- 1 sigma\n");
  for (float roughness : kRoughnesses)
    for (float cosThetaV : kViewCosines) {
      const glm::vec3 v = viewAt(cosThetaV, n);
      const DirectionGrid grid = reflectionGrid(n, v, ggxAlpha(roughness));
      const double quadrature =
          integrate(grid, [&](glm::vec3 l) { return materialBrdfCosine(n, v, l, glm::vec3(1.0f), 1.0f, roughness).x; });
      double error;
      const double sampled = sampledAlbedo(n, v, glm::vec3(1.0f), 1.0f, roughness, 100000, 40u, &error);
      std::printf("[furnace]   %.2f %.2f: %.4f  %.4f +- %.4f\n", roughness, cosThetaV, quadrature, sampled, error);
      EXPECT_LE(quadrature, 1.0 + 1e-4) << label(roughness, cosThetaV);
      EXPECT_LE(sampled, 1.0 + 1e-6) << label(roughness, cosThetaV);  // every weight F G2 / G1 is <= 1
      EXPECT_NEAR(sampled, quadrature, 1e-2) << label(roughness, cosThetaV);
      EXPECT_LT(error, 2e-3);
    }
  // A smooth metal keeps nearly everything at normal incidence.
  double error;
  EXPECT_GT(sampledAlbedo(n, viewAt(1.0f, n), glm::vec3(1.0f), 1.0f, 0.1f, 100000, 41u, &error), 0.99);
}

// specularReflectance() is an analytic fit of the specular lobe's
// directional albedo, which demodulates indirect specular. It only has to be
// close (the same function demodulates and remodulates, so its error cancels
// in the composite), but its error is measured here against quadrature and
// bounded: within 0.07 for dielectrics (F0 = 0.04) and 0.25 for smooth
// metals; rough metals (r >= 0.75) and grazing views are off by up to 0.4
// (docs/known-issues.md).
TEST(Material, SpecularReflectanceFitFollowsTheLobesAlbedo) {
  const glm::vec3 n = kTiltedNormal;
  double worst = 0.0, worstDielectric = 0.0, worstSmooth = 0.0;
  for (float f0 : {0.04f, 0.5f, 1.0f})
    for (float roughness : kRoughnesses)
      for (float cosThetaV : kViewCosines) {
        const glm::vec3 v = viewAt(cosThetaV, n);
        const DirectionGrid grid = reflectionGrid(n, v, ggxAlpha(roughness));
        const double albedo = integrate(
            grid, [&](glm::vec3 l) { return ggxSpecularCosine(n, v, l, glm::vec3(f0), ggxAlpha(roughness)).x; });
        const double fit = specularReflectance(glm::vec3(f0), cosThetaV, roughness).x;
        std::printf("[reflectance] F0 %.2f r %.2f cos %.2f: albedo %.4f fit %.4f\n", f0, roughness, cosThetaV, albedo,
                    fit);
        const double error = std::abs(fit - albedo);
        worst = std::max(worst, error);
        if (f0 < 0.1f) worstDielectric = std::max(worstDielectric, error);
        if (roughness <= 0.5f && cosThetaV >= 0.3f) worstSmooth = std::max(worstSmooth, error);
        EXPECT_GE(fit, kMinSpecularReflectance);
      }
  std::printf("[reflectance] largest absolute error of the fit: %.4f (dielectrics %.4f, r <= 0.5 off grazing %.4f)\n",
              worst, worstDielectric, worstSmooth);
  EXPECT_LT(worstDielectric, 0.07);
  EXPECT_LT(worstSmooth, 0.25);
  EXPECT_LT(worst, 0.42);
}

// Both lobes together, for materials with a diffuse part: unbiased (agrees
// with quadrature). A white dielectric reflects more than it receives at
// grazing angles: the model's Lambert lobe has no (1 - F) factor (see
// docs/material-model.md); the numbers are printed for the docs.
TEST(Material, SampledAlbedoOfBothLobesMatchesQuadrature) {
  const glm::vec3 n = kTiltedNormal;
  for (const TestMaterial& material :
       {kMaterials[0], kMaterials[1], TestMaterial{glm::vec3(1.0f), 0.0f, "white dielectric"}})
    for (float roughness : {0.05f, 0.5f, 1.0f})
      for (float cosThetaV : {1.0f, 0.3f, 0.05f}) {
        const glm::vec3 v = viewAt(cosThetaV, n);
        const DirectionGrid grid = reflectionGrid(n, v, ggxAlpha(roughness));
        const double quadrature = integrate(grid, [&](glm::vec3 l) {
          return materialBrdfCosine(n, v, l, material.baseColor, material.metallic, roughness).x;
        });
        double error;
        const double sampled =
            sampledAlbedo(n, v, material.baseColor, material.metallic, roughness, 100000, 50u, &error);
        std::printf("[furnace] %s %.2f %.2f: quadrature %.4f sampled %.4f +- %.4f\n", material.name, roughness,
                    cosThetaV, quadrature, sampled, error);
        EXPECT_NEAR(sampled, quadrature, std::max(1e-2, 5.0 * error)) << material.name << label(roughness, cosThetaV);
      }
}

// The estimator f cos / pdf of every valid sample is finite and bounded: at
// most F G2 / G1 / p_s <= 1 / p_s for the specular lobe plus (1 - metallic)
// baseColor / (1 - p_s) for the diffuse one, which the lobe clamp keeps <= 20.
TEST(Material, EstimatorIsFiniteAndBounded) {
  uint state = 61u;
  int valid = 0;
  float worstSmooth = 0.0f, worstRough = 0.0f;  // largest weight / bound - 1
  for (int i = 0; i < 200000; ++i) {
    const glm::vec3 baseColor(rngUniform(state), rngUniform(state), rngUniform(state));
    const float metallic = rngUniform(state) < 0.2f ? 1.0f : rngUniform(state);
    const float roughness = rngUniform(state) < 0.1f ? 0.0f : rngUniform(state);
    const glm::vec3 n = viewAt(2.0f * rngUniform(state) - 1.0f);
    const glm::vec3 v = viewAt(rngUniform(state) * rngUniform(state), n);
    const glm::vec3 u(rngUniform(state), rngUniform(state), rngUniform(state));
    glm::vec3 l;
    float pdf;
    if (!sampleMaterial(n, v, baseColor, metallic, roughness, u, l, pdf)) {
      ASSERT_EQ(pdf, 0.0f);
      continue;
    }
    ++valid;
    const float specularProbability = specularSelectionProbability(baseColor, metallic, glm::dot(n, v));
    const glm::vec3 weight = materialBrdfCosine(n, v, l, baseColor, metallic, roughness) / pdf;
    const glm::vec3 bound =
        glm::vec3(1.0f / specularProbability) +
        (specularProbability < 1.0f ? baseColor * (1.0f - metallic) / (1.0f - specularProbability) : glm::vec3(0.0f));
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(weight[c])) << i;
      ASSERT_GE(weight[c], 0.0f) << i;
      ASSERT_LE(weight[c], bound[c] * (1.0f + ggxDRoundingTolerance(ggxAlpha(roughness)))) << i;
      ASSERT_LE(weight[c], 20.0f) << i;
      float& worst = ggxAlpha(roughness) < 0.04f ? worstSmooth : worstRough;
      worst = std::max(worst, weight[c] / bound[c] - 1.0f);
    }
  }
  EXPECT_GT(valid, 150000);
  std::printf("[weight] f cos / pdf over its bound: at most 1 + %.2g (alpha < 0.04), 1 + %.2g (rougher)\n", worstSmooth,
              worstRough);
}

// f(v, l) = f(l, v): materialBrdfCosine / cos(theta_l) is symmetric, for
// both diffuse models.
TEST(Material, BrdfIsReciprocal) {
  uint state = 71u;
  const glm::vec3 n = kTiltedNormal;
  for (int i = 0; i < 20000; ++i) {
    const glm::vec3 a = viewAt(0.01f + 0.99f * rngUniform(state), n);
    const glm::vec3 b = glm::normalize(glm::reflect(-viewAt(0.01f + 0.99f * rngUniform(state), n), n) +
                                       0.3f * glm::vec3(rngUniform(state), rngUniform(state), rngUniform(state)));
    if (glm::dot(n, b) <= 0.01f) continue;
    const glm::vec3 baseColor(rngUniform(state), rngUniform(state), rngUniform(state));
    const float metallic = rngUniform(state), roughness = rngUniform(state);
    for (int model : {kDiffuseLambert, kDiffuseBurley}) {
      const glm::vec3 ab = materialBrdfCosineWithDiffuse(n, a, b, baseColor, metallic, roughness, model);
      const glm::vec3 ba = materialBrdfCosineWithDiffuse(n, b, a, baseColor, metallic, roughness, model);
      const float fab = ab.y / glm::dot(n, b), fba = ba.y / glm::dot(n, a);
      ASSERT_NEAR(fab, fba, 1e-3f * std::max(1.0f, fab)) << i << " model " << model;
    }
  }
}

TEST(Material, DiffuseModelsLambertIsTheDefaultAndBurleyBehaves) {
  uint state = 81u;
  const glm::vec3 n = kTiltedNormal;
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 v = viewAt(rngUniform(state), n), l = viewAt(rngUniform(state), n);
    const glm::vec3 base(rngUniform(state), rngUniform(state), rngUniform(state));
    const float metallic = rngUniform(state), roughness = rngUniform(state);
    ASSERT_EQ(materialBrdfCosineWithDiffuse(n, v, l, base, metallic, roughness, kDiffuseLambert),
              materialBrdfCosine(n, v, l, base, metallic, roughness));
  }
  // Burley equals Lambert where light and view are the normal...
  EXPECT_FLOAT_EQ(burleyDiffuseFactor(1.0f, 1.0f, 1.0f, 0.7f), 1.0f);
  // ...darkens smooth surfaces at grazing angles (F_D90 = 0.5)...
  EXPECT_NEAR(burleyDiffuseFactor(0.0f, 1.0f, 0.7f, 0.0f), 0.5f, 1e-6f);
  // ...and brightens rough ones towards grazing retro-reflection (F_D90 = 2.5).
  EXPECT_NEAR(burleyDiffuseFactor(0.0f, 0.0f, 1.0f, 1.0f), 2.5f * 2.5f, 1e-5f);
  // The material's diffuse part is Lambert times that factor.
  const glm::vec3 v = viewAt(0.3f, n), l = glm::normalize(2.0f * n - v);
  const glm::vec3 h = glm::normalize(v + l);
  const float factor = burleyDiffuseFactor(glm::dot(n, l), glm::dot(n, v), glm::dot(l, h), 0.6f);
  const glm::vec3 base(0.5f);
  const glm::vec3 lambert = materialBrdfCosine(n, v, l, base, 0.0f, 0.6f);
  const glm::vec3 burley = materialBrdfCosineWithDiffuse(n, v, l, base, 0.0f, 0.6f, kDiffuseBurley);
  const glm::vec3 specular = ggxSpecularCosine(n, v, l, glm::vec3(0.04f), ggxAlpha(0.6f));
  EXPECT_NEAR(burley.x - specular.x, (lambert.x - specular.x) * factor, 1e-6f);
}

// Every function over the edges of its valid inputs: roughness 0, views at
// and below the horizon, v == n, v == -n, u at the corners of the square.
TEST(Material, NoNanOrInfAtTheEdges) {
  const glm::vec3 n = kTiltedNormal;
  vec3 t, b;
  buildOrthonormalBasis(n, t, b);
  std::vector<glm::vec3> views = {
      n, -n, t, glm::normalize(n * 1e-7f + t), glm::normalize(n * 1e-3f + b), glm::normalize(-n * 1e-6f + t)};
  for (float c : kViewCosines) views.push_back(viewAt(c, n));
  const std::vector<glm::vec3> corners = {
      {0, 0, 0}, {0.99999994f, 0.99999994f, 0.99999994f}, {0, 0.99999994f, 0.5f}, {0.5f, 0.0f, 0.05f}};
  for (float roughness : {0.0f, 1e-4f, 0.05f, 1.0f})
    for (float metallic : {0.0f, 1.0f})
      for (glm::vec3 baseColor : {glm::vec3(0.0f), glm::vec3(1.0f)})
        for (const glm::vec3& v : views) {
          uint state = 91u;
          std::vector<glm::vec3> us = corners;
          for (int i = 0; i < 200; ++i)
            us.push_back(glm::vec3(rngUniform(state), rngUniform(state), rngUniform(state)));
          for (const glm::vec3& u : us) {
            glm::vec3 l;
            float pdf;
            const bool ok = sampleMaterial(n, v, baseColor, metallic, roughness, u, l, pdf);
            ASSERT_TRUE(std::isfinite(pdf));
            ASSERT_TRUE(std::isfinite(l.x) && std::isfinite(l.y) && std::isfinite(l.z));
            if (!ok) {
              ASSERT_EQ(pdf, 0.0f);
              continue;
            }
            ASSERT_GT(glm::dot(n, v), 0.0f);
            ASSERT_GT(glm::dot(n, l), 0.0f);
            ASSERT_NEAR(glm::length(l), 1.0f, 1e-5f);
            const glm::vec3 f = materialBrdfCosine(n, v, l, baseColor, metallic, roughness);
            ASSERT_TRUE(std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z));
            ASSERT_TRUE(std::isfinite(f.x / pdf)) << roughness;
            ASSERT_LE(f.x / pdf, 20.0f);
          }
          for (const glm::vec3& l : views) {
            const float pdf = pdfMaterial(n, v, l, baseColor, metallic, roughness);
            ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0.0f);
            const glm::vec3 f = materialBrdfCosineWithDiffuse(n, v, l, baseColor, metallic, roughness, kDiffuseBurley);
            ASSERT_TRUE(std::isfinite(f.x) && f.x >= 0.0f);
          }
        }
  // The local-frame functions at v == n, grazing v, smallest alpha.
  for (glm::vec3 v : {glm::vec3(0, 0, 1), glm::normalize(glm::vec3(1, 0, 1e-6f)), glm::vec3(0, 0.6f, 0.8f)})
    for (float alpha : {kMinGgxAlpha, 1.0f})
      for (const glm::vec3& u : corners) {
        const glm::vec3 m = sampleGgxVisibleNormal(v, alpha, vec2(u.x, u.y));
        ASSERT_NEAR(glm::length(m), 1.0f, 1e-5f);
        ASSERT_GE(m.z, 0.0f);
        ASSERT_TRUE(std::isfinite(pdfGgxVisibleNormal(v, m, alpha)));
        ASSERT_TRUE(std::isfinite(pdfGgxReflection(v, reflect(-v, m), alpha)));
        ASSERT_TRUE(std::isfinite(smithG1OverCos(v.z, alpha)));
      }
  EXPECT_NEAR(smithG1OverCos(0.0f, 0.5f), 2.0f / 0.5f, 1e-5f);  // the grazing limit 2 / alpha
}

// --- Uniform sampling of the specular lobe

TEST(SpecularLobe, UniformConeSamplerMatchesItsPdf) {
  ChiSquareFamily family("uniform specular lobe");
  const glm::vec3 n = kTiltedNormal;
  for (float roughness : kRoughnesses)
    for (float cosThetaV : kLobeAxisViewCosines) {
      const float alpha = ggxAlpha(roughness);
      const glm::vec3 axis = ggxDominantDirection(n, viewAt(cosThetaV, n), alpha);
      const float halfAngle = specularLobeHalfAngle(alpha, 0.75f);
      // A sphere grid around the axis with the cone's edge on a cell edge.
      DirectionGrid grid;
      grid.axisZ = glm::dvec3(axis);
      vec3 t, b;
      buildOrthonormalBasis(axis, t, b);
      grid.axisX = glm::dvec3(t);
      grid.axisY = glm::dvec3(b);
      grid.thetaEdges = cellEdges(0.0, halfAngle, 12, 0.0, 0.0);
      for (int i = 1; i <= 8; ++i) grid.thetaEdges.push_back(halfAngle + (std::numbers::pi - halfAngle) * i / 8.0);
      grid.phiEdges = cellEdges(0.0, 2.0 * std::numbers::pi, 24, 0.0, 0.0);
      const Sampler sampler = [&](glm::vec3 u, glm::vec3& d) {
        d = sampleSpecularLobeUniform(axis, halfAngle, vec2(u.x, u.y));
        EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
        return true;
      };
      const Pdf pdf = [&](glm::vec3 d) {
        return isInSpecularLobe(axis, halfAngle, d) ? pdfSpecularLobeUniform(halfAngle) : 0.0;
      };
      EXPECT_NEAR(integrate(grid, pdf), 1.0, 1e-4) << label(roughness, cosThetaV);
      family.check(chiSquareTest(grid, sampler, pdf, 200000, 60u), label(roughness, cosThetaV));
    }
}

TEST(SpecularLobe, ConeHoldsTheRequestedShareOfReflectionsAtNormalIncidence) {
  const glm::vec3 n(0, 0, 1);
  constexpr int kCount = 100000;
  for (float roughness : {0.05f, 0.25f, 0.5f, 0.7f})
    for (float fraction : {0.5f, 0.75f, 0.9f}) {
      const float alpha = ggxAlpha(roughness);
      const float halfAngle = specularLobeHalfAngle(alpha, fraction);
      if (halfAngle >= 0.5f * kPi) continue;  // capped at a hemisphere
      uint state = 70u;
      int inside = 0;
      for (int i = 0; i < kCount; ++i) {
        const glm::vec3 l = reflect(-n, sampleGgxVisibleNormal(n, alpha, vec2(rngUniform(state), rngUniform(state))));
        inside += isInSpecularLobe(n, halfAngle, l) ? 1 : 0;
      }
      EXPECT_NEAR(double(inside) / kCount, fraction, 5.0 * std::sqrt(fraction * (1.0 - fraction) / kCount))
          << roughness << " " << fraction;
    }
  EXPECT_FLOAT_EQ(specularLobeHalfAngle(1.0f, 0.75f), 0.5f * kPi);
}

TEST(SpecularLobe, PdfIsViewIndependentAndMembershipIsSharp) {
  const float alpha = kMinGgxAlpha;
  const float halfAngle = specularLobeHalfAngle(alpha, 0.75f);
  // Two views give two axes but one pdf value: the cone depends on roughness only.
  const glm::vec3 n = kTiltedNormal;
  const glm::vec3 axisA = ggxDominantDirection(n, viewAt(0.9f, n), alpha);
  const glm::vec3 axisB = ggxDominantDirection(n, viewAt(0.2f, n), alpha);
  const glm::vec3 sample = sampleSpecularLobeUniform(axisA, halfAngle, vec2(0.3f, 0.8f));
  EXPECT_TRUE(isInSpecularLobe(axisA, halfAngle, sample));
  EXPECT_FALSE(isInSpecularLobe(axisB, halfAngle, sample)) << "a sample from another view's lobe must be rejected";
  EXPECT_NEAR(pdfSpecularLobeUniform(halfAngle), 1.0 / (2.0 * std::numbers::pi * (1.0 - std::cos(double(halfAngle)))),
              1e-3 * pdfSpecularLobeUniform(halfAngle));
  // The narrowest cone (about 0.5 degrees) still separates directions 0.01 %
  // inside and outside its edge (a dot product against cos(halfAngle) cannot:
  // that is 1e-8 in cos, below float's resolution near 1).
  vec3 t, b;
  buildOrthonormalBasis(axisA, t, b);
  for (int k = 0; k < 64; ++k)
    for (double scale : {0.9999, 1.0001}) {
      const double angle = halfAngle * scale, phi = 2.0 * std::numbers::pi * k / 64.0;
      const glm::dvec3 tangent = std::cos(phi) * glm::dvec3(t) + std::sin(phi) * glm::dvec3(b);
      const glm::vec3 d = glm::vec3(std::sin(angle) * tangent + std::cos(angle) * glm::dvec3(axisA));
      EXPECT_EQ(isInSpecularLobe(axisA, halfAngle, d), scale < 1.0) << scale << " " << k;
    }
}

// --- GGX dominant direction

TEST(DominantDirection, MovesFromMirrorToNormalAndTracksTheLobe) {
  EXPECT_FLOAT_EQ(ggxDominantFactor(0.0f), 1.0f);
  EXPECT_FLOAT_EQ(ggxDominantFactor(1.0f), 0.0f);
  for (float alpha = 0.0f; alpha < 1.0f; alpha += 0.01f)
    EXPECT_GT(ggxDominantFactor(alpha), ggxDominantFactor(alpha + 0.01f));
  const glm::vec3 n(0, 0, 1);
  for (float roughness : kRoughnesses)
    for (float cosThetaV : {0.7f, 0.3f, 0.05f}) {
      const float alpha = ggxAlpha(roughness);
      const glm::vec3 v = viewAt(cosThetaV), mirror = reflect(-v, n);
      const glm::vec3 dominant = ggxDominantDirection(n, v, alpha);
      // The direction the BRDF times cos reflects on average (F = 1), from VNDF samples weighted F G2 / G1.
      uint state = 80u;
      glm::dvec3 mean(0.0);
      for (int i = 0; i < 40000; ++i) {
        const glm::vec3 l = reflect(-v, sampleGgxVisibleNormal(v, alpha, vec2(rngUniform(state), rngUniform(state))));
        if (l.z > 0.0f) mean += glm::dvec3(l) * double(ggxReflectionWeight(glm::vec3(1.0f), 1.0f, l.z, v.z, alpha).x);
      }
      const glm::vec3 centroid = glm::normalize(glm::vec3(mean));
      const float dominantError = std::acos(std::min(1.0f, glm::dot(dominant, centroid)));
      const float mirrorError = std::acos(std::min(1.0f, glm::dot(mirror, centroid)));
      if (roughness >= 0.5f) {
        // Rough: the lobe leans towards n (off-specular peak), and so does the dominant direction.
        EXPECT_LT(dominantError, 0.8f * mirrorError) << label(roughness, cosThetaV);
      } else {
        // Smooth: it stays well inside the mirror direction's lobe.
        const float offMirror = std::acos(std::min(1.0f, glm::dot(dominant, mirror)));
        EXPECT_LT(offMirror, 0.5f * specularLobeHalfAngle(alpha, 0.5f)) << label(roughness, cosThetaV);
      }
    }
}

// --- Sample sequences

TEST(Sequences, RadicalInversesAreExact) {
  EXPECT_EQ(radicalInverseBase2(0u), 0.0f);
  EXPECT_EQ(radicalInverseBase2(1u), 0.5f);
  EXPECT_EQ(radicalInverseBase2(6u), 0.375f);
  EXPECT_NEAR(radicalInverseBase3(1u), 1.0f / 3.0f, 1e-7f);
  EXPECT_NEAR(radicalInverseBase3(5u), 2.0f / 3.0f + 1.0f / 9.0f, 1e-7f);  // 5 = 12 in base 3
  EXPECT_LT(radicalInverseBase2(0xffffffffu), 1.0f);
  EXPECT_LT(radicalInverseBase3(0xffffffffu), 1.0f);
}

// The RMS error, over many pixels, of estimating the area of a disk from 64
// points: a measure of 2-D uniformity that white noise does poorly on.
double diskAreaRmsError(const std::function<glm::vec2(int pixel, int index)>& point) {
  constexpr int kPixels = 512;
  const double area = std::numbers::pi * 0.4 * 0.4;
  double sumSquares = 0.0;
  for (int pixel = 0; pixel < kPixels; ++pixel) {
    int inside = 0;
    for (int i = 0; i < 64; ++i) {
      const glm::vec2 p = point(pixel, i) - glm::vec2(0.5f);
      inside += glm::dot(p, p) < 0.16f ? 1 : 0;
    }
    sumSquares += (inside / 64.0 - area) * (inside / 64.0 - area);
  }
  return std::sqrt(sumSquares / kPixels);
}

// The gaps between sorted coordinates, on the circle (so a shift keeps them).
std::vector<float> circularGaps(std::vector<float> values) {
  std::sort(values.begin(), values.end());
  std::vector<float> gaps;
  for (size_t i = 0; i < values.size(); ++i)
    gaps.push_back(i + 1 < values.size() ? values[i + 1] - values[i] : values[0] + 1.0f - values[i]);
  return gaps;
}

TEST(Sequences, HaltonCycleIsStratifiedOffsetAndRotatedPerPixel) {
  std::set<std::pair<float, float>> firstFrame, firstSteps;
  for (uint x = 0; x < 16; ++x)
    for (uint y = 0; y < 16; ++y) {
      const uint seed = rngSeed(uvec2(x, y), 0u, 3u);
      std::vector<float> xs, ys;
      for (uint i = 0; i < kHaltonCycleLength; ++i) {
        const glm::vec2 p = haltonPixelSample(i, seed);
        ASSERT_GE(p.x, 0.0f);
        ASSERT_LT(p.x, 1.0f);
        ASSERT_GE(p.y, 0.0f);
        ASSERT_LT(p.y, 1.0f);
        ASSERT_EQ(p, haltonPixelSample(i + kHaltonCycleLength, seed)) << "the cycle repeats";
        xs.push_back(p.x);
        ys.push_back(p.y);
      }
      // Base 2: the 64 x values are 64 equal strata, shifted; base 3: every
      // multiple of 1/27 is among them, so no gap exceeds 1/27.
      for (float gap : circularGaps(xs)) ASSERT_NEAR(gap, 1.0f / 64.0f, 1e-5f);
      for (float gap : circularGaps(ys)) ASSERT_LE(gap, 1.0f / 27.0f + 1e-5f);
      firstFrame.insert({haltonPixelSample(0u, seed).x, haltonPixelSample(0u, seed).y});
      // The step from frame 0 to 1 does not depend on the rotation, only on
      // where in the cycle the pixel is: it shows the start offset.
      const glm::vec2 step = glm::fract(haltonPixelSample(1u, seed) - haltonPixelSample(0u, seed) + glm::vec2(1.0f));
      firstSteps.insert({std::round(step.x * 1e4f), std::round(step.y * 1e4f)});
    }
  EXPECT_EQ(firstFrame.size(), 256u) << "neighbours must not share a point in the same frame";
  // The 64-point cycle has 17 distinct steps to a successor; without start
  // offsets every pixel would take the same one.
  EXPECT_GE(firstSteps.size(), 12u) << "pixels must start at different points of the cycle";

  const double halton = diskAreaRmsError(
      [](int pixel, int i) { return haltonPixelSample(uint(i), rngSeed(uvec2(uint(pixel), 0u), 0u, 3u)); });
  const double whiteNoise = diskAreaRmsError([](int pixel, int i) {
    uint state = rngSeed(uvec2(uint(pixel), uint(i)), 1u, 3u);
    return glm::vec2(rngUniform(state), rngUniform(state));
  });
  std::printf("[sequences] disk-area RMS error of 64 points: Halton %.4f, R2 see below, white noise %.4f\n", halton,
              whiteNoise);
  EXPECT_LT(halton, 0.4 * whiteNoise);
}

TEST(Sequences, R2IsExactLowDiscrepancyAndFarApartBetweenNeighbours) {
  EXPECT_EQ(r2Point(0u), glm::vec2(0.5f, 0.5f));
  // The fixed-point steps are 1/g and 1/g^2 to 2^-33, so index n is off the
  // ideal sequence by at most n 2^-33 (plus the 2^-24 of the final float):
  // within 1e-4 for a million frames, where float arithmetic is long gone.
  for (uint index : {1u, 1000u, 1000000u}) {
    const long double g = 1.32471795724474602596L;
    const long double x = std::fmod(0.5L + index / g, 1.0L), y = std::fmod(0.5L + index / (g * g), 1.0L);
    const double tolerance = index * 0x1p-33 + 0x1p-24;
    EXPECT_NEAR(r2Point(index).x, double(x), tolerance) << index;
    EXPECT_NEAR(r2Point(index).y, double(y), tolerance) << index;
  }
  EXPECT_NE(r2Point(4000000000u), r2Point(4000000001u)) << "still moving after 2^31 frames";
  // Over frames, a pixel's points are as uniform as Halton's.
  const double r2 = diskAreaRmsError([](int pixel, int i) { return r2PixelSample(uvec2(uint(pixel), 7u), uint(i)); });
  std::printf("[sequences] disk-area RMS error of 64 points: R2 %.4f\n", r2);
  EXPECT_LT(r2, 0.025);  // 0.4 x white noise's 0.0625, the Halton test's bar
  // Across pixels, in one frame, any two of a 3 x 3 block are far apart on
  // the torus (9 white-noise points: typically 0.08), and no pixel within 2
  // replays another's sequence up to 8 frames apart.
  const auto torusDistance = [](glm::vec2 a, glm::vec2 b) {
    glm::vec2 d = glm::abs(a - b);
    d = glm::min(d, glm::vec2(1.0f) - d);
    return glm::length(d);
  };
  float closestInBlock = 1.0f, closestEcho = 1.0f;
  const uvec2 here(100u, 200u);
  for (int dx = -2; dx <= 2; ++dx)
    for (int dy = -2; dy <= 2; ++dy) {
      if (dx == 0 && dy == 0) continue;
      // Two pixels of one 3 x 3 block are at most 2 apart in each coordinate.
      const uvec2 there(uint(100 + dx), uint(200 + dy));
      for (uint frame = 0; frame < 8u; ++frame) {
        const glm::vec2 a = r2PixelSample(here, frame);
        closestInBlock = std::min(closestInBlock, torusDistance(a, r2PixelSample(there, frame)));
        for (uint later = 1; later <= 8u; ++later)
          closestEcho = std::min(closestEcho, torusDistance(a, r2PixelSample(there, frame + later)));
      }
    }
  std::printf("[sequences] R2 pixel lattice: closest pair in a 3x3 block %.3f, closest echo %.3f\n", closestInBlock,
              closestEcho);
  EXPECT_GT(closestInBlock, 0.12f);
  EXPECT_GT(closestEcho, 0.02f);
}

}  // namespace
