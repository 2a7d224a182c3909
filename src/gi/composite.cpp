#include "gi/frame_constants.h"
#include "gi/frame_passes.h"
#include "gi/gi_shaders.h"
#include "gi/units.h"
#include "gpu/format.h"

namespace bounce::gi {

gpu::PassDesc compositePass() {
  using gpu::Access;
  using gpu::ResourceKind;
  std::vector<gpu::ResourceDecl> resources = frameGroupDecls(GroupPart::Surfaces);
  resources.insert(
      resources.end(),
      {{"gIn_Direct", Access::Read, VK_FORMAT_UNDEFINED, "the engine's direct light (and emission), sky behind",
        ResourceKind::SampledImage},
       {"gIn_BaseColorMetallic", Access::Read, VK_FORMAT_UNDEFINED, "remodulation of indirect diffuse and specular",
        ResourceKind::SampledImage},
       {"gIn_Emissive", Access::Read, VK_FORMAT_UNDEFINED, "emission, when given apart", ResourceKind::SampledImage},
       // Sampled, so that any float format reads: the denoiser's results
       // are rgba16f, the branches' own filters' rgba32f.
       {"gIn_IndirectDiffuse", Access::Read, VK_FORMAT_UNDEFINED, "the diffuse signal's result",
        ResourceKind::SampledImage},
       {"gIn_IndirectSpecular", Access::Read, VK_FORMAT_UNDEFINED, "the specular signal's result",
        ResourceKind::SampledImage},
       {"gOut_Composite", Access::Write, gpu::formats::kRgba16f, "the frame, linear HDR; next frame's light source"}});
  return {.name = "gi.composite",
          .shader = "gi/composite",
          .shaders = shaders(),
          .resources = std::move(resources),
          .constants = {frameConstantsLayout()}};
}

namespace {

// gi.composite, last of every frame: the engine's direct light and the
// library's two signals, remodulated, into the frame (the next frame's light).
class CompositeUnit final : public Unit {
 public:
  CompositeUnit(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize)
      : images_(context, arena, compositeImageTable(), maxSize), pass_(context, compositePass()) {}
  std::string_view name() const override { return "composite"; }
  Plan plan(const FramePlan&) const override {
    return {.records = true, .takes = {kLibrarySignals[0].name, kLibrarySignals[1].name}};
  }
  // Last frame's composite, until this frame's composite overwrites it:
  // every unit that takes it records before this one.
  void putHistory(Products& products, std::uint64_t frameIndex) override {
    products.put(product::kPreviousComposite, images_.current(0, frameIndex));
  }
  void record(const FrameState& frame) override {
    EngineImages& engine = frame.engine;
    gpu::Image& direct = engine[Input::Direct];
    const VkSampler nearest = frame.nearestSampler;
    gpu::Image& composite = images_.current(0, frame.frameIndex);
    frame.recorder.dispatch(pass_, frame.renderSize.width, frame.renderSize.height,
                            frame.group.binds(GroupPart::Surfaces),
                            {{"gIn_Direct", direct, nearest},
                             {"gIn_BaseColorMetallic", engine[Input::BaseColorMetallic], nearest},
                             // Not read without an emissive image (the constants say so); bound only to fill the slot.
                             {"gIn_Emissive", engine.has(Input::Emissive) ? engine[Input::Emissive] : direct, nearest},
                             {"gIn_IndirectDiffuse", frame.products.image(kLibrarySignals[0].name), nearest},
                             {"gIn_IndirectSpecular", frame.products.image(kLibrarySignals[1].name), nearest},
                             {"gOut_Composite", composite}});
    frame.products.put(product::kComposite, composite);
  }
  std::vector<ImageSet*> imageSets() override { return {&images_}; }

 private:
  ImageSet images_;
  gpu::ComputePass pass_;
};

}  // namespace

UnitRegistration compositeUnit() {
  return sizedUnit<CompositeUnit>("composite",
                                  {std::string(product::kComposite), std::string(product::kPreviousComposite)},
                                  [](Extent maxSize) { return imageSetBytes(compositeImageTable(), maxSize); });
}

}  // namespace bounce::gi
