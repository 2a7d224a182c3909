// One frame as every command, the viewer and the tests record it: the frame
// renderer's G-buffer and direct light, then the GI library on them
// (through GiBridge), into one command buffer of a frame loop. The view of
// the frame before, which the library's reprojection needs, is kept here
// once; a frame that is a cut restarts the library's
// histories.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <utility>

#include "bounce/gi.h"
#include "bounce/gi_settings.h"
#include "gpu/context.h"
#include "gpu/frame_loop.h"
#include "render/frame_renderer.h"
#include "render/gi_bridge.h"

namespace bounce::render {

struct FramePipelineDesc {
  FrameRendererOptions renderer;
  // The GI library's context and settings; none: the frame is direct light alone.
  std::optional<std::pair<gi::ContextDesc, gi::Settings>> gi;
  // How the library is handed each frame (jitter, emission apart); captureStages is per frame.
  GiFrameOptions giFrame;
};

// What one frame of a FramePipeline records besides its view.
struct PipelineFrameOptions {
  bool captureStages = false;  // every pass's output of this frame is copied (renderer and library)
  bool gi = true;              // record the library after the renderer (false: the caller records its own)
};

class FramePipeline {
 public:
  // `scene` outlives the pipeline (the renderer keeps a reference to it).
  FramePipeline(gpu::Context& context, const scene::Scene& scene, const FramePipelineDesc& desc);
  ~FramePipeline();

  // Begins frame `view` in the loop and records the renderer and the
  // library; the caller may record passes of its own after them into the
  // recorder returned, then calls end().
  gpu::Recorder& begin(const FrameView& view, const PipelineFrameOptions& options = {});
  // Submits the frame begun; it becomes the previous one.
  void end();
  // begin() and end(); returns the frame's index.
  std::uint64_t frame(const FrameView& view, const PipelineFrameOptions& options = {});
  // Waits for every frame submitted.
  void finish() { loop_.finish(); }

  // Replaces the library (none: the frame is direct light alone) once every
  // frame in flight is done; a new library has no history, so the next
  // frame should be a cut.
  void setGi(const std::optional<std::pair<gi::ContextDesc, gi::Settings>>& gi);

  FrameRenderer& renderer() { return renderer_; }
  GiBridge* gi() { return gi_.get(); }  // null without the library
  gpu::FrameLoop& loop() { return loop_; }
  std::uint64_t frameIndex() const { return loop_.frameIndex(); }
  // The view of the frame before the one begun (or, between frames, of the last one).
  const FrameView& previousView() const { return previous_; }
  std::uint32_t framesRecorded() const { return frames_; }
  // What the frame is: the library's composite, or the direct light alone.
  gpu::Image& frameImage();

 private:
  // Destroyed first: the loop waits for the frames in flight, which use the renderer's and the library's images.
  gpu::Context& context_;
  FrameRenderer renderer_;
  std::unique_ptr<GiBridge> gi_;
  gpu::FrameLoop loop_;
  GiFrameOptions giFrame_;
  FrameView previous_{};
  FrameView current_{};
  bool open_ = false;
  std::uint32_t frames_ = 0;
};

}  // namespace bounce::render
