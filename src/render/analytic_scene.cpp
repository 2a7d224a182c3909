#include "render/analytic_scene.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "gpu/error.h"
#include "gpu/transfer.h"
#include "render/analytic_scene_types.glsl"

namespace bounce::render {
namespace {

using shared::AnalyticGround;
using shared::AnalyticSceneParams;
using shared::AnalyticSphere;

const gpu::ResourceDecl kSceneBuffer{"gIn_Scene", gpu::Access::Read, VK_FORMAT_UNDEFINED, "ground material and spheres",
                                     gpu::ResourceKind::StorageBuffer};

gpu::PassDesc gbufferPassDesc() {
  return {.name = "render.analytic_gbuffer",
          .shader = "render/analytic_gbuffer",
          .resources = {kSceneBuffer,
                        {"gOut_ViewZ", gpu::Access::Write, VK_FORMAT_R32_SFLOAT, "linear view depth, 0 = sky"},
                        {"gOut_NormalRoughness", gpu::Access::Write, VK_FORMAT_R16G16B16A16_SFLOAT,
                         "world normal, perceptual roughness"},
                        {"gOut_BaseColorMetallic", gpu::Access::Write, VK_FORMAT_R8G8B8A8_UNORM,
                         "linear base colour, metallic"}},
          .pushConstantSize = sizeof(AnalyticSceneParams)};
}

gpu::PassDesc directSunPassDesc() {
  return {.name = "render.direct_sun",
          .shader = "render/direct_sun",
          .resources = {kSceneBuffer,
                        {"gIn_ViewZ", gpu::Access::Read, VK_FORMAT_R32_SFLOAT, "linear view depth"},
                        {"gIn_NormalRoughness", gpu::Access::Read, VK_FORMAT_R16G16B16A16_SFLOAT, "normal"},
                        {"gIn_BaseColorMetallic", gpu::Access::Read, VK_FORMAT_R8G8B8A8_UNORM, "base colour"},
                        {"gOut_Radiance", gpu::Access::Write, VK_FORMAT_R16G16B16A16_SFLOAT,
                         "direct sunlight with shadows; sky behind background pixels"}},
          .pushConstantSize = sizeof(AnalyticSceneParams)};
}

}  // namespace

glm::vec3 Sun::direction() const {
  const float elevation = glm::radians(elevationDegrees);
  const float azimuth = glm::radians(azimuthDegrees);
  return {std::cos(elevation) * std::sin(azimuth), std::sin(elevation), std::cos(elevation) * std::cos(azimuth)};
}

AnalyticScene AnalyticScene::standard() {
  AnalyticScene scene;
  scene.spheres = {
      {{-1.7f, 0.7f, 0.2f}, 0.7f, {0.85f, 0.2f, 0.15f}, 0.0f, 0.4f},
      {{0.0f, 1.0f, -0.4f}, 1.0f, {0.8f, 0.8f, 0.8f}, 0.0f, 0.6f},
      {{1.75f, 0.6f, 0.5f}, 0.6f, {0.15f, 0.35f, 0.85f}, 0.0f, 0.3f},
  };
  return scene;
}

CameraBasis cameraBasis(const Camera& camera, std::uint32_t width, std::uint32_t height) {
  const glm::vec3 forward = glm::normalize(camera.target - camera.position);
  const glm::vec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::vec3 up = glm::cross(right, forward);
  const float tanHalf = std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
  const float aspect = float(width) / float(height);
  return {right * tanHalf * aspect, up * tanHalf, forward};
}

AnalyticRenderer::AnalyticRenderer(gpu::Context& context, std::uint32_t width, std::uint32_t height,
                                   const AnalyticScene& scene)
    : context_(context), width_(width), height_(height), scene_(scene) {
  for (const AnalyticSphereDesc& s : scene.spheres)
    if (!(s.radius > 0.0f) || !std::isfinite(s.radius) || !std::isfinite(glm::dot(s.center, s.center)))
      throw gpu::GpuError("analytic scene: a sphere has a non-finite centre or a radius that is not positive");

  std::vector<std::uint8_t> bytes(sizeof(AnalyticGround) +
                                  std::max<std::size_t>(1, scene.spheres.size()) * sizeof(AnalyticSphere));
  AnalyticGround ground{glm::vec4(scene.groundColor, 0.0f), glm::vec4(scene.groundRoughness, 0.0f, 0.0f, 0.0f)};
  std::memcpy(bytes.data(), &ground, sizeof ground);
  for (std::size_t i = 0; i < scene.spheres.size(); ++i) {
    const AnalyticSphereDesc& s = scene.spheres[i];
    AnalyticSphere packed{glm::vec4(s.center, s.radius), glm::vec4(s.baseColor, s.metallic),
                          glm::vec4(s.roughness, 0.0f, 0.0f, 0.0f)};
    std::memcpy(bytes.data() + sizeof ground + i * sizeof packed, &packed, sizeof packed);
  }
  sceneBuffer_ =
      std::make_unique<gpu::Buffer>(context, "render.analytic_scene", bytes.size(), gpu::BufferUsage::DeviceLocal);
  gpu::uploadBuffer(context, *sceneBuffer_, bytes.data(), bytes.size());

  viewZ_ = std::make_unique<gpu::Image>(
      context, gpu::ImageDesc{"gbuffer.viewZ", width, height, VK_FORMAT_R32_SFLOAT, gpu::Visualize::Range});
  normalRoughness_ = std::make_unique<gpu::Image>(
      context,
      gpu::ImageDesc{"gbuffer.normal_roughness", width, height, VK_FORMAT_R16G16B16A16_SFLOAT, gpu::Visualize::Signed});
  baseColorMetallic_ = std::make_unique<gpu::Image>(
      context,
      gpu::ImageDesc{"gbuffer.base_color_metallic", width, height, VK_FORMAT_R8G8B8A8_UNORM, gpu::Visualize::Color});
  direct_ = std::make_unique<gpu::Image>(
      context, gpu::ImageDesc{"light.direct", width, height, VK_FORMAT_R16G16B16A16_SFLOAT, gpu::Visualize::Radiance});
  gbufferPass_ = std::make_unique<gpu::ComputePass>(context, gbufferPassDesc());
  directSunPass_ = std::make_unique<gpu::ComputePass>(context, directSunPassDesc());
}

void AnalyticRenderer::record(gpu::Recorder& recorder, const Camera& camera) {
  const CameraBasis basis = cameraBasis(camera, width_, height_);
  AnalyticSceneParams params{};
  params.cameraPosition = glm::vec4(camera.position, float(width_));
  params.cameraRight = glm::vec4(basis.right, float(height_));
  params.cameraUp = glm::vec4(basis.up, float(scene_.spheres.size()));
  params.cameraForward = glm::vec4(basis.forward, 0.0f);
  params.sunDirection = glm::vec4(scene_.sun.direction(), scene_.sun.illuminance);
  params.sunColor = glm::vec4(scene_.sun.color, 0.0f);
  params.skyRadiance = glm::vec4(scene_.skyRadiance, 0.0f);

  recorder.dispatch(*gbufferPass_, width_, height_,
                    {{"gIn_Scene", *sceneBuffer_},
                     {"gOut_ViewZ", *viewZ_},
                     {"gOut_NormalRoughness", *normalRoughness_},
                     {"gOut_BaseColorMetallic", *baseColorMetallic_}},
                    params);
  recorder.dispatch(*directSunPass_, width_, height_,
                    {{"gIn_Scene", *sceneBuffer_},
                     {"gIn_ViewZ", *viewZ_},
                     {"gIn_NormalRoughness", *normalRoughness_},
                     {"gIn_BaseColorMetallic", *baseColorMetallic_},
                     {"gOut_Radiance", *direct_}},
                    params);
}

}  // namespace bounce::render
