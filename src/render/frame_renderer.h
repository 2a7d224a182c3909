// The frame renderer: for a scene and a camera, makes exactly the per-frame
// inputs a real engine hands a GI pass — a full-resolution G-buffer from
// BVH-traced primary rays, and direct lighting with ray-traced shadows.
//
//   render.gbuffer       viewZ, normal+roughness, geometric normal, base colour+metallic,
//                        emissive, motion vectors, object/material ids
//   render.direct_light  sun + punctual lights (GGX + Lambert), emission; environment behind
//
// Animated nodes move between frames; their motion vectors include the
// motion (previous transforms are kept per instance).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpu/context.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"
#include "render/environment.h"
#include "render/frame_types.glsl"
#include "scene/scene.h"

namespace bounce::render {

class SceneBvh;
class GpuBvh;
class TextureAtlas;

// The camera of a pose as the passes see it (render/frame_types.glsl).
shared::GpuCamera gpuCamera(const scene::CameraPose& pose, std::uint32_t width, std::uint32_t height);

// Throws gpu::GpuError "camera: <the condition that failed, with its values>"
// for a pose that cannot make an image: a position or target that is not
// finite or lies more than 1e18 from the origin along an axis, position and
// target at the same point, an up vector that is zero, not finite or
// parallel to the view, a vertical field of view outside (0, 180) degrees.
// FrameRenderer::record checks every frame's camera with it.
void checkCamera(const scene::CameraPose& pose);

// The sub-pixel offset (pixels, in [-0.5, 0.5)) of frame `frameIndex`'s rays
// when jitter is on: Halton (2, 3), 16 frames long.
glm::vec2 jitterOffset(std::uint64_t frameIndex);

struct FrameRendererOptions {
  std::uint32_t width = 960;
  std::uint32_t height = 540;
  bool jitter = false;  // sub-pixel camera jitter (Halton 2,3), kept out of motion vectors
  std::uint32_t maxTextureSize = 2048;
  EnvironmentDesc environment;
  // Receives each warning, one line without a newline (once per renderer:
  // mesh instances that cannot be drawn). Empty: "bounce: warning: <line>" on stderr.
  std::function<void(const std::string&)> warn;
};

// One frame's view: where the camera is, when it is (animation time), and
// whether it jumped (no motion vectors across a cut).
struct FrameView {
  scene::CameraPose camera;
  float time = 0.0f;
  bool cut = false;
};

// A named image the renderer makes, for --aov and --dump-stages.
struct Aov {
  std::string name;  // viewZ, normal, geometric-normal, albedo, roughness, metallic, emissive, motion, ids, direct
  gpu::Image* image;
};

class FrameRenderer {
 public:
  FrameRenderer(gpu::Context& context, const scene::Scene& scene, const FrameRendererOptions& options);
  ~FrameRenderer();
  // The bytes of the images a frame of this size holds (the G-buffer and
  // direct light; the scene's buffers and textures come on top).
  static std::uint64_t frameImageBytes(std::uint32_t width, std::uint32_t height);

  // Records one frame into the recorder of the FrameLoop slot `frameIndex % framesInFlight`.
  void record(gpu::Recorder& recorder, std::uint64_t frameIndex, const FrameView& view);

  gpu::Image& viewZ() { return *viewZ_; }
  gpu::Image& normalRoughness() { return *normalRoughness_; }
  gpu::Image& geometricNormal() { return *geometricNormal_; }
  gpu::Image& baseColorMetallic() { return *baseColorMetallic_; }
  gpu::Image& emissive() { return *emissive_; }
  gpu::Image& motion() { return *motion_; }
  gpu::Image& ids() { return *ids_; }
  gpu::Image& direct() { return *direct_; }
  std::vector<Aov> aovs();
  Environment& environment() { return *environment_; }
  GpuBvh& gpuBvh() { return *gpuBvh_; }
  const SceneBvh& bvh() const { return *bvh_; }
  gpu::Buffer& lights() { return *lights_; }
  // The declarations of render/scene_access.glsl's bindings (frame constants,
  // materials, instances, vertex attributes, texture atlas, BVH), for any
  // pass that traces into the scene, and their binds for frame `frameIndex`
  // (whose constants the last record() of that frame wrote).
  static std::vector<gpu::ResourceDecl> sceneResources();
  // The layout of their gIn_Frame (shared::FrameConstants), for PassDesc::constants.
  static std::vector<gpu::ConstantsDecl> sceneConstants();
  std::vector<gpu::Bind> sceneBinds(std::uint64_t frameIndex);
  gpu::Buffer& frameConstants(std::uint64_t frameIndex) { return *slots_[frameIndex % kFramesInFlight].constants; }
  std::uint32_t width() const { return options_.width; }
  std::uint32_t height() const { return options_.height; }
  std::size_t triangleCount() const { return triangleCount_; }

