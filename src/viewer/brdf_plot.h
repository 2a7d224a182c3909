// The material editor's BRDF plots: brdf-viz's three hemisphere plots of one
// material (plot/hemisphere_plot.h) as one RGBA8 image that the viewer draws
// beside the editor and refines a little every frame, as the microfacet write-up
// "A new shiny specular BRDF" says raydiance re-renders its material preview progressively.
//
// Panels, left to right: "f cos" (luminance of f cos over light directions)
// and "pdf" (sampleMaterial's pdf), both evaluated per pixel, and "samples":
// a histogram of sampleMaterial's samples over the disk's pixels, scaled to a
// pdf estimate and drawn with the same colour map, so that as it accumulates
// it converges to the pdf panel beside it (a visual check of the sampler
// against its pdf). The view is fixed at kViewDegrees from the normal on the
// right of each disk (cyan dot), its mirror direction on the left (white dot).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "plot/canvas.h"
#include "plot/hemisphere_plot.h"

namespace bounce::viewer {

class BrdfPlot {
 public:
  static constexpr float kViewDegrees = 45.0f;
  static constexpr int kDefaultPanelSize = 128;
  // Enough for the histogram to settle visibly (its relative noise is
  // 1/sqrt(samples in a pixel)); refine() adds nothing beyond it.
  static constexpr std::uint32_t kMaxSamples = 1u << 20;

  enum class Panel { BrdfCosine, Pdf, Samples };
  // A panel's square within the image, in pixels.
  struct Rect {
    int x = 0;
    int y = 0;
    int width = 0;
    int height = 0;
  };

  // panelSize: each disk's diameter in pixels (at least 16). The image
  // starts with the default material of plot::MaterialView, not yet drawn.
  explicit BrdfPlot(int panelSize = kDefaultPanelSize);

  // Restarts the plots (sample count 0) when any value differs from the
  // current material's; the same values change nothing, so the editor may
  // call this every frame. The image changes in the next refine(). Throws
  // std::invalid_argument for a value outside [0, 1] or not finite.
  void setMaterial(glm::vec3 baseColor, float roughness, float metallic);

  // Adds up to `samples` samples to the histogram (none past kMaxSamples)
  // and redraws the samples panel; the first call after a restart draws the
  // analytic panels too. Returns whether any byte of the image changed.
  // About 1 ms for 4096 samples at the default size (the analytic panels,
  // once per material, a few more).
  bool refine(std::uint32_t samples);

  std::uint32_t samples() const { return samples_; }

  // width() * height() pixels, row 0 at the top, 4 bytes each: display
  // (sRGB-encoded) values as a PNG stores them, alpha 255.
  const std::vector<std::uint8_t>& rgba() const { return rgba_; }
  int width() const { return canvas_.width(); }
  int height() const { return canvas_.height(); }
  Rect panelRect(Panel panel) const;

 private:
  plot::HemispherePanel panel(Panel which) const;
  void drawAnalyticPanels();
  void drawSamplesPanel();
  // Copies a rectangle of the canvas into rgba_; whether a byte changed.
  bool encode(const Rect& rect);

  int panelSize_;
  plot::MaterialView material_;
  plot::Canvas canvas_;
  std::vector<std::uint8_t> rgba_;
  std::vector<std::uint32_t> histogram_;  // samples per pixel of the samples panel
  std::uint32_t samples_ = 0;
  bool analyticDrawn_ = false;
};

}  // namespace bounce::viewer
