#include "gi/frame_constants.h"
#include "gi/frame_passes.h"
#include "gi/gi_shaders.h"
#include "gi/units.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

using namespace gpu::formats;

constexpr ImageSpec kFrameImages[] = {
    {"gi.history_surface", Resolution::Full, kRg32ui, true, gpu::Visualize::Raw,
     "viewZ bits, octahedral normal and material id of every pixel, for the next frame (and this frame's id)"},
    {"gi.march_depth", Resolution::Full, kR32f, false, gpu::Visualize::Range,
     "this frame's viewZ (0 where unusable) in the library's own storage image: what visibility marches read"},
    // One copy: the branches read last frame's before the composite, the
    // last unit of a frame, writes this frame's over it.
    {"gi.composite", Resolution::Full, kRgba16f, false, gpu::Visualize::Radiance,
     "the frame, linear HDR: direct light + remodulated indirect light; next frame's light source"},
};
// The history unit's images (the first two), then the composite's.
constexpr std::size_t kHistoryImageCount = 2;
enum HistoryImage : std::size_t { kHistorySurface, kMarchDepth };

// gi.store_history, first of every frame: the surfaces of this frame for
// the next, and the depth visibility marches read.
class HistoryUnit final : public Unit {
 public:
  HistoryUnit(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize)
      : images_(context, arena, historyImageTable(), maxSize), pass_(context, storeHistoryPass()) {}
  std::string_view name() const override { return "history"; }
  Plan plan(const FramePlan&) const override { return {.records = true}; }
  void record(const FrameState& frame) override {
    const std::uint64_t f = frame.frameIndex;
    EngineImages& engine = frame.engine;
    frame.recorder.dispatch(
        pass_, frame.renderSize.width, frame.renderSize.height, frame.group.binds(),
        {{"gOut_Surface", images_.current(kHistorySurface, f)},
         {"gOut_MarchDepth", images_.current(kMarchDepth, f)},
         // Not read without material ids (the constants say so): last frame's
         // surfaces, an unsigned-integer image, only fill the slot.
         {"gIn_MaterialId",
          engine.has(Input::MaterialId) ? engine[Input::MaterialId] : images_.previous(kHistorySurface, f),
          frame.nearestSampler}});
    frame.products.put(product::kSurface, images_.current(kHistorySurface, f));
    frame.products.put(product::kPreviousSurface, images_.previous(kHistorySurface, f));
    frame.products.put(product::kMarchDepth, images_.current(kMarchDepth, f));
  }
  std::vector<ImageSet*> imageSets() override { return {&images_}; }

 private:
  ImageSet images_;
  gpu::ComputePass pass_;
};

}  // namespace

std::span<const ImageSpec> frameImageTable() { return kFrameImages; }
std::span<const ImageSpec> historyImageTable() { return frameImageTable().first(kHistoryImageCount); }
std::span<const ImageSpec> compositeImageTable() { return frameImageTable().subspan(kHistoryImageCount); }

UnitRegistration historyUnit() {
  return sizedUnit<HistoryUnit>(
      "history",
      {std::string(product::kSurface), std::string(product::kPreviousSurface), std::string(product::kMarchDepth)},
      [](Extent maxSize) { return imageSetBytes(historyImageTable(), maxSize); });
}

gpu::PassDesc storeHistoryPass() {
  std::vector<gpu::ResourceDecl> resources = frameGroupDecls();
  resources.push_back({"gOut_Surface", gpu::Access::Write, gpu::formats::kRg32ui,
                       "this frame's viewZ, octahedral normal and material id, for the next"});
  // The engine's viewZ may be any format of its family and sampled only;
  // marches read this many times a pixel, and a storage image of the
  // library's own reads faster on GPUs than the engine's image through the
  // texture path (the resolve: 7 % on an H100).
  resources.push_back({"gOut_MarchDepth", gpu::Access::Write, gpu::formats::kR32f,
                       "this frame's viewZ, 0 where unusable, for visibility marches"});
  resources.push_back({"gIn_MaterialId", gpu::Access::Read, VK_FORMAT_UNDEFINED,
                       "the engine's material ids (any unsigned-integer format), when given",
                       gpu::ResourceKind::SampledImage});
  return {.name = "gi.store_history",
          .shader = "gi/store_history",
          .shaders = shaders(),
          .resources = std::move(resources),
          .constants = {frameConstantsLayout()}};
}

}  // namespace bounce::gi
