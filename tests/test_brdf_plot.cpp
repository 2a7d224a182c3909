// The material editor's BRDF plots (viewer/brdf_plot.h), on the CPU: what
// the panels show for known materials, progressive refinement and its
// convergence to the pdf, restarts, determinism; and that the shared plot
// code sits below both of its users (src/plot/ includes neither the app nor
// the viewer; the viewer does not include the app).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/colormap.h"
#include "viewer/brdf_plot.h"

namespace bounce::viewer {
namespace {

using Panel = BrdfPlot::Panel;

// The plots draw magma(t) with t = 1 - exp(-value); a pixel's t is the
// index of the nearest magma entry over 255.
float toneOf(const std::uint8_t* rgb) {
  int best = 0, bestDistance = std::numeric_limits<int>::max();
  for (int k = 0; k < 256; ++k) {
    const std::array<std::uint8_t, 3> entry = io::magma(float(k) / 255.0f);
    int distance = 0;
    for (int c = 0; c < 3; ++c) distance += (int(rgb[c]) - int(entry[c])) * (int(rgb[c]) - int(entry[c]));
    if (distance < bestDistance) best = k, bestDistance = distance;
  }
  return float(best) / 255.0f;
}

// One panel's pixels: tone, and whether the pixel is part of the plot
// (centre inside the disk, clear of the view and mirror marks) with its
// distance from the disk's centre in disk radii.
struct PanelTones {
  int size = 0;
  std::vector<float> tone;
  std::vector<bool> plotted;
  std::vector<float> radius;

  float at(int x, int y) const { return tone[std::size_t(y * size + x)]; }
  bool plottedAt(int x, int y) const { return plotted[std::size_t(y * size + x)]; }
};

PanelTones tonesOf(const BrdfPlot& plot, Panel panel) {
  const BrdfPlot::Rect rect = plot.panelRect(panel);
  PanelTones tones;
  tones.size = rect.width;
  const float half = 0.5f * float(rect.width);
  // The marks: the view 45 degrees from the normal lands sqrt(1 - cos 45) of
  // the radius right of the centre (the equal-area map), its mirror as far left.
  const float markOffset = std::sqrt(1.0f - std::cos(glm::radians(BrdfPlot::kViewDegrees))) * half;
  for (int y = 0; y < rect.height; ++y)
    for (int x = 0; x < rect.width; ++x) {
      const float dx = float(x) + 0.5f - half, dy = float(y) + 0.5f - half;
      const float r = std::sqrt(dx * dx + dy * dy) / half;
      const bool nearMark = std::hypot(std::abs(dx) - markOffset, dy) < 6.0f;
      const std::uint8_t* rgb =
          &plot.rgba()[(std::size_t(rect.y + y) * std::size_t(plot.width()) + std::size_t(rect.x + x)) * 4];
      tones.tone.push_back(toneOf(rgb));
      tones.plotted.push_back(r < 1.0f && !nearMark);
      tones.radius.push_back(r);
    }
  return tones;
}

// Mean |a - b| of the tones of plotted pixels within maxRadius.
float meanToneDifference(const PanelTones& a, const PanelTones& b, float maxRadius = 1.0f) {
  double sum = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < a.tone.size(); ++i)
    if (a.plotted[i] && a.radius[i] < maxRadius) {
      sum += std::abs(a.tone[i] - b.tone[i]);
      ++count;
    }
  return float(sum / count);
}

float meanTone(const PanelTones& tones, float minRadius, float maxRadius) {
  double sum = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < tones.tone.size(); ++i)
    if (tones.plotted[i] && tones.radius[i] >= minRadius && tones.radius[i] < maxRadius) {
      sum += tones.tone[i];
      ++count;
    }
  return float(sum / count);
}

BrdfPlot plotOf(glm::vec3 baseColor, float roughness, float metallic, std::uint32_t samples = 0) {
  BrdfPlot plot;
  plot.setMaterial(baseColor, roughness, metallic);
  plot.refine(samples);
  return plot;
}