  // The material index of the surface that pixel (x, y) of the last
  // completed frame shows (the low 16 bits of its ids texel), or nullopt for
  // the background and for a pixel outside the image. Reads that one texel
  // back (blocking). Precondition: the GPU is idle (FrameLoop::finish()), so
  // the ids image holds a finished frame.
  std::optional<std::uint32_t> materialAt(std::uint32_t x, std::uint32_t y);

  // The materials as the renderer draws them: the scene's, with the edits of
  // setMaterial.
  const std::vector<scene::Material>& materials() const { return materials_; }
  // Replaces material `index`'s editable values (base colour factor,
  // metallic, roughness, emissive factor and strength; name, textures, alpha
  // mode and the rest stay) and uploads the material table, so every pass
  // that reads it through sceneBinds() (the G-buffer, direct light, the GI
  // library's scene bridge, the reference path tracer) draws the new values
  // from the next recorded frame on. Throws std::out_of_range for an index
  // past the materials, std::invalid_argument for a value that is not
  // finite, a base colour, metallic or roughness outside [0, 1], a negative
  // emissive factor or strength, or an emission above
  // scene::kMaxLightStrength; nothing changes then.
  // Precondition: the GPU is idle (FrameLoop::finish()) and no frame is
  // being recorded: the upload is blocking (submitAndWait) and overwrites
  // the table frames in flight would read.
  void setMaterial(std::size_t index, const scene::Material& material);
  // Moves the sun: its direct light from the next recorded frame on, and a
  // procedural sky baked and prefiltered again for it (a map stays).
  // Throws gpu::GpuError, changing nothing, for a sun out of range; throws
  // std::logic_error where the renderer has no sun (hasSun false).
  // Precondition: the GPU is idle (FrameLoop::finish()).
  void setSun(const scene::Sun& sun);
  // Goes up by one with every setMaterial, so whoever built something from
  // materials() (the reference's emissive-triangle list) sees it is stale.
  std::uint64_t materialRevision() const { return materialRevision_; }
  // The share of its light the emission edits since the last call changed
  // (of each material setMaterial edited, |after - before| / the larger
  // luminance of its emission; the largest of them), and resets it to 0:
  // the GI library's FrameInputs::lightChange for the next frame, since a
  // lamp the frame does not show (off screen, smaller than a pixel) leaves
  // no trace in the direct light the library compares.
  float takeLightChange();

  static constexpr std::uint32_t kFramesInFlight = 2;
  static constexpr std::uint32_t kMaxLights = 256;

 private:
  struct Slot {
    std::unique_ptr<gpu::Buffer> constants;  // uniform, written by the CPU
    std::unique_ptr<gpu::Buffer> instancesStaging;
    std::unique_ptr<gpu::Buffer> lightsStaging;
  };
  void uploadStatic();
  void uploadMaterials();
  // Once per renderer: which instances the BVH could not take (their node
  // transforms have no inverse in floats), so they are not silently missing.
  void warnAboutUntraceableInstances(std::span<const scene::Instance> instances);

  gpu::Context& context_;
  const scene::Scene& scene_;
  FrameRendererOptions options_;
  std::size_t triangleCount_ = 0;
  std::size_t instanceCount_ = 0;
  std::unique_ptr<SceneBvh> bvh_;
  std::unique_ptr<GpuBvh> gpuBvh_;
  std::unique_ptr<TextureAtlas> atlas_;
  std::unique_ptr<Environment> environment_;
  std::vector<scene::Material> materials_;
  std::uint64_t materialRevision_ = 0;
  float lightChange_ = 0.0f;  // takeLightChange()
  std::unique_ptr<gpu::Buffer> materialTable_, vertexAttributes_, instances_, lights_;
  std::array<Slot, kFramesInFlight> slots_;
  std::unique_ptr<gpu::Image> viewZ_, normalRoughness_, geometricNormal_, baseColorMetallic_, emissive_, motion_, ids_,
      direct_;
  std::unique_ptr<gpu::ComputePass> gbufferPass_, directLightPass_;
  // The previous frame's camera and instance transforms, for motion vectors.
  bool hasPrevious_ = false;
  scene::CameraPose previousCamera_;
  std::vector<glm::mat4> previousTransforms_;
  bool warnedAboutUntraceable_ = false;
};

}  // namespace bounce::render
