#include "render/frame_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "gpu/constants_layout.h"
#include "gpu/error.h"
#include "gpu/format.h"
#include "gpu/transfer.h"
#include "render/bvh.h"
#include "render/frame_types.glsl"
#include "render/gpu_bvh.h"
#include "render/render_shaders.h"
#include "render/texture_atlas.h"
#include "shared/packing.glsl"
#include "util/printable.h"

namespace bounce::render {
namespace {

using shared::FrameConstants;
using shared::GpuCamera;
using shared::GpuInstance;
using shared::GpuLight;
using shared::GpuMaterial;

using namespace gpu::formats;

}  // namespace

GpuCamera gpuCamera(const scene::CameraPose& pose, std::uint32_t width, std::uint32_t height) {
  const glm::vec3 forward = glm::normalize(pose.target - pose.position);
  const glm::vec3 right = glm::normalize(glm::cross(forward, pose.up));
  const glm::vec3 up = glm::cross(right, forward);
  const float tanHalf = std::tan(glm::radians(pose.fovYDegrees) * 0.5f);
  const float aspect = float(width) / float(height);
  return {glm::vec4(pose.position, tanHalf), glm::vec4(right * tanHalf * aspect, 0.0f), glm::vec4(up * tanHalf, 0.0f),
          glm::vec4(forward, 0.0f)};
}

namespace {

// The renderer squares distances (dot products of offsets) in 32-bit floats,
// which overflow beyond about 1.8e19; a camera this far from the origin on
// any axis keeps that well out of reach.
constexpr float kMaxCameraCoordinate = 1e18f;

std::string text(float value, int digits = 6) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, double(value));
  return buffer;
}
std::string text(const glm::vec3& v) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%g, %g, %g)", double(v.x), double(v.y), double(v.z));
  return buffer;
}

}  // namespace

// Camera poses that cannot make an image are refused before they make NaN,
// naming the condition that failed and the values that failed it.
void checkCamera(const scene::CameraPose& pose) {
  const auto refuse = [](const std::string& problem) { throw gpu::GpuError("camera: " + problem); };
  const auto finite = [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  const std::pair<const char*, glm::vec3> points[] = {{"position", pose.position}, {"target", pose.target}};
  for (const auto& [name, point] : points) {
    if (!finite(point)) refuse(std::string(name) + " " + text(point) + " is not finite");
    const glm::vec3 distance = glm::abs(point);
    if (std::max({distance.x, distance.y, distance.z}) > kMaxCameraCoordinate)
      refuse(std::string(name) + " " + text(point) + " is more than " + text(kMaxCameraCoordinate) +
             " from the origin along an axis; the renderer's 32-bit floats cannot square distances that large");
  }
  if (!finite(pose.up)) refuse("up vector " + text(pose.up) + " is not finite");
  if (!(pose.fovYDegrees > 0.0f && pose.fovYDegrees < 180.0f))
    refuse("vertical field of view " + text(pose.fovYDegrees, 9) + " degrees is outside (0, 180)");
  const glm::vec3 forward = pose.target - pose.position;
  if (!(glm::length(forward) >= 1e-6f))
    refuse("position " + text(pose.position) + " and target " + text(pose.target) + " are the same point");
  if (!(glm::length(pose.up) >= 1e-6f)) refuse("up vector " + text(pose.up) + " is zero");
  if (glm::length(glm::cross(glm::normalize(forward), glm::normalize(pose.up))) < 1e-6f)
    refuse("up vector " + text(pose.up) + " is parallel to the view direction " + text(glm::normalize(forward)));
}

glm::vec2 jitterOffset(std::uint64_t frameIndex) {
  const auto halton = [](std::uint32_t index, std::uint32_t base) {
    float result = 0.0f;
    float fraction = 1.0f / float(base);
    for (; index > 0; index /= base, fraction /= float(base)) result += fraction * float(index % base);
    return result;
  };
  const std::uint32_t index = std::uint32_t(frameIndex % 16) + 1;
  return {halton(index, 2) - 0.5f, halton(index, 3) - 0.5f};
}

namespace {

void rows3x4(const glm::mat4& m, glm::vec4 out[3]) {
  for (int r = 0; r < 3; ++r) out[r] = glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]);
}