TEST(BrdfPlot, ImageHoldsThreeLabelledPanelsSideBySide) {
  const BrdfPlot plot = plotOf(glm::vec3(0.5f), 0.5f, 0.0f);
  ASSERT_EQ(plot.rgba().size(), std::size_t(plot.width()) * std::size_t(plot.height()) * 4);
  int right = 0;
  for (Panel panel : {Panel::BrdfCosine, Panel::Pdf, Panel::Samples}) {
    const BrdfPlot::Rect rect = plot.panelRect(panel);
    EXPECT_EQ(rect.width, BrdfPlot::kDefaultPanelSize);
    EXPECT_EQ(rect.height, BrdfPlot::kDefaultPanelSize);
    EXPECT_GT(rect.x, right) << "panels side by side with a gap";
    EXPECT_LE(rect.x + rect.width, plot.width());
    EXPECT_LE(rect.y + rect.height, plot.height());
    right = rect.x + rect.width;
    // The label strip above the panel has light (label) pixels.
    int ink = 0;
    for (int y = 0; y < rect.y; ++y)
      for (int x = rect.x; x < rect.x + rect.width; ++x)
        ink += plot.rgba()[(std::size_t(y) * std::size_t(plot.width()) + std::size_t(x)) * 4] > 200;
    EXPECT_GT(ink, 20) << "label of panel " << int(panel);
  }
  for (std::size_t i = 3; i < plot.rgba().size(); i += 4) ASSERT_EQ(plot.rgba()[i], 255) << "opaque";
}

TEST(BrdfPlot, RoughWhiteDielectricReflectsMostNearTheNormalAndLittleAtGrazingAngles) {
  const PanelTones fCos = tonesOf(plotOf(glm::vec3(1.0f), 0.8f, 0.0f), Panel::BrdfCosine);
  const float inner = meanTone(fCos, 0.0f, 0.5f), rim = meanTone(fCos, 0.95f, 1.0f);
  EXPECT_GT(inner, 0.15f) << "a white surface reflects visibly";
  EXPECT_GT(inner, 3.0f * rim) << "f cos falls with cos towards the horizon";
}

TEST(BrdfPlot, AnalyticPlotsAreSymmetricAboutThePlaneOfIncidence) {
  const BrdfPlot plot = plotOf(glm::vec3(0.9f, 0.6f, 0.3f), 0.4f, 0.3f);
  for (Panel panel : {Panel::BrdfCosine, Panel::Pdf}) {
    const PanelTones tones = tonesOf(plot, panel);
    const int size = tones.size;
    int pixels = 0;
    for (int y = 0; y < size / 2; ++y)
      for (int x = 0; x < size; ++x)
        if (tones.plottedAt(x, y)) {
          EXPECT_LE(std::abs(tones.at(x, y) - tones.at(x, size - 1 - y)), 1.5f / 255.0f)
              << "panel " << int(panel) << " pixel " << x << "," << y;
          ++pixels;
        }
    EXPECT_GT(pixels, 4000);
  }
}

TEST(BrdfPlot, GlossyLobeLiesOnTheMirrorSide) {
  // The view is on the right of each disk, the mirror direction on the left.
  for (Panel panel : {Panel::BrdfCosine, Panel::Pdf}) {
    const PanelTones tones = tonesOf(plotOf(glm::vec3(0.9f), 0.3f, 1.0f), panel);
    double left = 0.0, right = 0.0;
    for (int y = 0; y < tones.size; ++y)
      for (int x = 0; x < tones.size; ++x)
        if (tones.plottedAt(x, y)) (x < tones.size / 2 ? left : right) += tones.at(x, y);
    EXPECT_GT(left, 3.0 * right) << "panel " << int(panel);
  }
}

// Pixels of the f cos panel at or above half its brightest tone.
int pixelsAboveHalfMaximum(const PanelTones& tones) {
  float maximum = 0.0f;
  for (std::size_t i = 0; i < tones.tone.size(); ++i)
    if (tones.plotted[i]) maximum = std::max(maximum, tones.tone[i]);
  int count = 0;
  for (std::size_t i = 0; i < tones.tone.size(); ++i) count += tones.plotted[i] && tones.tone[i] >= 0.5f * maximum;
  return count;
}

