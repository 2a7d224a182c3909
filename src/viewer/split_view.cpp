#include "viewer/split_view.h"

#include <cstdio>

#include "gpuio/gpu_images.h"
#include "metrics/image_metrics.h"
#include "viewer/fly_camera.h"

namespace bounce::viewer {
namespace {

// Samples per pixel the progressive reference adds each frame: few enough
// that the window stays interactive on a CPU device.
constexpr std::uint32_t kReferenceSamplesPerFrame = 1;

}  // namespace

SplitView::SplitView(gpu::Context& context, const scene::Scene& scene, const ViewerOptions& options,
                     render::FramePipeline& pipeline)
    : context_(context), scene_(scene), options_(options), pipeline_(pipeline) {}

void SplitView::set(PanelState& panels, SplitMode split) {
  if (split == SplitMode::Reference && panels.split != SplitMode::Reference) {
    referenceStale_ = true;
    referenceTime_ = pipeline_.previousView().time;
  }
  if (split != SplitMode::Other && other_) {
    pipeline_.finish();
    other_.reset();
  }
  panels.split = split;
}

void SplitView::setOtherSettings(PanelState& panels, const gi::Settings& settings) {
  panels.otherSettings = settings;
  pipeline_.finish();
  other_.reset();
}

float SplitView::prepare(const PanelState& panels, std::uint64_t framesRendered, float time) {
  const bool referenceShown = panels.split == SplitMode::Reference;
  // The reference traces the renderer's last frame, whose environment must
  // be built: it starts after the first frame.
  if (referenceShown && !reference_ && framesRendered > 0) {
    pipeline_.finish();
    reference_ =
        std::make_unique<render::ReferenceRenderer>(context_, pipeline_.renderer(), scene_, pipeline_.frameIndex(),
                                                    pipeline_.previousView().time, render::ReferenceOptions{});
    referenceStale_ = true;
  }
  return referenceShown ? referenceTime_ : time;
}

gpu::Image* SplitView::record(gpu::Recorder& recorder, std::uint64_t index, const render::FrameView& view,
                              PanelState& panels) {
  gpu::Image* right = nullptr;
  if (panels.split == SplitMode::GiOff) right = &pipeline_.renderer().direct();
  if (panels.split == SplitMode::Other && panels.mode != GiMode::Off) {
    // The same frame through a second library with the other settings.
    if (!other_) {
      other_ = std::make_unique<render::GiBridge>(
          context_, panels.mode == GiMode::Hybrid ? options_.hybrid : options_.screenOnly, panels.otherSettings);
      otherCut_ = true;
    }
    other_->record(recorder, pipeline_.renderer(), index, {view.camera, view.time, view.cut || otherCut_},
                   pipeline_.previousView());
    otherCut_ = false;
    right = &other_->composite();
  }
  if (panels.split == SplitMode::Reference && reference_) {
    // Accumulates while the camera and the materials stay; anything else starts it over.
    if (referenceStale_ || !samePose(view.camera, referencePose_) || reference_->materialsChanged()) {
      reference_->restart(recorder, index, view.time);
      referencePose_ = view.camera;
      referenceStale_ = false;
      measuredAtSpp_ = 0;
      panels.relMse.reset();
      panels.flip.reset();
    }
    reference_->record(recorder, kReferenceSamplesPerFrame);
    reference_->recordResolve(recorder);
    panels.referenceSpp = reference_->samplesPerPixel();
    right = &reference_->radianceImage();
  }
  return right;
}

bool SplitView::dueForMeasure(const PanelState& panels) const {
  const std::uint64_t spp = reference_ && panels.split == SplitMode::Reference ? reference_->samplesPerPixel() : 0;
  return spp >= 4 && (spp & (spp - 1)) == 0 && spp != measuredAtSpp_;
}

void SplitView::measure(PanelState& panels, gpu::Image& frame) {
  if (!reference_) return;
  pipeline_.finish();
  const io::ImageF reference = gpuio::readbackImage(context_, reference_->radianceImage());
  const io::ImageF shown = gpuio::readbackImage(context_, frame);
  const metrics::Comparison comparison = metrics::compareImages(reference, shown, {.flipMode = metrics::FlipMode::Hdr});
  panels.relMse = comparison.values.relMse;
  panels.flip = comparison.flip.mean;
  measuredAtSpp_ = reference_->samplesPerPixel();
  std::printf("against the reference (%llu spp): relMSE %.5g, HDR-FLIP %.5g\n",
              static_cast<unsigned long long>(measuredAtSpp_), *panels.relMse, *panels.flip);
}

}  // namespace bounce::viewer
