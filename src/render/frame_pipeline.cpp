#include "render/frame_pipeline.h"

#include <stdexcept>

namespace bounce::render {

FramePipeline::FramePipeline(gpu::Context& context, const scene::Scene& scene, const FramePipelineDesc& desc)
    : context_(context),
      renderer_(context, scene, desc.renderer),
      gi_(desc.gi ? std::make_unique<GiBridge>(context, desc.gi->first, desc.gi->second) : nullptr),
      loop_(context, FrameRenderer::kFramesInFlight),
      giFrame_(desc.giFrame) {}

FramePipeline::~FramePipeline() = default;

gpu::Recorder& FramePipeline::begin(const FrameView& view, const PipelineFrameOptions& options) {
  if (open_) throw std::logic_error("FramePipeline::begin: the frame begun before was not ended");
  gpu::Recorder& recorder = loop_.beginFrame(options.captureStages);
  const std::uint64_t index = loop_.frameIndex();
  current_ = view;
  renderer_.record(recorder, index, current_);
  if (gi_ && options.gi) {
    GiFrameOptions giOptions = giFrame_;
    giOptions.captureStages = options.captureStages;
    gi_->record(recorder, renderer_, index, current_, previous_, giOptions);
  }
  open_ = true;
  return recorder;
}

void FramePipeline::end() {
  if (!open_) throw std::logic_error("FramePipeline::end: no frame was begun");
  loop_.endFrame();
  previous_ = current_;
  open_ = false;
  ++frames_;
}

std::uint64_t FramePipeline::frame(const FrameView& view, const PipelineFrameOptions& options) {
  begin(view, options);
  const std::uint64_t index = loop_.frameIndex();
  end();
  return index;
}

void FramePipeline::setGi(const std::optional<std::pair<gi::ContextDesc, gi::Settings>>& gi) {
  if (open_) throw std::logic_error("FramePipeline::setGi: a frame is being recorded");
  loop_.finish();
  gi_.reset();
  if (gi) gi_ = std::make_unique<GiBridge>(context_, gi->first, gi->second);
}

gpu::Image& FramePipeline::frameImage() { return gi_ ? gi_->composite() : renderer_.direct(); }

}  // namespace bounce::render