// The inverse transpose that carries normals to world space, scaled to a
// largest entry of 1: shaders normalise what it gives, and at scales far
// from 1 the plain inverse transpose would overflow or underflow there.
// Identity for an instance the BVH cannot take (it is never hit).
glm::mat3 normalMatrix(const glm::mat4& objectToWorld) {
  const std::optional<glm::mat4> worldToObject = instanceWorldToObject(objectToWorld);
  if (!worldToObject) return glm::mat3(1.0f);
  const glm::dmat3 inverseTranspose = glm::transpose(glm::dmat3(glm::dmat4(*worldToObject)));
  double largest = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) largest = std::max(largest, std::abs(inverseTranspose[c][r]));
  return glm::mat3(inverseTranspose / largest);
}

GpuMaterial packMaterial(const scene::Material& m) {
  const auto texture = [](int index) { return index < 0 ? shared::kNoTexture : std::uint32_t(index); };
  GpuMaterial g{};
  g.baseColorFactor = m.baseColorFactor;
  g.emissive =
      glm::vec4(m.emissiveFactor * m.emissiveStrength, m.alphaMode == scene::AlphaMode::Opaque  ? -1.0f
                                                       : m.alphaMode == scene::AlphaMode::Blend ? 0.5f
                                                                                                : m.alphaCutoff);
  g.factors = glm::vec4(m.metallicFactor, m.roughnessFactor, m.normalScale, m.doubleSided ? 1.0f : 0.0f);
  g.textures = glm::uvec4(texture(m.baseColorTexture), texture(m.metallicRoughnessTexture), texture(m.normalTexture),
                          texture(m.emissiveTexture));
  return g;
}

// Vertex attributes of every mesh, concatenated in mesh order (the same
// global vertex numbering the BVH's triangles use).
std::vector<glm::uvec4> packVertexAttributes(const scene::Scene& scene) {
  std::vector<glm::uvec4> packed;
  for (const scene::Mesh& mesh : scene.meshes)
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const glm::vec4& t = mesh.tangents[v];
      const std::uint32_t tangent =
          (shared::packNormalOct32(glm::vec3(t)) & ~1u) | (t.w < 0.0f ? 1u : 0u);  // lowest bit: handedness
      packed.emplace_back(shared::packNormalOct32(mesh.normals[v]), tangent, glm::floatBitsToUint(mesh.texcoords[v].x),
                          glm::floatBitsToUint(mesh.texcoords[v].y));
    }
  if (packed.empty()) packed.emplace_back(0u);
  return packed;
}

}  // namespace

std::vector<gpu::ResourceDecl> FrameRenderer::sceneResources() {
  using gpu::Access;
  using gpu::ResourceKind;
  std::vector<gpu::ResourceDecl> decls = {
      {"gIn_Frame", Access::Read, VK_FORMAT_UNDEFINED, "camera, previous camera, sun, jitter",
       ResourceKind::UniformBuffer},
      {"gIn_Materials", Access::Read, VK_FORMAT_UNDEFINED, "materials", ResourceKind::StorageBuffer},
      {"gIn_Instances", Access::Read, VK_FORMAT_UNDEFINED, "instance transforms, now and before",
       ResourceKind::StorageBuffer},
      {"gIn_VertexAttributes", Access::Read, VK_FORMAT_UNDEFINED, "normals, tangents, texcoords",
       ResourceKind::StorageBuffer},
      {"gIn_TextureAtlas", Access::Read, VK_FORMAT_UNDEFINED, "every texture and its mips", ResourceKind::SampledImage},
      {"gIn_TextureAtlasEntries", Access::Read, VK_FORMAT_UNDEFINED, "where each texture is in the atlas",
       ResourceKind::StorageBuffer},
  };
  for (const gpu::ResourceDecl& decl : GpuBvh::traceResources()) decls.push_back(decl);
  return decls;
}

std::vector<gpu::ConstantsDecl> FrameRenderer::sceneConstants() {
  return {BOUNCE_CONSTANTS_LAYOUT("gIn_Frame", FrameConstants, camera, previousCamera, imageSize, jitter, sunDirection,
                                  sunColor, environment)};
}

