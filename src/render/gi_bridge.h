// The frame renderer as the GI library's first user. Everything here goes
// through the library's public interface (include/bounce/gi.h), exactly as an
// engine's integration would: the renderer's device as a gi::Device, its
// images as ImageRefs carrying the state its Recorder tracked, its command
// buffer to record into; the library's images and results come back as
// plain Vulkan handles, which are wrapped here as gpu::Images so that the
// renderer's own passes, readbacks and stage dumps can use them with
// correct barriers.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "bounce/gi.h"
#include "gpu/context.h"
#include "gpu/frame_loop.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"
#include "render/frame_renderer.h"

namespace bounce::render {

// The context's device for the library (it creates no device of its own).
gi::Device giDevice(gpu::Context& context);

// An image as the library should take it now: the layout, stage and access
// of its last use as the image's SyncState records them.
gi::ImageRef imageRef(gpu::Image& image);
// Updates an image's SyncState after the library handed it back
// (InputState::Restore): the layout it came in, last used at the stages
// given and by the library's compute reads.
void tookBack(gpu::Image& image, const gi::ImageRef& given);

// A stage copy the library took as the renderer's own captures hold them
// (`frame`: the frame index to file it under).
gpu::CapturedStage capturedStage(gi::CapturedStage&& stage, std::uint64_t frame);

gpu::Visualize fromVisualization(gi::Visualization view);

// The gi::Camera of a pose rendered at width x height with `jitter` (pixels).
gi::Camera giCamera(const scene::CameraPose& pose, std::uint32_t width, std::uint32_t height, glm::vec2 jitter);

struct GiFrameOptions {
  bool jitter = false;            // the renderer jittered its rays (FrameRendererOptions::jitter)
  bool separateEmissive = false;  // hand the emission over apart (the direct light holds it too: tests only)
  bool captureStages = false;     // the library copies every pass output of this frame
};

// What the renderer hands the library for frame `frameIndex` it recorded with
// `view` (`previous`: the view of the frame before), and the gpu::Images
// those ImageRefs were made of (for GiBridge::record to update their states).
struct RendererInputs {
  gi::FrameInputs inputs;
  std::vector<gpu::Image*> images;
};
RendererInputs rendererInputs(FrameRenderer& renderer, std::uint64_t frameIndex, const FrameView& view,
                              const FrameView& previous, const GiFrameOptions& options = {});

// A GI library context on the renderer's device, and the wrappers of its images.
class GiBridge {
 public:
  GiBridge(gpu::Context& context, const gi::ContextDesc& desc, const gi::Settings& settings = {});
  ~GiBridge();

  gi::GiContext& library() { return *library_; }

  // Records the library's frame into the recorder's command buffer, after
  // `renderer` recorded frame `frameIndex` with `view`; `previous` is the
  // view of the frame before (ignored on a cut or for the first frame).
  // With the scene bridge "bvh" (render/scene_bridge.h) the renderer's
  // scene goes along.
  void record(gpu::Recorder& recorder, FrameRenderer& renderer, std::uint64_t frameIndex, const FrameView& view,
              const FrameView& previous, const GiFrameOptions& options = {});
  // The same with inputs made by hand: `images` are the gpu::Images the
  // ImageRefs of `inputs` came from (imageRef()), whose states are updated.
  void record(gpu::Recorder& recorder, const gi::FrameInputs& inputs, std::span<gpu::Image* const> images);

  // The library's images as gpu::Images of this context, in the state the
  // last record() left them; the renderer may read them in its recorders
  // and hands them back at the next record().
  gpu::Image& composite();
  gpu::Image& indirect(gi::SignalId signal);  // gi::GiContext::indirect
  gpu::Image& indirectDiffuse() { return indirect(gi::kDiffuseSignal); }
  gpu::Image& indirectSpecular() { return indirect(gi::kSpecularSignal); }
  struct Named {
    std::string name;
    gpu::Image* image;
  };
  std::vector<Named> images();

  // The world rays of the frames collected since the last resetWorldRays()
  // (gi::FrameResults::worldRays), summed by purpose and by pass; sum.frameIndex is the
  // last frame added.
  struct WorldRayTally {
    std::uint64_t frames = 0;
    gi::WorldRayCount sum;
  };
  const WorldRayTally& worldRays() const { return worldRays_; }
  void resetWorldRays() { worldRays_ = {}; }

 private:
  gpu::Image& wrap(const gi::ImageRef& ref, const std::string& name, gpu::Visualize view);
  void handBackWrappers(gpu::Recorder& recorder);

  gpu::Context& context_;
  std::unique_ptr<gi::GiContext> library_;
  bool tracesScene_;  // made with bvhSceneBridge(): each frame hands it the renderer's scene
  struct Wrapper {
    std::unique_ptr<gpu::Image> image;
    gpu::SyncState handedOut;  // the state the library left it in
  };
  std::unordered_map<VkImage, Wrapper> wrappers_;
  WorldRayTally worldRays_;
};

}  // namespace bounce::render
