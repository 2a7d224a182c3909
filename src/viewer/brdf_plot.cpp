#include "viewer/brdf_plot.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

namespace bounce::viewer {
namespace {

constexpr int kMargin = 6;
const glm::vec3 kBackground(0.08f);
const glm::vec3 kLabelColour(0.9f);

// Large labels where they fit over a panel ("samples" is 84 pixels wide), else small.
int labelScale(int panelSize) { return panelSize >= 96 ? 2 : 1; }
int labelHeight(int panelSize) { return 7 * labelScale(panelSize) + 4; }

void checkUnitRange(const char* name, float value) {
  if (!(value >= 0.0f && value <= 1.0f))
    throw std::invalid_argument(std::string("BrdfPlot: ") + name + " " + std::to_string(value) + " is not in [0, 1]");
}

int checkedPanelSize(int panelSize) {
  if (panelSize < 16) throw std::invalid_argument("BrdfPlot: panel size " + std::to_string(panelSize) + " is below 16");
  return panelSize;
}

// As PNG files store display values (io::writePng's rounding).
std::uint8_t toByte(float v) { return std::uint8_t(std::floor(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f)); }

}  // namespace

BrdfPlot::BrdfPlot(int panelSize)
    : panelSize_(checkedPanelSize(panelSize)),
      material_{glm::vec3(0.8f), 0.0f, 0.5f, kViewDegrees},
      canvas_(3 * panelSize_ + 4 * kMargin, 2 * kMargin + labelHeight(panelSize_) + panelSize_, kBackground),
      rgba_(std::size_t(canvas_.width()) * std::size_t(canvas_.height()) * 4, 255),
      histogram_(std::size_t(panelSize_) * std::size_t(panelSize_), 0) {
  const char* labels[] = {"f cos", "pdf", "samples"};
  for (int index = 0; index < 3; ++index)
    canvas_.text(panelRect(Panel(index)).x, kMargin, labels[index], kLabelColour, labelScale(panelSize_));
  encode({0, 0, canvas_.width(), canvas_.height()});
}

BrdfPlot::Rect BrdfPlot::panelRect(Panel which) const {
  return {kMargin + int(which) * (panelSize_ + kMargin), kMargin + labelHeight(panelSize_), panelSize_, panelSize_};
}

plot::HemispherePanel BrdfPlot::panel(Panel which) const {
  const Rect rect = panelRect(which);
  return {rect.x, rect.y, rect.width};
}

void BrdfPlot::setMaterial(glm::vec3 baseColor, float roughness, float metallic) {
  checkUnitRange("base colour red", baseColor.x);
  checkUnitRange("base colour green", baseColor.y);
  checkUnitRange("base colour blue", baseColor.z);
  checkUnitRange("roughness", roughness);
  checkUnitRange("metallic", metallic);
  if (baseColor == material_.baseColor && roughness == material_.roughness && metallic == material_.metallic) return;
  material_.baseColor = baseColor;
  material_.roughness = roughness;
  material_.metallic = metallic;
  std::fill(histogram_.begin(), histogram_.end(), 0u);
  samples_ = 0;
  analyticDrawn_ = false;
}

bool BrdfPlot::refine(std::uint32_t samples) {
  bool changed = false;
  const bool restarted = !analyticDrawn_;
  if (restarted) {
    drawAnalyticPanels();
    changed = encode(panelRect(Panel::BrdfCosine));
    changed = encode(panelRect(Panel::Pdf)) || changed;
    analyticDrawn_ = true;
  }
  const std::uint32_t added = std::min(samples, kMaxSamples - samples_);
  const plot::HemispherePanel samplesPanel = panel(Panel::Samples);
  for (std::uint32_t index = samples_; index < samples_ + added; ++index) {
    glm::vec3 direction;
    bool specular;
    if (!material_.sample(index, direction, specular)) continue;
    const glm::ivec2 pixel = samplesPanel.pixelOf(direction);
    ++histogram_[std::size_t(pixel.y) * std::size_t(panelSize_) + std::size_t(pixel.x)];
  }
  samples_ += added;
  if (added > 0 || restarted) {
    drawSamplesPanel();
    changed = encode(panelRect(Panel::Samples)) || changed;
  }
  return changed;
}

void BrdfPlot::drawAnalyticPanels() {
  panel(Panel::BrdfCosine).fill(canvas_, [&](glm::vec3 l) { return material_.brdfCosine(l); });
  panel(Panel::Pdf).fill(canvas_, [&](glm::vec3 l) { return material_.pdf(l); });
  panel(Panel::BrdfCosine).markViewAndMirror(canvas_, material_);
  panel(Panel::Pdf).markViewAndMirror(canvas_, material_);
}

void BrdfPlot::drawSamplesPanel() {
  // A pixel is (2 / size)^2 of the unit disk, twice that in solid angle
  // (plot::diskToDirection); rejected samples count in the total, as the
  // pdf's missing mass below the horizon.
  const float pixelSolidAngle = 8.0f / float(panelSize_ * panelSize_);
  const float toPdf = samples_ > 0 ? 1.0f / (float(samples_) * pixelSolidAngle) : 0.0f;
  const plot::HemispherePanel samplesPanel = panel(Panel::Samples);
  for (int y = 0; y < panelSize_; ++y)
    for (int x = 0; x < panelSize_; ++x)
      if (samplesPanel.directionAt(x, y)) {
        const std::uint32_t count = histogram_[std::size_t(y) * std::size_t(panelSize_) + std::size_t(x)];
        canvas_.set(samplesPanel.left + x, samplesPanel.top + y, plot::plotColour(float(count) * toPdf));
      }
  samplesPanel.markViewAndMirror(canvas_, material_);
}

bool BrdfPlot::encode(const Rect& rect) {
  const io::ImageF& image = canvas_.image();
  bool changed = false;
  for (int y = rect.y; y < rect.y + rect.height; ++y)
    for (int x = rect.x; x < rect.x + rect.width; ++x) {
      std::uint8_t* out = &rgba_[(std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 4];
      for (int c = 0; c < 3; ++c) {
        const std::uint8_t byte = toByte(image.at(x, y, c));
        changed = changed || out[c] != byte;
        out[c] = byte;
      }
    }
  return changed;
}

}  // namespace bounce::viewer