namespace {

gpu::PassDesc gbufferDesc() {
  std::vector<gpu::ResourceDecl> decls = FrameRenderer::sceneResources();
  decls.insert(decls.end(), {
                                {"gOut_ViewZ", gpu::Access::Write, kR32f, "positive view depth; 0 = background"},
                                {"gOut_NormalRoughness", gpu::Access::Write, kRgba16f, "shading normal, roughness"},
                                {"gOut_GeometricNormal", gpu::Access::Write, kRgba16f, "triangle normal"},
                                {"gOut_BaseColorMetallic", gpu::Access::Write, kRgba8, "base colour, metallic"},
                                {"gOut_Emissive", gpu::Access::Write, kRgba16f, "emitted radiance"},
                                {"gOut_Motion", gpu::Access::Write, kRg16f, "pixels; previous = current + motion"},
                                {"gOut_Ids", gpu::Access::Write, kR32ui, "object << 16 | material"},
                            });
  return {.name = "render.gbuffer",
          .shader = "render/gbuffer",
          .shaders = shaders(),
          .resources = decls,
          .constants = FrameRenderer::sceneConstants()};
}

gpu::PassDesc directLightDesc() {
  // Shading reads the G-buffer, not instances; glslc drops the unused binding.
  std::vector<gpu::ResourceDecl> decls = FrameRenderer::sceneResources();
  std::erase_if(decls, [](const gpu::ResourceDecl& d) { return d.name == "gIn_Instances"; });
  using gpu::ResourceKind;
  decls.insert(decls.end(), {
                                {"gIn_ViewZ", gpu::Access::Read, kR32f, "position reconstruction"},
                                {"gIn_NormalRoughness", gpu::Access::Read, kRgba16f, "shading normal, roughness"},
                                {"gIn_GeometricNormal", gpu::Access::Read, kRgba16f, "shadow ray offset, horizon test"},
                                {"gIn_BaseColorMetallic", gpu::Access::Read, kRgba8, "material"},
                                {"gIn_Emissive", gpu::Access::Read, kRgba16f, "emission, added"},
                                {"gIn_Lights", gpu::Access::Read, VK_FORMAT_UNDEFINED, "punctual lights",
                                 ResourceKind::StorageBuffer},
                                {"gIn_Environment", gpu::Access::Read, VK_FORMAT_UNDEFINED,
                                 "sky or HDR map behind the scene", ResourceKind::SampledImage},
                                {"gOut_Radiance", gpu::Access::Write, kRgba16f, "direct light + emission, linear HDR"},
                            });
  return {.name = "render.direct_light",
          .shader = "render/direct_light",
          .shaders = shaders(),
          .resources = decls,
          .constants = FrameRenderer::sceneConstants()};
}

}  // namespace

namespace {

// The images of a frame, made at the render size: the G-buffer and the direct light.
struct FrameImage {
  const char* name;
  VkFormat format;
  gpu::Visualize visualize;
};
constexpr FrameImage kFrameImages[] = {
    {"gbuffer.viewZ", kR32f, gpu::Visualize::Range},
    {"gbuffer.normal_roughness", kRgba16f, gpu::Visualize::Signed},
    {"gbuffer.geometric_normal", kRgba16f, gpu::Visualize::Signed},
    {"gbuffer.base_color_metallic", kRgba8, gpu::Visualize::Color},
    {"gbuffer.emissive", kRgba16f, gpu::Visualize::Radiance},
    {"gbuffer.motion", kRg16f, gpu::Visualize::Motion},
    {"gbuffer.ids", kR32ui, gpu::Visualize::Ids},
    {"light.direct", kRgba16f, gpu::Visualize::Radiance},
};

}  // namespace

