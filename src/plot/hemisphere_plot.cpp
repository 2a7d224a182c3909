#include "plot/hemisphere_plot.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "io/colormap.h"
#include "shared/brdf.glsl"
#include "shared/color.glsl"
#include "shared/sampling.glsl"

namespace bounce::plot {
namespace {

const glm::vec3 kNormal(0.0f, 0.0f, 1.0f);

}  // namespace

glm::vec3 diskToDirection(glm::vec2 p) {
  const float r2 = glm::dot(p, p);  // in [0, 1] inside the disk
  const float cosTheta = 1.0f - r2;
  const float scale = std::sqrt(std::max(0.0f, 2.0f - r2));
  return {p.x * scale, p.y * scale, cosTheta};
}

glm::vec2 directionToDisk(glm::vec3 d) {
  const float r = std::sqrt(std::max(0.0f, 1.0f - d.z));
  const float horizontal = std::sqrt(d.x * d.x + d.y * d.y);
  return horizontal > 0.0f ? glm::vec2(d.x, d.y) * (r / horizontal) : glm::vec2(0.0f);
}

glm::vec3 MaterialView::view() const {
  const float viewRadians = glm::radians(viewDegrees);
  return {std::sin(viewRadians), 0.0f, std::cos(viewRadians)};
}

glm::vec3 MaterialView::mirror() const { return glm::reflect(-view(), kNormal); }

float MaterialView::brdfCosine(glm::vec3 l) const {
  return shared::luminance(shared::materialBrdfCosine(kNormal, view(), l, baseColor, metallic, roughness));
}

float MaterialView::pdf(glm::vec3 l) const {
  return shared::pdfMaterial(kNormal, view(), l, baseColor, metallic, roughness);
}

float MaterialView::specularProbability() const {
  return shared::specularSelectionProbability(baseColor, metallic, view().z);
}

bool MaterialView::sample(std::uint32_t index, glm::vec3& direction, bool& specular) const {
  const glm::vec2 u2 = shared::r2Point(index);
  const glm::vec3 u(u2.x, u2.y, shared::radicalInverseBase2(index));
  float pdf;
  if (!shared::sampleMaterial(kNormal, view(), baseColor, metallic, roughness, u, direction, pdf)) return false;
  specular = u.z < specularProbability();
  return true;
}

glm::vec3 plotColour(float value) {
  const std::array<std::uint8_t, 3> colour = io::magma(1.0f - std::exp(-value));
  return glm::vec3(colour[0], colour[1], colour[2]) / 255.0f;
}

std::optional<glm::vec3> HemispherePanel::directionAt(int x, int y) const {
  const float radius = 0.5f * float(size);
  const glm::vec2 disk((float(x) + 0.5f - radius) / radius, (radius - float(y) - 0.5f) / radius);
  if (glm::dot(disk, disk) > 1.0f) return std::nullopt;
  return diskToDirection(disk);
}

glm::ivec2 HemispherePanel::pixelOf(glm::vec3 direction) const {
  const float radius = 0.5f * float(size);
  const glm::vec2 q = directionToDisk(direction);
  const auto clampToSquare = [&](float p) { return std::clamp(int(std::floor(p)), 0, size - 1); };
  return {clampToSquare(radius + q.x * radius), clampToSquare(radius - q.y * radius)};
}

void HemispherePanel::fill(Canvas& canvas, const std::function<float(glm::vec3)>& value) const {
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      if (const std::optional<glm::vec3> direction = directionAt(x, y))
        canvas.set(left + x, top + y, plotColour(value(*direction)));
}

void HemispherePanel::mark(Canvas& canvas, glm::vec3 direction, float radius, glm::vec3 colour) const {
  const float diskRadius = 0.5f * float(size);
  const glm::vec2 centre(float(left) + diskRadius, float(top) + diskRadius);
  const glm::vec2 q = directionToDisk(direction);
  canvas.dot(centre.x + q.x * diskRadius, centre.y - q.y * diskRadius, radius, colour);
}

void HemispherePanel::markViewAndMirror(Canvas& canvas, const MaterialView& material) const {
  mark(canvas, material.view(), 4.0f, kViewMarkColour);
  mark(canvas, material.mirror(), 4.0f, kMirrorMarkColour);
}

}  // namespace bounce::plot
