#include "render/gi_bridge.h"

#include <algorithm>

#include <glm/gtc/type_ptr.hpp>

#include "gpu/timing.h"
#include "render/scene_bridge.h"

namespace bounce::render {
namespace {

// What LibraryImage promises about every library image after record().
gpu::SyncState libraryState() {
  gpu::SyncState state;
  state.writeStage = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
  state.writeAccess = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
  state.layout = VK_IMAGE_LAYOUT_GENERAL;
  return state;
}

bool sameState(const gpu::SyncState& a, const gpu::SyncState& b) {
  return a.writeStage == b.writeStage && a.writeAccess == b.writeAccess && a.readStages == b.readStages &&
         a.visibleTo == b.visibleTo && a.layout == b.layout;
}

}  // namespace

gi::Device giDevice(gpu::Context& context) {
  return {.instance = context.instance(),
          .physicalDevice = context.physicalDevice(),
          .device = context.device(),
          .queueFamily = context.queueFamily(),
          .debugUtils = context.debugLabelsAvailable()};
}

gi::ImageRef imageRef(gpu::Image& image) {
  const gpu::SyncState& state = image.sync();
  return {.image = image.handle(),
          .view = image.view(),
          .format = image.format(),
          .width = image.width(),
          .height = image.height(),
          .mipLevels = image.desc().mipLevels,
          .layout = state.layout,
          .stage = state.writeStage | state.readStages,
          .access = state.writeAccess};
}

void tookBack(gpu::Image& image, const gi::ImageRef& given) {
  gpu::SyncState& state = image.sync();
  state.layout = given.layout;
  // The library chained its reads into given.stage (or, reading in compute
  // without a transition, left them for a barrier from compute to cover).
  state.writeStage = given.stage | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
  state.writeAccess = given.access & gpu::kWriteAccessFlags;
  state.readStages = VK_PIPELINE_STAGE_2_NONE;
  state.visibleTo = VK_ACCESS_2_NONE;
}

gpu::CapturedStage capturedStage(gi::CapturedStage&& stage, std::uint64_t frame) {
  return {.frame = frame,
          .pass = stage.pass,
          .binding = stage.binding,
          .image = {.name = stage.pass + "." + stage.binding,
                    .width = stage.width,
                    .height = stage.height,
                    .format = stage.format,
                    .visualize = fromVisualization(stage.visualization)},
          .texels = std::move(stage.texels)};
}

gpu::Visualize fromVisualization(gi::Visualization view) { return gpu::Visualize(int(view)); }
static_assert(int(gpu::Visualize::Heat) == int(gi::Visualization::Heat) &&
                  int(gpu::Visualize::Radiance) == int(gi::Visualization::Radiance) &&
                  int(gpu::Visualize::Ids) == int(gi::Visualization::Ids),
              "gpu::Visualize and gi::Visualization list the same ways in the same order");

gi::Camera giCamera(const scene::CameraPose& pose, std::uint32_t width, std::uint32_t height, glm::vec2 jitter) {
  // The same basis as gpuCamera(), unscaled: the renderer's rays and the
  // library's reconstruction must agree to the last bit that matters.
  const glm::vec3 forward = glm::normalize(pose.target - pose.position);
  const glm::vec3 right = glm::normalize(glm::cross(forward, pose.up));
  const glm::vec3 up = glm::cross(right, forward);
  return gi::cameraFromBasis(glm::value_ptr(pose.position), glm::value_ptr(right), glm::value_ptr(up),
                             glm::value_ptr(forward), glm::radians(pose.fovYDegrees), float(width) / float(height),
                             glm::value_ptr(jitter));
}

GiBridge::GiBridge(gpu::Context& context, const gi::ContextDesc& desc, const gi::Settings& settings)
    : context_(context),
      library_(std::make_unique<gi::GiContext>(giDevice(context), desc, settings)),
      tracesScene_(!desc.sceneBridge.shaders.empty()) {}

GiBridge::~GiBridge() = default;

gpu::Image& GiBridge::wrap(const gi::ImageRef& ref, const std::string& name, gpu::Visualize view) {
  Wrapper& wrapper = wrappers_[ref.image];
  if (!wrapper.image) {
    gpu::ExternalImage external{.image = ref.image,
                                .view = ref.view,
                                .desc = {.name = name,
                                         .width = ref.width,
                                         .height = ref.height,
                                         .format = ref.format,
                                         .visualize = view,
                                         .mipLevels = ref.mipLevels},
                                .state = libraryState()};
    wrapper.image = std::make_unique<gpu::Image>(context_, external);
    wrapper.handedOut = libraryState();
  }
  return *wrapper.image;
}

void GiBridge::handBackWrappers(gpu::Recorder& recorder) {
  // What the renderer did with the library's images since the last frame
  // (readbacks, its own reads), made to complete before the library's
  // compute passes, back in GENERAL.
  for (auto& [handle, wrapper] : wrappers_)
    if (!sameState(wrapper.image->sync(), wrapper.handedOut))
      recorder.handOver(*wrapper.image, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        gi::kLibraryImageAccess);
  recorder.flush();
}

RendererInputs rendererInputs(FrameRenderer& renderer, std::uint64_t frameIndex, const FrameView& view,
                              const FrameView& previous, const GiFrameOptions& options) {
  const std::uint32_t w = renderer.width(), h = renderer.height();
  RendererInputs made;
  made.images = {&renderer.viewZ(),  &renderer.normalRoughness(), &renderer.baseColorMetallic(),
                 &renderer.motion(), &renderer.direct(),          &renderer.environment().radiance(),
                 &renderer.ids()};
  gi::FrameInputs& inputs = made.inputs;
  inputs.viewZ = imageRef(renderer.viewZ());
  inputs.normalRoughness = imageRef(renderer.normalRoughness());
  inputs.baseColorMetallic = imageRef(renderer.baseColorMetallic());
  inputs.motion = imageRef(renderer.motion());
  inputs.direct = imageRef(renderer.direct());  // holds the emission too
  // instance << 16 | material: the low 8 bits the library compares are the material's.
  inputs.materialId = imageRef(renderer.ids());
  if (options.separateEmissive) {
    inputs.emissive = imageRef(renderer.emissive());
    made.images.push_back(&renderer.emissive());
  }
  inputs.environment = imageRef(renderer.environment().radiance());
  inputs.environmentSampler = renderer.environment().sampler();
  inputs.width = w;
  inputs.height = h;
  inputs.camera = giCamera(view.camera, w, h, options.jitter ? jitterOffset(frameIndex) : glm::vec2(0.0f));
  inputs.previousCamera = giCamera(previous.camera, w, h,
                                   options.jitter && frameIndex > 0 ? jitterOffset(frameIndex - 1) : glm::vec2(0.0f));
  inputs.frameIndex = frameIndex;
  inputs.cameraCut = view.cut;
  inputs.lightChange = renderer.takeLightChange();
  inputs.captureStages = options.captureStages;
  return made;
}

void GiBridge::record(gpu::Recorder& recorder, FrameRenderer& renderer, std::uint64_t frameIndex,
                      const FrameView& view, const FrameView& previous, const GiFrameOptions& options) {
  RendererInputs made = rendererInputs(renderer, frameIndex, view, previous, options);
  SceneResources scene;
  if (tracesScene_) {
    scene = bvhSceneResources(renderer, frameIndex);
    made.inputs.sceneResources = scene.resources;
  }
  record(recorder, made.inputs, made.images);
  sceneBuffersRead(scene.buffers);
}

void GiBridge::record(gpu::Recorder& recorder, const gi::FrameInputs& inputs, std::span<gpu::Image* const> images) {
  handBackWrappers(recorder);
  library_->record(recorder.commandBuffer(), inputs);
  // Once the command buffer is done, the frame's GPU times and stage copies
  // join the recorder's owner's (FrameLoop: its timings and takeCaptures()).
  recorder.onCompleted([this, frame = inputs.frameIndex](gpu::TimingStats* timings,
                                                         std::vector<gpu::CapturedStage>* captures) {
    gi::FrameResults results = library_->collect(frame);
    if (timings)
      for (const gi::PassTiming& timing : results.timings)
        timings->add(timing.pass, timing.milliseconds, {timing.imageBytes, timing.bufferBytes});
    for (const gi::WorldRayCount& count : results.worldRays) {
      ++worldRays_.frames;
      worldRays_.sum.frameIndex = count.frameIndex;
      for (std::size_t p = 0; p < count.rays.size(); ++p) worldRays_.sum.rays[p] += count.rays[p];
      for (std::size_t p = 0; p < count.passRays.size(); ++p) {
        worldRays_.sum.passRays[p] += count.passRays[p];
        worldRays_.sum.passQueued[p] += count.passQueued[p];
      }
    }
    if (captures)
      for (gi::CapturedStage& stage : results.stages) captures->push_back(capturedStage(std::move(stage), stage.frameIndex));
  });
  const gi::ImageRef* refs[] = {&inputs.viewZ,        &inputs.normalRoughness, &inputs.baseColorMetallic,
                                &inputs.motion,       &inputs.direct,          &inputs.emissive,
                                &inputs.environment,  &inputs.noisyDiffuse,    &inputs.noisySpecular,
                                &inputs.materialId};
  for (gpu::Image* image : images) {
    const auto ref = std::find_if(std::begin(refs), std::end(refs),
                                  [&](const gi::ImageRef* r) { return r->image == image->handle(); });
    if (ref != std::end(refs)) {
      tookBack(*image, **ref);
      continue;
    }
    const auto noisy = std::find_if(inputs.noisy.begin(), inputs.noisy.end(),
                                    [&](const gi::ImageRef& r) { return r.image == image->handle(); });
    if (noisy != inputs.noisy.end()) tookBack(*image, *noisy);
  }
  for (auto& [handle, wrapper] : wrappers_) {
    wrapper.image->sync() = libraryState();
    wrapper.handedOut = libraryState();
  }
}

gpu::Image& GiBridge::composite() {
  return wrap(library_->composite(), "gi.composite", gpu::Visualize::Radiance);
}

gpu::Image& GiBridge::indirect(gi::SignalId signal) {
  const std::vector<gi::SignalDesc> signals = library_->signals();
  const std::string name = signal < signals.size() ? signals[signal].name : std::to_string(signal);
  return wrap(library_->indirect(signal), "gi.indirect." + name, gpu::Visualize::Radiance);
}

std::vector<GiBridge::Named> GiBridge::images() {
  std::vector<Named> named;
  for (const gi::LibraryImage& image : library_->images())
    named.push_back({image.name, &wrap(image.image, image.name, fromVisualization(image.visualization))});
  return named;
}

}  // namespace bounce::render
