// Hemisphere plots of the material model (the pictures of the
// microfacet write-up "A new shiny specular BRDF"): the upper
// hemisphere of light directions drawn as a disk on a Canvas, coloured by a
// value the shared material functions give for each direction (f cos, the
// sampling pdf) or marked where samples land. The values come from the same
// shared functions the shaders run (shaders/shared/brdf.glsl, sampling.glsl),
// evaluated on the CPU. `bounce brdf-viz` animates these plots; the material
// editor of `bounce view` refines them live (viewer/brdf_plot.h).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include <glm/glm.hpp>

#include "plot/canvas.h"

namespace bounce::plot {

// The upper hemisphere (z up) in a unit disk, area-preserving (Lambert
// azimuthal): equal areas on the disk are equal solid angles (a disk area A
// is a solid angle 2A), so a lobe's visual size is its real share of
// directions, and a histogram of samples over the disk's pixels estimates
// their pdf.
glm::vec3 diskToDirection(glm::vec2 p);
glm::vec2 directionToDisk(glm::vec3 d);

// A material seen from one view direction, as the plots evaluate it: normal
// +z, the view in the xz plane on the +x side, so the plots are symmetric
// about their horizontal centre line and the mirror direction lies at -x.
struct MaterialView {
  glm::vec3 baseColor{0.8f};
  float metallic = 0.0f;
  float roughness = 0.5f;     // perceptual, as the material model takes it
  float viewDegrees = 45.0f;  // from the normal

  glm::vec3 view() const;
  glm::vec3 mirror() const;  // the view reflected about the normal
  // Luminance of materialBrdfCosine towards light direction l.
  float brdfCosine(glm::vec3 l) const;
  // pdfMaterial of l: what sampleMaterial's samples are distributed by.
  float pdf(glm::vec3 l) const;
  float specularProbability() const;
  // Sample `index` of the plots' sequence (R2 for the lobe's two dimensions,
  // the base-2 radical inverse for the choice of lobe): deterministic and
  // low-discrepancy, so any prefix of it covers the lobes evenly. False where
  // sampleMaterial rejects the sample (a reflection below the horizon).
  bool sample(std::uint32_t index, glm::vec3& direction, bool& specular) const;
};

// The colour a plotted value is drawn in: the magma map of a fixed,
// saturating tone curve 1 - exp(-value), the same for every panel and frame
// so that they compare with each other.
glm::vec3 plotColour(float value);

// Dot colours: the view (cyan), its mirror (white), samples of the specular
// lobe (orange) and of the diffuse lobe (green).
inline constexpr glm::vec3 kViewMarkColour(0.3f, 0.8f, 1.0f);
inline constexpr glm::vec3 kMirrorMarkColour(1.0f);
inline constexpr glm::vec3 kSpecularSampleColour(1.0f, 0.6f, 0.2f);
inline constexpr glm::vec3 kDiffuseSampleColour(0.4f, 0.9f, 0.4f);

// One disk plot on a canvas: the top-left pixel of its square and its
// diameter in pixels. Pixel coordinates (x, y) below are the square's own,
// in [0, size).
struct HemispherePanel {
  int left = 0;
  int top = 0;
  int size = 0;

  // The direction through the centre of pixel (x, y), or none where that
  // centre is outside the disk (the pixel is not part of the plot).
  std::optional<glm::vec3> directionAt(int x, int y) const;
  // The pixel a direction lands in (clamped into the square).
  glm::ivec2 pixelOf(glm::vec3 direction) const;
  // Every pixel of the disk in plotColour(value(its direction)).
  void fill(Canvas& canvas, const std::function<float(glm::vec3)>& value) const;
  // A dot of `radius` pixels where a direction lands.
  void mark(Canvas& canvas, glm::vec3 direction, float radius, glm::vec3 colour) const;
  // The view and mirror directions' dots, drawn over every panel.
  void markViewAndMirror(Canvas& canvas, const MaterialView& material) const;
};

}  // namespace bounce::plot