TEST(BrdfPlot, SmootherMaterialConcentratesItsFCosLobe) {
  const int smooth = pixelsAboveHalfMaximum(tonesOf(plotOf(glm::vec3(0.9f), 0.25f, 1.0f), Panel::BrdfCosine));
  const int rough = pixelsAboveHalfMaximum(tonesOf(plotOf(glm::vec3(0.9f), 0.7f, 1.0f), Panel::BrdfCosine));
  EXPECT_GT(smooth, 0);
  EXPECT_LT(2 * smooth, rough) << "smooth " << smooth << " rough " << rough;
}

TEST(BrdfPlot, RefineAccumulatesSamplesAndConverges) {
  BrdfPlot plot;
  plot.setMaterial(glm::vec3(0.5f), 0.5f, 0.0f);
  EXPECT_TRUE(plot.refine(0)) << "the first refine draws the material";
  EXPECT_EQ(plot.samples(), 0u);
  EXPECT_FALSE(plot.refine(0)) << "nothing new to draw";
  // The samples panel at 16k, 32k, 256k and 512k samples: once pixels hold
  // a few samples each, the histogram's noise falls as 1 / sqrt(samples).
  std::vector<PanelTones> at;
  std::uint32_t total = 0;
  for (std::uint32_t target : {1u << 14, 1u << 15, 1u << 18, 1u << 19}) {
    const std::vector<std::uint8_t> before = plot.rgba();
    EXPECT_TRUE(plot.refine(target - total));
    total = target;
    EXPECT_EQ(plot.samples(), total);
    EXPECT_NE(plot.rgba(), before);
    at.push_back(tonesOf(plot, Panel::Samples));
  }
  const float early = meanToneDifference(at[0], at[1]), late = meanToneDifference(at[2], at[3]);
  EXPECT_GT(late, 0.0f);
  EXPECT_LT(2.0f * late, early) << "the histogram's change shrinks as samples accumulate: from 16k to 32k " << early
                                << ", from 256k to 512k " << late;
}

TEST(BrdfPlot, SamplesPanelConvergesToThePdfPanel) {
  // The histogram, scaled to a pdf estimate, approaches the pdf evaluated
  // per pixel: the sampler and its pdf agree (away from the rim, where a
  // pixel lies partly outside the disk). A diffuse-heavy dielectric (which
  // lobe a sample takes matters) and a glossy metal (the lobe's shape does).
  struct Material {
    glm::vec3 baseColor;
    float roughness, metallic;
  };
  for (const Material& material :
       {Material{glm::vec3(0.5f), 0.5f, 0.0f}, Material{glm::vec3(1.0f, 0.78f, 0.34f), 0.4f, 1.0f}}) {
    BrdfPlot plot;
    plot.setMaterial(material.baseColor, material.roughness, material.metallic);
    plot.refine(4096);
    const PanelTones pdf = tonesOf(plot, Panel::Pdf);
    const float few = meanToneDifference(tonesOf(plot, Panel::Samples), pdf, 0.9f);
    plot.refine(BrdfPlot::kMaxSamples - 4096);
    const float many = meanToneDifference(tonesOf(plot, Panel::Samples), pdf, 0.9f);
    EXPECT_LT(many, 0.25f * few) << "metallic " << material.metallic << ": 4k samples " << few;
    EXPECT_LT(many, 0.008f) << "metallic " << material.metallic;
  }
}

TEST(BrdfPlot, ChangingTheMaterialRestarts) {
  BrdfPlot plot;
  plot.setMaterial(glm::vec3(0.5f), 0.5f, 0.0f);
  plot.refine(4096);
  const std::vector<std::uint8_t> refined = plot.rgba();
  plot.setMaterial(glm::vec3(0.5f), 0.5f, 0.0f);
  EXPECT_EQ(plot.samples(), 4096u) << "the same values do not restart";
  EXPECT_FALSE(plot.refine(0));
  plot.setMaterial(glm::vec3(0.5f), 0.2f, 0.0f);
  EXPECT_EQ(plot.samples(), 0u);
  EXPECT_EQ(plot.rgba(), refined) << "the image changes in refine()";
  EXPECT_TRUE(plot.refine(4096));
  EXPECT_EQ(plot.samples(), 4096u);
  EXPECT_EQ(plot.rgba(), plotOf(glm::vec3(0.5f), 0.2f, 0.0f, 4096).rgba())
      << "nothing of the previous material's samples remains";
}

