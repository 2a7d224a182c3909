#include "render/light_sampling.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "shared/color.glsl"

namespace bounce::render {
namespace {

// Turns non-negative weights into a cumulative distribution of size + 1
// values from 0 to 1; returns their sum. All-zero weights give a uniform cdf.
double cumulative(std::span<const double> weights, float* cdf) {
  double sum = 0.0;
  for (double w : weights) sum += w;
  cdf[0] = 0.0f;
  double running = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    running += weights[i];
    cdf[i + 1] = sum > 0.0 ? float(running / sum) : float(double(i + 1) / double(weights.size()));
  }
  cdf[weights.size()] = 1.0f;
  return sum;
}

float luminanceOf(const io::ImageF& image, int x, int y) {
  const float r = image.at(x, y, 0), g = image.at(x, y, 1), b = image.at(x, y, 2);
  const float l = shared::luminance(glm::vec3(r, g, b));
  return std::isfinite(l) && l > 0.0f ? l : 0.0f;
}

}  // namespace

EnvironmentDistribution buildEnvironmentDistribution(const io::ImageF& equirect, std::uint32_t maxWidth) {
  if (equirect.width < 2 || equirect.height < 1 || equirect.channelCount() < 3)
    throw std::invalid_argument("environment distribution: the map needs at least 2x1 texels and RGB channels");
  if (maxWidth < 2) throw std::invalid_argument("environment distribution: maxWidth must be at least 2");
  EnvironmentDistribution d;
  d.width = std::min<std::uint32_t>(std::uint32_t(equirect.width), maxWidth);
  d.height = std::max<std::uint32_t>(1, std::uint32_t(std::lround(double(equirect.height) * d.width / equirect.width)));

  // Shaders read the map bilinearly, which spreads a bright texel half a
  // texel into its neighbours: the integral of that reconstruction over a
  // texel is the [1 2 1] x [1 2 1] / 16 tent of the texels (u wraps, v clamps).
  const int w = equirect.width, h = equirect.height;
  std::vector<double> luminance(std::size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) luminance[std::size_t(y) * w + x] = luminanceOf(equirect, x, y);
  const auto at = [&](int x, int y) { return luminance[std::size_t(std::clamp(y, 0, h - 1)) * w + (x + w) % w]; };
  // Each cell's weight: the sum over its texels of that integral times
  // sin(theta), proportional to the power the cell's patch of sky sends.
  std::vector<double> weights(std::size_t(d.width) * d.height, 0.0);
  for (int y = 0; y < h; ++y) {
    const double sinTheta = std::sin((double(y) + 0.5) / h * M_PI);
    const std::size_t row = std::min<std::size_t>(d.height - 1, std::size_t(y) * d.height / h);
    for (int x = 0; x < w; ++x) {
      const double tent = (4.0 * at(x, y) + 2.0 * (at(x - 1, y) + at(x + 1, y) + at(x, y - 1) + at(x, y + 1)) +
                           at(x - 1, y - 1) + at(x + 1, y - 1) + at(x - 1, y + 1) + at(x + 1, y + 1)) /
                          16.0;
      const std::size_t column = std::min<std::size_t>(d.width - 1, std::size_t(x) * d.width / w);
      weights[row * d.width + column] += tent * sinTheta;
    }
  }
  double total = 0.0;
  for (double w : weights) total += w;
  if (!(total > 0.0) || !std::isfinite(total)) return d;  // black: empty
  const double floor = kEnvironmentDistributionFloor * total / double(weights.size());
  for (double& w : weights) w += floor;

  d.marginalCdf.resize(d.height + 1);
  d.conditionalCdf.resize(std::size_t(d.height) * (d.width + 1));
  std::vector<double> rowWeights(d.height);
  for (std::uint32_t y = 0; y < d.height; ++y)
    rowWeights[y] = cumulative(std::span(weights).subspan(std::size_t(y) * d.width, d.width),
                               d.conditionalCdf.data() + std::size_t(y) * (d.width + 1));
  d.totalWeight = cumulative(rowWeights, d.marginalCdf.data());
  return d;
}

float EnvironmentDistribution::pdfUv(glm::vec2 uv) const {
  if (empty()) return 0.0f;
  const std::uint32_t x = std::min(width - 1, std::uint32_t(std::max(0.0f, uv.x) * float(width)));
  const std::uint32_t y = std::min(height - 1, std::uint32_t(std::max(0.0f, uv.y) * float(height)));
  const float* row = conditionalCdf.data() + std::size_t(y) * (width + 1);
  return (marginalCdf[y + 1] - marginalCdf[y]) * float(height) * (row[x + 1] - row[x]) * float(width);
}

std::vector<float> EnvironmentDistribution::packed() const {
  std::vector<float> values(marginalCdf);
  values.insert(values.end(), conditionalCdf.begin(), conditionalCdf.end());
  if (values.empty()) values.push_back(0.0f);  // a buffer may not be empty
  return values;
}

EmissiveTriangles collectEmissiveTriangles(const scene::Scene& scene, const SceneBvh& bvh,
                                           std::span<const scene::Instance> instances) {
  return collectEmissiveTriangles(scene.materials, bvh, instances);
}

EmissiveTriangles collectEmissiveTriangles(std::span<const scene::Material> materials, const SceneBvh& bvh,
                                           std::span<const scene::Instance> instances) {
  std::vector<float> materialPower(materials.size());
  for (std::size_t m = 0; m < materials.size(); ++m) {
    const scene::Material& material = materials[m];
    materialPower[m] = std::max(0.0f, shared::luminance(material.emissiveFactor * material.emissiveStrength));
  }
  struct Entry {
    std::uint32_t instance, triangle;
    float area;
    double power;
  };
  std::vector<Entry> entries;
  double total = 0.0;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const std::size_t mesh = std::size_t(instances[i].mesh);
    const glm::mat4& toWorld = instances[i].objectToWorld;
    for (std::uint32_t t = bvh.meshFirstTriangle(mesh); t < bvh.meshFirstTriangle(mesh + 1); ++t) {
      const glm::uvec4& triangle = bvh.triangles()[t];
      const float power = materialPower[triangle.w & ~shared::kBvhAlphaMaskedBit];
      if (!(power > 0.0f)) continue;
      const glm::vec3 p0 = glm::vec3(toWorld * bvh.positions()[triangle.x]);
      const glm::vec3 p1 = glm::vec3(toWorld * bvh.positions()[triangle.y]);
      const glm::vec3 p2 = glm::vec3(toWorld * bvh.positions()[triangle.z]);
      const float area = 0.5f * glm::length(glm::cross(p1 - p0, p2 - p0));
      if (!(area > 0.0f) || !std::isfinite(area)) continue;  // degenerate: cannot be hit either
      entries.push_back({std::uint32_t(i), t, area, double(power) * area});
      total += double(power) * area;
    }
  }
  EmissiveTriangles result;
  result.totalPower = total;
  double running = 0.0;
  for (const Entry& e : entries) {
    running += e.power;
    const float cdf = &e == &entries.back() ? 1.0f : float(running / total);
    result.packed.emplace_back(e.instance, e.triangle, glm::floatBitsToUint(cdf), glm::floatBitsToUint(e.area));
  }
  return result;
}

}  // namespace bounce::render
