// The distributions the reference path tracer samples lights from, built on
// the CPU once per reference and read by shaders/render/light_sampling.glsl.
//
//   environment  a piecewise-constant density over the equirect map's uv,
//                proportional to luminance * sin(theta) (the solid angle a
//                texel covers) of the map as shaders read it (bilinearly),
//                so bright parts of the sky are sampled in proportion to the
//                light they send;
//   emissive     every triangle of an emissive material, chosen in proportion
//                to its emitted power (luminance of the material's emission
//                times world area), a point on it uniformly by area.
//
// Both are what multiple importance sampling needs: a sampler, and the pdf
// of any direction or hit another strategy produced, computed the same way.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "io/image_io.h"
#include "render/bvh.h"
#include "scene/scene.h"

namespace bounce::render {

// Cells of the environment distribution are at most this wide (the map is
// box-filtered down); light sampling only needs the map's coarse shape, and
// the radiance itself is still read from the full-resolution map.
inline constexpr std::uint32_t kEnvironmentDistributionMaxWidth = 512;

// Every cell keeps at least this fraction of the mean cell weight, so no
// direction the map lights (even through bilinear filtering at a cell's
// edge) has a zero pdf.
inline constexpr float kEnvironmentDistributionFloor = 1e-3f;

struct EnvironmentDistribution {
  std::uint32_t width = 0;   // cells along u
  std::uint32_t height = 0;  // cells along v
  // Cumulative distribution over rows: height + 1 values from 0 to 1.
  std::vector<float> marginalCdf;
  // Per row, the cumulative distribution over its cells: width + 1 values from 0 to 1.
  std::vector<float> conditionalCdf;
  double totalWeight = 0.0;  // 0: a black environment, nothing to sample

  bool empty() const { return totalWeight <= 0.0; }
  // The density over uv in [0,1)^2 at uv (integrates to 1 over the square).
  float pdfUv(glm::vec2 uv) const;
  // marginalCdf then conditionalCdf, the layout light_sampling.glsl reads.
  std::vector<float> packed() const;
};

// The distribution of an equirect map (RGB or RGBA, 2:1). Non-finite or
// negative texels count as black.
EnvironmentDistribution buildEnvironmentDistribution(const io::ImageF& equirect,
                                                     std::uint32_t maxWidth = kEnvironmentDistributionMaxWidth);

// The emissive triangles of a scene at one moment, in the layout
// light_sampling.glsl reads: per triangle x = instance (the scene instance
// index the BVH reports), y = triangle (BLAS leaf order), z = float bits of
// the cumulative share of power up to and including this triangle, w = float
// bits of its world area.
struct EmissiveTriangles {
  std::vector<glm::uvec4> packed;
  // Sum of luminance(material emission) * world area; a hit emitter's pdf
  // per unit area is luminance(its material's emission) / totalPower.
  double totalPower = 0.0;

  std::size_t count() const { return packed.size(); }
};

// Materials count as emissive when the luminance of emissiveFactor *
// emissiveStrength is positive (an emissive texture only modulates that).
EmissiveTriangles collectEmissiveTriangles(const scene::Scene& scene, const SceneBvh& bvh,
                                           std::span<const scene::Instance> instances);
// The same with other values for the scene's materials, one per material
// (a FrameRenderer's materials() after setMaterial).
EmissiveTriangles collectEmissiveTriangles(std::span<const scene::Material> materials, const SceneBvh& bvh,
                                           std::span<const scene::Instance> instances);

}  // namespace bounce::render