FrameRenderer::FrameRenderer(gpu::Context& context, const scene::Scene& scene, const FrameRendererOptions& options)
    : context_(context), scene_(scene), options_(options), materials_(scene.materials) {
  if (options.width == 0 || options.height == 0 || options.width > 16384 || options.height > 16384)
    throw gpu::GpuError("frame size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                        " is outside 1..16384");
  scene::validate(scene);
  const std::vector<scene::Instance> instances = scene::instancesAt(scene, 0.0f);
  instanceCount_ = instances.size();
  if (instanceCount_ > 65535) throw gpu::GpuError(scene.name + ": more than 65535 mesh instances");
  if (scene.materials.size() > 65535) throw gpu::GpuError(scene.name + ": more than 65535 materials");
  const auto lightNodes =
      std::count_if(scene.nodes.begin(), scene.nodes.end(), [](const scene::Node& n) { return n.light >= 0; });
  if (lightNodes > std::ptrdiff_t(kMaxLights))
    throw gpu::GpuError(scene.name + ": " + std::to_string(lightNodes) +
                        " punctual lights; the renderer takes at most " + std::to_string(kMaxLights));
  for (const scene::Instance& instance : instances)
    triangleCount_ += scene.meshes[std::size_t(instance.mesh)].indices.size() / 3;

  bvh_ = std::make_unique<SceneBvh>(scene);
  bvh_->setInstances(instances);
  warnAboutUntraceableInstances(instances);
  gpuBvh_ = std::make_unique<GpuBvh>(context, *bvh_, kFramesInFlight);
  atlas_ = std::make_unique<TextureAtlas>(context, scene.textures, options.maxTextureSize);
  EnvironmentDesc environment = options.environment;
  environment_ = std::make_unique<Environment>(context, environment);

  uploadStatic();
  const std::size_t instanceBytes = std::max<std::size_t>(1, instanceCount_) * sizeof(GpuInstance);
  instances_ = std::make_unique<gpu::Buffer>(context, "scene.instances", instanceBytes, gpu::BufferUsage::DeviceLocal);
  lights_ = std::make_unique<gpu::Buffer>(context, "scene.lights", kMaxLights * sizeof(GpuLight),
                                          gpu::BufferUsage::DeviceLocal);
  for (std::uint32_t i = 0; i < kFramesInFlight; ++i) {
    const std::string suffix = ".slot" + std::to_string(i);
    slots_[i].constants = std::make_unique<gpu::Buffer>(context, "frame.constants" + suffix, sizeof(FrameConstants),
                                                        gpu::BufferUsage::Upload);
    slots_[i].instancesStaging = std::make_unique<gpu::Buffer>(context, "scene.instances.staging" + suffix,
                                                               instanceBytes, gpu::BufferUsage::Upload);
    slots_[i].lightsStaging = std::make_unique<gpu::Buffer>(context, "scene.lights.staging" + suffix,
                                                            kMaxLights * sizeof(GpuLight), gpu::BufferUsage::Upload);
  }

  std::unique_ptr<gpu::Image>* const made[] = {
      &viewZ_, &normalRoughness_, &geometricNormal_, &baseColorMetallic_, &emissive_, &motion_, &ids_, &direct_};
  static_assert(std::size(made) == std::size(kFrameImages));
  for (std::size_t i = 0; i < std::size(kFrameImages); ++i)
    *made[i] = std::make_unique<gpu::Image>(context, gpu::ImageDesc{kFrameImages[i].name, options.width, options.height,
                                                                    kFrameImages[i].format, kFrameImages[i].visualize});
  gbufferPass_ = std::make_unique<gpu::ComputePass>(context, gbufferDesc());
  directLightPass_ = std::make_unique<gpu::ComputePass>(context, directLightDesc());
}

FrameRenderer::~FrameRenderer() = default;

std::uint64_t FrameRenderer::frameImageBytes(std::uint32_t width, std::uint32_t height) {
  std::uint64_t bytesPerPixel = 0;
  for (const FrameImage& image : kFrameImages) bytesPerPixel += gpu::formatInfo(image.format).bytesPerPixel;
  return bytesPerPixel * width * height;
}

void FrameRenderer::uploadStatic() {
  // A buffer may not be empty; a scene without materials has nothing that reads one.
  const std::size_t tableBytes = std::max<std::size_t>(1, materials_.size()) * sizeof(GpuMaterial);
  materialTable_ =
      std::make_unique<gpu::Buffer>(context_, "scene.materials", tableBytes, gpu::BufferUsage::DeviceLocal);
  uploadMaterials();
  const std::vector<glm::uvec4> attributes = packVertexAttributes(scene_);
  vertexAttributes_ = std::make_unique<gpu::Buffer>(
      context_, "scene.vertex_attributes", attributes.size() * sizeof(glm::uvec4), gpu::BufferUsage::DeviceLocal);
  gpu::uploadBuffer(context_, *vertexAttributes_, attributes.data(), attributes.size() * sizeof(glm::uvec4));
}

void FrameRenderer::uploadMaterials() {
  std::vector<GpuMaterial> packed;
  for (const scene::Material& m : materials_) packed.push_back(packMaterial(m));
  if (packed.empty()) packed.push_back(packMaterial(scene::Material{}));
  gpu::uploadBuffer(context_, *materialTable_, packed.data(), packed.size() * sizeof(GpuMaterial));
}

void FrameRenderer::warnAboutUntraceableInstances(std::span<const scene::Instance> instances) {
  const std::vector<std::size_t>& untraceable = bvh_->untraceableInstances();
  if (warnedAboutUntraceable_ || untraceable.empty()) return;
  warnedAboutUntraceable_ = true;
  constexpr std::size_t kNamedNodes = 8;
  std::string line = "scene '" + scene_.name + "': " + std::to_string(untraceable.size()) +
                     " mesh instance(s) cannot be drawn: their node transforms have no inverse in 32-bit floats "
                     "(a scale of 0, or one whose inverse is beyond float's range): ";
  for (std::size_t k = 0; k < untraceable.size() && k < kNamedNodes; ++k) {
    const int node = instances[untraceable[k]].node;
    const std::string& name = scene_.nodes[std::size_t(node)].name;
    line += (k ? ", node " : "node ") + std::to_string(node) + (name.empty() ? "" : " '" + name + "'");
  }
  if (untraceable.size() > kNamedNodes) line += " and " + std::to_string(untraceable.size() - kNamedNodes) + " more";
  if (options_.warn)
    options_.warn(line);
  else
    std::fprintf(stderr, "bounce: warning: %s\n", util::printable(line).c_str());
}

std::vector<Aov> FrameRenderer::aovs() {
  return {{"viewZ", viewZ_.get()},
          {"normal", normalRoughness_.get()},
          {"geometric-normal", geometricNormal_.get()},
          {"albedo", baseColorMetallic_.get()},
          {"emissive", emissive_.get()},
          {"motion", motion_.get()},
          {"ids", ids_.get()},
          {"direct", direct_.get()}};
}

void FrameRenderer::record(gpu::Recorder& recorder, std::uint64_t frameIndex, const FrameView& view) {
  checkCamera(view.camera);
  Slot& slot = slots_[frameIndex % kFramesInFlight];
  const std::vector<glm::mat4> world = scene::nodeWorldMatrices(scene_, view.time);
  const std::vector<scene::Instance> instances = scene::instancesAt(scene_, view.time);
  const bool continuous = hasPrevious_ && !view.cut && previousTransforms_.size() == instances.size();

  // Instances: this frame's and the previous frame's transforms.
  auto* gpuInstances = static_cast<GpuInstance*>(slot.instancesStaging->mapped());
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const glm::mat4& current = instances[i].objectToWorld;
    GpuInstance g{};
    rows3x4(current, g.objectToWorld);
    rows3x4(continuous ? previousTransforms_[i] : current, g.previousObjectToWorld);
    rows3x4(glm::mat4(normalMatrix(current)), g.normalToWorld);
    g.ids = glm::uvec4(std::uint32_t(i), 0u, 0u, 0u);
    gpuInstances[i] = g;
  }

  // Punctual lights at their nodes' current places.
  auto* gpuLights = static_cast<GpuLight*>(slot.lightsStaging->mapped());
  std::uint32_t lightCount = 0;
  for (std::size_t n = 0; n < scene_.nodes.size(); ++n) {
    const int lightIndex = scene_.nodes[n].light;
    if (lightIndex < 0) continue;
    const scene::Light& light = scene_.lights[std::size_t(lightIndex)];
    const glm::vec3 position(world[n][3]);
    const glm::vec3 direction = glm::normalize(glm::vec3(world[n] * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f)));
    const float type = light.type == scene::LightType::Directional ? float(shared::kLightDirectional)
                       : light.type == scene::LightType::Point     ? float(shared::kLightPoint)
                                                                   : float(shared::kLightSpot);
    const float cosOuter = std::cos(light.outerConeAngle);
    const float cosInner = std::cos(light.innerConeAngle);
    gpuLights[lightCount++] = {glm::vec4(position, type), glm::vec4(direction, light.range),
                               glm::vec4(light.color * light.intensity, 0.0f),
                               glm::vec4(cosOuter, 1.0f / std::max(cosInner - cosOuter, 1e-4f), 0.0f, 0.0f)};
  }

  FrameConstants constants{};
  constants.camera = gpuCamera(view.camera, options_.width, options_.height);
  constants.previousCamera =
      continuous ? gpuCamera(previousCamera_, options_.width, options_.height) : constants.camera;
  constants.imageSize = glm::vec4(float(options_.width), float(options_.height), 1.0f / float(options_.width),
                                  1.0f / float(options_.height));
  const glm::vec2 jitter = options_.jitter ? jitterOffset(frameIndex) : glm::vec2(0.0f);
  const float pixelSpread = 2.0f * constants.camera.position.w / float(options_.height);
  constants.jitter = glm::vec4(jitter, pixelSpread, float(frameIndex));
  const scene::Sun& sun = options_.environment.sun;
  constants.sunDirection = glm::vec4(sun.direction(), options_.environment.hasSun ? sun.illuminance : 0.0f);
  constants.sunColor = glm::vec4(sun.color, float(lightCount));
  constants.environment = glm::vec4(float(environment_->mipCount()), 1.0f, 0.0f, 0.0f);
  std::memcpy(slot.constants->mapped(), &constants, sizeof constants);

  recorder.copyBuffer(*slot.instancesStaging, *instances_,
                      std::max<std::size_t>(1, instances.size()) * sizeof(GpuInstance));
  recorder.copyBuffer(*slot.lightsStaging, *lights_, kMaxLights * sizeof(GpuLight));
  bvh_->setInstances(instances);
  warnAboutUntraceableInstances(instances);
  gpuBvh_->updateInstances(recorder, std::uint32_t(frameIndex % kFramesInFlight));
  environment_->record(recorder);

  std::vector<gpu::Bind> binds = sceneBinds(frameIndex);
  binds.insert(binds.end(), {{"gOut_ViewZ", *viewZ_},
                             {"gOut_NormalRoughness", *normalRoughness_},
                             {"gOut_GeometricNormal", *geometricNormal_},
                             {"gOut_BaseColorMetallic", *baseColorMetallic_},
                             {"gOut_Emissive", *emissive_},
                             {"gOut_Motion", *motion_},
                             {"gOut_Ids", *ids_}});
  recorder.dispatch(*gbufferPass_, options_.width, options_.height, binds);

  binds = sceneBinds(frameIndex);
  std::erase_if(binds, [](const gpu::Bind& b) { return b.name == "gIn_Instances"; });
  binds.insert(binds.end(), {{"gIn_ViewZ", *viewZ_},
                             {"gIn_NormalRoughness", *normalRoughness_},
                             {"gIn_GeometricNormal", *geometricNormal_},
                             {"gIn_BaseColorMetallic", *baseColorMetallic_},
                             {"gIn_Emissive", *emissive_},
                             {"gIn_Lights", *lights_},
                             {"gIn_Environment", environment_->radiance(), environment_->sampler()},
                             {"gOut_Radiance", *direct_}});
  recorder.dispatch(*directLightPass_, options_.width, options_.height, binds);

  hasPrevious_ = true;
  previousCamera_ = view.camera;
  previousTransforms_.clear();
  for (const scene::Instance& instance : instances) previousTransforms_.push_back(instance.objectToWorld);
}

