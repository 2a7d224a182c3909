// gi.engine_signal.SIGNAL: how an engine's own noisy signal reaches the
// denoiser (FrameInputs::noisy). The denoiser reads
// its input as a storage image in rgba16f, the format of the branches'
// resolved signals; an engine's image is sampled only and may be rgba32f,
// so one full-resolution pass copies it into an image of the library's,
// and drops non-finite values on the way (docs/gi.md, "Denoising an
// engine's own signals"). In checkerboard mode (gi.denoise.checkerboard)
// the engine's image is half as wide: the same pass unpacks it, marking the
// pixels without a sample for the denoiser's pre-pass to fill.
#include <memory>

#include "gi/frame_passes.h"
#include "gi/pass_decls.h"
#include "gi/units.h"
#include "gpu/constants_layout.h"
#include "gpu/format.h"
#include "shared/checkerboard.glsl"

namespace bounce::gi {
void addEngineSignalImage(ImageTableBuilder& table, const std::string& signal) {
  table.add("gi.engine_signal." + signal,
            {"", Resolution::Full, gpu::formats::kRgba16f, false, gpu::Visualize::Radiance,
             "the engine's noisy signal as the denoiser reads it: demodulated radiance, hit distance (-1: no "
             "sample, checkerboard mode)"});
}

gpu::PassDesc engineSignalPass(const std::string& signal) {
  gpu::PassDesc desc = framePass(
      "gi.engine_signal." + signal, "gi/engine_signal", GroupPart::Constants,
      {{"gIn_Noisy", gpu::Access::Read, VK_FORMAT_UNDEFINED,
        "the engine's noisy signal: demodulated radiance, hit distance (world units, 0 unknown); in checkerboard "
        "mode half as wide, the pixels with a sample packed",
        gpu::ResourceKind::SampledImage},
       {"gOut_Signal", gpu::Access::Write, gpu::formats::kRgba16f,
        "the same, finite, full width: what the denoiser reads (checkerboard: hit distance -1 where no sample)"}});
  desc.constants.push_back(BOUNCE_CONSTANTS_LAYOUT("", EngineSignalParams, checkerboard, dataParity));
  return desc;
}

namespace {

// The engine's own noisy signals, taken in for the denoiser: SIGNAL.noisy
// for each signal the engine gives this frame.
class EngineSignalUnit final : public Unit {
 public:
  EngineSignalUnit(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize, std::span<const SignalDesc> signals,
                   bool checkerboard)
      : context_(context),
        arena_(arena),
        maxSize_(maxSize),
        signals_(signals.begin(), signals.end()),
        checkerboard_(checkerboard) {}
  std::string_view name() const override { return "engine_signal"; }
  Plan plan(const FramePlan& frame) const override {
    return {.records = std::find(frame.given.begin(), frame.given.end(), true) != frame.given.end()};
  }
  void record(const FrameState& frame) override {
    makeImages();
    for (std::size_t signal = 0; signal < signals_.size(); ++signal) {
      if (!frame.given[signal]) continue;
      gpu::Image& taken = images_->current(signal, frame.frameIndex);
      const EngineSignalParams params{checkerboard_ ? 1u : 0u,
                                      shared::checkerboardParityOfKind(signals_[signal].kind == SignalKind::Specular)};
      frame.recorder.dispatch(
          *passes_[signal], frame.renderSize.width, frame.renderSize.height, frame.group.binds(GroupPart::Constants),
          {{"gIn_Noisy", *frame.engine.noisy(signal), frame.nearestSampler}, {"gOut_Signal", taken}}, params);
      frame.products.put(product::noisy(signals_[signal].name), taken);
    }
  }
  std::vector<ImageSet*> imageSets() override {
    return images_ ? std::vector<ImageSet*>{images_.get()} : std::vector<ImageSet*>{};
  }

 private:
  // The passes and images, made before the first frame that gives a
  // signal records anything: a context whose engine never does holds no
  // memory for them.
  void makeImages() {
    if (images_) return;
    for (const SignalDesc& signal : signals_) {
      addEngineSignalImage(table_, signal.name);
      passes_.push_back(std::make_unique<gpu::ComputePass>(context_, engineSignalPass(signal.name)));
    }
    images_ = std::make_unique<ImageSet>(context_, arena_, table_.specs(), maxSize_);
  }

  gpu::Context& context_;
  gpu::MemoryArena& arena_;
  Extent maxSize_;
  std::vector<SignalDesc> signals_;
  bool checkerboard_;  // gi.denoise.checkerboard: the engine's images are packed to half width
  ImageTableBuilder table_;
  std::unique_ptr<ImageSet> images_;
  std::vector<std::unique_ptr<gpu::ComputePass>> passes_;
};

}  // namespace

UnitRegistration engineSignalUnit() {
  return {.name = "engine_signal",
          .produces =
              [](const UnitSetup& setup) {
                std::vector<std::string> names;
                for (const SignalDesc& signal : setup.signals) names.push_back(product::noisy(signal.name));
                return names;
              },
          .make = [](const UnitSetup& setup, const UnitResources& resources) -> std::unique_ptr<Unit> {
            return std::make_unique<EngineSignalUnit>(resources.context, resources.arena, setup.maxSize, setup.signals,
                                                      setup.settings.denoise.checkerboard);
          },
          // Made on the first frame that gives a signal: not part of the estimate.
          .memoryBytes = [](const UnitSetup&) { return std::uint64_t(0); }};
}

}  // namespace bounce::gi
