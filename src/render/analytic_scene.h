// The analytic test scene: a ground plane and a few spheres under a sun,
// ray-cast in compute with closed-form intersections (no scene files, no
// BVH). It writes the same G-buffer and direct light a real engine would hand
// the GI library, so it proves the whole GPU path with known answers.
#pragma once

#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/context.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"

namespace bounce::render {

struct AnalyticSphereDesc {
  glm::vec3 center{0.0f};
  float radius = 1.0f;
  glm::vec3 baseColor{0.8f};
  float metallic = 0.0f;
  float roughness = 0.5f;
};

struct Camera {
  glm::vec3 position{0.0f, 1.6f, 5.5f};
  glm::vec3 target{0.0f, 0.6f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovYDegrees = 45.0f;
};

struct Sun {
  float elevationDegrees = 50.0f;  // above the horizon
  float azimuthDegrees = 30.0f;    // from +Z towards +X
  float illuminance = 3.0f;        // E, irradiance on a surface facing the sun
  glm::vec3 color{1.0f, 0.96f, 0.9f};
  glm::vec3 direction() const;  // unit vector towards the sun
};

struct AnalyticScene {
  glm::vec3 groundColor{0.8f};
  float groundRoughness = 0.9f;
  std::vector<AnalyticSphereDesc> spheres;
  Sun sun;
  glm::vec3 skyRadiance{0.35f, 0.5f, 0.8f};

  // The quick start's scene: three spheres on a grey ground.
  static AnalyticScene standard();
};

// Camera basis for a frame: how the passes turn a pixel into a ray.
struct CameraBasis {
  glm::vec3 right, up, forward;  // right and up are scaled by the half-extents of the image plane at distance 1
};
CameraBasis cameraBasis(const Camera& camera, std::uint32_t width, std::uint32_t height);

// Owns the G-buffer and direct-light images and records the two passes
// render.analytic_gbuffer and render.direct_sun.
class AnalyticRenderer {
 public:
  AnalyticRenderer(gpu::Context& context, std::uint32_t width, std::uint32_t height, const AnalyticScene& scene);

  void record(gpu::Recorder& recorder, const Camera& camera);

  gpu::Image& viewZ() { return *viewZ_; }                      // r32f, positive distance along the view axis; 0 = sky
  gpu::Image& normalRoughness() { return *normalRoughness_; }  // rgba16f world normal, perceptual roughness
  gpu::Image& baseColorMetallic() { return *baseColorMetallic_; }  // rgba8 linear base colour, metallic
  gpu::Image& directLight() { return *direct_; }                   // rgba16f linear radiance
  std::uint32_t width() const { return width_; }
  std::uint32_t height() const { return height_; }

 private:
  gpu::Context& context_;
  std::uint32_t width_, height_;
  AnalyticScene scene_;
  std::unique_ptr<gpu::Buffer> sceneBuffer_;
  std::unique_ptr<gpu::Image> viewZ_, normalRoughness_, baseColorMetallic_, direct_;
  std::unique_ptr<gpu::ComputePass> gbufferPass_, directSunPass_;
};

}  // namespace bounce::render