std::optional<std::uint32_t> FrameRenderer::materialAt(std::uint32_t x, std::uint32_t y) {
  if (x >= options_.width || y >= options_.height) return std::nullopt;
  gpu::Buffer texel(context_, "gbuffer.ids.texel", sizeof(std::uint32_t), gpu::BufferUsage::Readback);
  context_.submitAndWait([&](gpu::Recorder& recorder) {
    recorder.copyImageToBuffer(*ids_, texel, gpu::ImageRegion{.x = x, .y = y, .width = 1, .height = 1});
    recorder.makeHostReadable(texel);
  });
  std::uint32_t ids = 0;
  std::memcpy(&ids, texel.mapped(), sizeof ids);
  // render.gbuffer writes instance << 16 | material, and all ones for the background.
  if (ids == 0xffffffffu) return std::nullopt;
  return ids & 0xffffu;
}

namespace {

// Why setMaterial refuses `m` as material `index` ("" when it does not), so
// that a refused edit changes nothing.
std::string materialProblem(const scene::Material& m) {
  const auto finite = [](const auto& v) {
    for (int i = 0; i < v.length(); ++i)
      if (!std::isfinite(v[i])) return false;
    return true;
  };
  const auto within = [](const auto& v, float low, float high) {
    for (int i = 0; i < v.length(); ++i)
      if (!(v[i] >= low && v[i] <= high)) return false;
    return true;
  };
  const auto vectorText = [](const glm::vec4& v, int n) {
    std::string t = "(";
    for (int i = 0; i < n; ++i) t += (i ? ", " : "") + text(v[i]);
    return t + ")";
  };
  if (!finite(m.baseColorFactor) || !within(m.baseColorFactor, 0.0f, 1.0f))
    return "base colour factor " + vectorText(m.baseColorFactor, 4) + " is not within [0, 1]";
  if (!(m.metallicFactor >= 0.0f && m.metallicFactor <= 1.0f))
    return "metallic " + text(m.metallicFactor) + " is not within [0, 1]";
  if (!(m.roughnessFactor >= 0.0f && m.roughnessFactor <= 1.0f))
    return "roughness " + text(m.roughnessFactor) + " is not within [0, 1]";
  if (!finite(m.emissiveFactor) || !within(m.emissiveFactor, 0.0f, std::numeric_limits<float>::max()))
    return "emissive factor " + vectorText(glm::vec4(m.emissiveFactor, 0.0f), 3) + " is not finite and >= 0";
  if (!(std::isfinite(m.emissiveStrength) && m.emissiveStrength >= 0.0f))
    return "emissive strength " + text(m.emissiveStrength) + " is not finite and >= 0";
  const double emission =
      double(m.emissiveStrength) * double(std::max({m.emissiveFactor.x, m.emissiveFactor.y, m.emissiveFactor.z}));
  if (const std::string problem = scene::lightStrengthProblem(emission); !problem.empty())
    return "emission (strength x factor) " + text(float(emission)) + " is " + problem;
  return {};
}

}  // namespace

