// The right half of bounce view's split screen: the direct light alone, the
// same frame through a second GI library with other settings, or a
// progressive path-traced reference of the view (accumulating while the
// camera and the materials stay), and the error readout against it.
#pragma once

#include <cstdint>
#include <memory>

#include "gpu/context.h"
#include "gpu/recorder.h"
#include "render/frame_pipeline.h"
#include "render/gi_bridge.h"
#include "render/reference_renderer.h"
#include "scene/scene.h"
#include "viewer/panels.h"
#include "viewer/viewer.h"

namespace bounce::viewer {

class SplitView {
 public:
  SplitView(gpu::Context& context, const scene::Scene& scene, const ViewerOptions& options,
            render::FramePipeline& pipeline);

  // Switches from the split the panels show to `split`.
  void set(PanelState& panels, SplitMode split);
  // The second library's settings: it starts anew with them.
  void setOtherSettings(PanelState& panels, const gi::Settings& settings);
  // Before a frame: makes the reference once a frame exists to trace.
  // Returns the scene's time for the frame (`time`, or while the reference
  // shows the time it holds the scene still at).
  float prepare(const PanelState& panels, std::uint64_t framesRendered, float time);
  // After the pipeline's passes of frame `index` (`view`): records the
  // right half; returns its image, or null when the screen is not split.
  gpu::Image* record(gpu::Recorder& recorder, std::uint64_t index, const render::FrameView& view, PanelState& panels);

  render::ReferenceRenderer* reference() { return reference_.get(); }
  // Whether the reference reached a new power of two of samples (4, 8,
  // 16...: each halves its noise) since the last measure().
  bool dueForMeasure(const PanelState& panels) const;
  // relMSE and HDR-FLIP of `frame` against the reference, into the panels.
  void measure(PanelState& panels, gpu::Image& frame);

 private:
  gpu::Context& context_;
  const scene::Scene& scene_;
  const ViewerOptions& options_;
  render::FramePipeline& pipeline_;
  std::unique_ptr<render::ReferenceRenderer> reference_;
  scene::CameraPose referencePose_;
  bool referenceStale_ = true;
  float referenceTime_ = 0.0f;  // the scene stands still at this time while the reference shows
  std::uint64_t measuredAtSpp_ = 0;
  std::unique_ptr<render::GiBridge> other_;
  bool otherCut_ = true;
};

}  // namespace bounce::viewer