TEST(BrdfPlot, SameInputsMakeTheSameBytes) {
  const auto run = [](glm::vec3 baseColor) {
    BrdfPlot plot;
    plot.setMaterial(baseColor, 0.35f, 0.6f);
    plot.refine(3000);
    plot.refine(5000);
    return plot.rgba();
  };
  EXPECT_EQ(run(glm::vec3(0.8f, 0.4f, 0.2f)), run(glm::vec3(0.8f, 0.4f, 0.2f)));
  EXPECT_NE(run(glm::vec3(0.8f, 0.4f, 0.2f)), run(glm::vec3(0.2f, 0.4f, 0.8f)));
}

TEST(BrdfPlot, StopsRefiningAtTheMostSamples) {
  BrdfPlot plot(32);
  plot.setMaterial(glm::vec3(0.5f), 0.5f, 0.0f);
  plot.refine(BrdfPlot::kMaxSamples - 10);
  EXPECT_EQ(plot.samples(), BrdfPlot::kMaxSamples - 10);
  plot.refine(100);
  EXPECT_EQ(plot.samples(), BrdfPlot::kMaxSamples);
  EXPECT_FALSE(plot.refine(100));
  EXPECT_EQ(plot.samples(), BrdfPlot::kMaxSamples);
}

TEST(BrdfPlot, RefusesValuesOutsideTheUnitRangeByName) {
  BrdfPlot plot;
  plot.setMaterial(glm::vec3(0.5f), 0.5f, 0.0f);
  plot.refine(1000);
  const auto message = [&](glm::vec3 baseColor, float roughness, float metallic) -> std::string {
    try {
      plot.setMaterial(baseColor, roughness, metallic);
    } catch (const std::invalid_argument& error) {
      return error.what();
    }
    return "accepted";
  };
  EXPECT_NE(message(glm::vec3(0.5f), std::nanf(""), 0.0f).find("roughness"), std::string::npos);
  EXPECT_NE(message(glm::vec3(0.5f), 0.5f, 1.5f).find("metallic"), std::string::npos);
  EXPECT_NE(message(glm::vec3(0.5f, -0.1f, 0.5f), 0.5f, 0.0f).find("green"), std::string::npos);
  EXPECT_NE(message(glm::vec3(0.5f, 0.5f, INFINITY), 0.5f, 0.0f).find("blue"), std::string::npos);
  EXPECT_EQ(plot.samples(), 1000u) << "a refused material leaves the plot as it was";
  EXPECT_THROW(BrdfPlot(8), std::invalid_argument);
}

// The plotting code sits below both of its users: neither src/plot/ nor the
// viewer includes the app (the top layer), and src/plot/ needs no Vulkan layer.
TEST(BrdfPlotLayering, SharedPlotsIncludeNothingAboveThem) {
  namespace fs = std::filesystem;
  const fs::path root(BOUNCE_SOURCE_DIR);
  struct Rule {
    const char* dir;
    std::vector<const char*> forbidden;
  };
  const Rule rules[] = {
      {"src/plot", {"\"app/", "\"viewer/", "\"render/", "\"gi/", "\"gpu/", "\"gpuio/", "\"scene/", "<vulkan"}},
      {"src/viewer", {"\"app/"}}};
  int scanned = 0;
  for (const Rule& rule : rules)
    for (const fs::directory_entry& entry : fs::directory_iterator(root / rule.dir)) {
      ++scanned;
      std::ifstream file(entry.path());
      std::string line;
      for (int number = 1; std::getline(file, line); ++number) {
        if (line.rfind("#include", 0) != 0) continue;
        for (const char* forbidden : rule.forbidden) {
          EXPECT_EQ(line.find(forbidden), std::string::npos)
              << entry.path().string() << ":" << number << " includes what its layer may not: " << line;
        }
      }
    }
  EXPECT_GE(scanned, 6);
}

}  // namespace
}  // namespace bounce::viewer