void FrameRenderer::setSun(const scene::Sun& sun) {
  if (!options_.environment.hasSun) throw std::logic_error("render: setSun on a renderer without a sun");
  environment_->setSun(sun);
  options_.environment.sun = sun;
}

void FrameRenderer::setMaterial(std::size_t index, const scene::Material& material) {
  if (index >= materials_.size())
    throw std::out_of_range("setMaterial: material index " + std::to_string(index) +
                            " is out of range; the scene has " + std::to_string(materials_.size()) + " materials");
  scene::Material& target = materials_[index];
  if (const std::string problem = materialProblem(material); !problem.empty())
    throw std::invalid_argument("setMaterial: material " + std::to_string(index) +
                                (target.name.empty() ? "" : " '" + target.name + "'") + ": " + problem);
  const auto emission = [](const scene::Material& m) {
    const glm::dvec3 rgb = glm::dvec3(m.emissiveFactor) * double(m.emissiveStrength);
    return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z;
  };
  const double before = emission(target), after = emission(material);
  if (std::max(before, after) > 0.0)
    lightChange_ = std::max(lightChange_, float(std::abs(after - before) / std::max(before, after)));
  target.baseColorFactor = material.baseColorFactor;
  target.metallicFactor = material.metallicFactor;
  target.roughnessFactor = material.roughnessFactor;
  target.emissiveFactor = material.emissiveFactor;
  target.emissiveStrength = material.emissiveStrength;
  uploadMaterials();
  ++materialRevision_;
}

float FrameRenderer::takeLightChange() { return std::exchange(lightChange_, 0.0f); }

std::vector<gpu::Bind> FrameRenderer::sceneBinds(std::uint64_t frameIndex) {
  std::vector<gpu::Bind> binds = {{"gIn_Frame", frameConstants(frameIndex)},
                                  {"gIn_Materials", *materialTable_},
                                  {"gIn_Instances", *instances_},
                                  {"gIn_VertexAttributes", *vertexAttributes_},
                                  {"gIn_TextureAtlas", atlas_->pages(), context_.nearestSampler()},
                                  {"gIn_TextureAtlasEntries", atlas_->entries()}};
  gpuBvh_->appendBinds(binds);
  return binds;
}

}  // namespace bounce::render
