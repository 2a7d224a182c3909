#include "gi/light_change.h"

#include "gi/gi_shaders.h"
#include "gi/pass_decls.h"
#include "gi/units.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

using gpu::Access;
using namespace gpu::formats;

enum LightChangeImage : std::size_t { kDirect, kTiles, kVerdict };

constexpr ImageSpec kImages[] = {
    {"gi.light_change.direct", Resolution::Full, kR32f, true, gpu::Visualize::Radiance,
     "each surface pixel's direct light and emission as luminance (0 elsewhere): what the next frame compares with"},
    {"gi.light_change.tiles", Resolution::Tile, kRgba32f, false, gpu::Visualize::Range,
     "per 16x16 tile: the summed absolute changes of its 4x4 blocks' light since last frame, the summed larger "
     "light, the pixels compared"},
    {"gi.light_change", Resolution::Single, kRgba32f, true, gpu::Visualize::Raw,
     "the share of the frame's direct light that changed since last frame, last frame's share, the share of its "
     "history every temporal history keeps, the most frames a screen history may hold"}};

}  // namespace

gpu::PassDesc lightChangeTilesPass() {
  return framePass(
      "gi.light_change.tiles", "gi/light_change/tiles", GroupPart::Surfaces,
      {{"gIn_Direct", Access::Read, VK_FORMAT_UNDEFINED, "the engine's direct light", gpu::ResourceKind::SampledImage},
       {"gIn_Emissive", Access::Read, VK_FORMAT_UNDEFINED,
        "the engine's emission, when it gives it apart (else bound only to fill the slot)",
        gpu::ResourceKind::SampledImage},
       motionDecl(),
       previousSurfaceDecl(),
       {"gPrev_Direct", Access::Read, kR32f, "last frame's gi.light_change.direct"},
       {"gOut_Direct", Access::Write, kR32f, "this frame's direct light as luminance"},
       {"gOut_Tiles", Access::Write, kRgba32f, "per tile: summed block changes, summed light, pixels compared"},
       currentSurfaceDecl()});
}

gpu::PassDesc lightChangeFramePass() {
  return framePass("gi.light_change.frame", "gi/light_change/frame", GroupPart::Constants,
                   {{"gIn_Tiles", Access::Read, kRgba32f, "this frame's gi.light_change.tiles"},
                    {"gPrev_LightChange", Access::Read, kRgba32f, "last frame's verdict: its share of light changed"},
                    {"gOut_LightChange", Access::Write, kRgba32f,
                     "the share changed, last frame's, the share of history kept, the hold"}});
}

gpu::ResourceDecl lightChangeDecl() {
  return {"gIn_LightChange", Access::Read, kRgba32f,
          "this frame's gi.light_change: z the share of its history a temporal history keeps after a change of "
          "light"};
}

std::span<const ImageSpec> lightChangeImageTable() { return kImages; }

LightChange::LightChange(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize)
    : images_(context, arena, kImages, maxSize),
      tiles_(context, lightChangeTilesPass()),
      frame_(context, lightChangeFramePass()) {}

std::uint64_t LightChange::memoryBytes(Extent maxSize) { return imageSetBytes(kImages, maxSize); }

void LightChange::record(gpu::Recorder& recorder, const FrameGroup& group, EngineImages& engine,
                         gpu::Image& previousSurface, gpu::Image& currentSurface, VkSampler nearest,
                         std::uint64_t frameIndex, Extent renderSize) {
  gpu::Image& direct = engine[Input::Direct];
  recorder.dispatch(tiles_, renderSize.width, renderSize.height, group.binds(),
                    {{"gIn_Direct", direct, nearest},
                     {"gIn_Emissive", engine.has(Input::Emissive) ? engine[Input::Emissive] : direct, nearest},
                     {"gIn_Motion", engine[Input::Motion], nearest},
                     {"gPrev_Surface", previousSurface},
                     {"gPrev_Direct", images_.previous(kDirect, frameIndex)},
                     {"gOut_Direct", images_.current(kDirect, frameIndex)},
                     {"gOut_Tiles", images_.current(kTiles, frameIndex)},
                     {"gIn_Surface", currentSurface}});
  recorder.dispatch(frame_, frame_.localSize()[0], 1, group.binds(GroupPart::Constants),
                    {{"gIn_Tiles", images_.current(kTiles, frameIndex)},
                     {"gPrev_LightChange", images_.previous(kVerdict, frameIndex)},
                     {"gOut_LightChange", images_.current(kVerdict, frameIndex)}});
}

gpu::Image& LightChange::verdict(std::uint64_t frameIndex) { return images_.current(kVerdict, frameIndex); }

std::vector<gpu::PassDesc> LightChange::passes() { return {lightChangeTilesPass(), lightChangeFramePass()}; }

namespace {

// Recorded on the frames a unit after it takes the verdict (every unit with
// a temporal history).
class LightChangeUnit final : public OnDemandUnit {
 public:
  LightChangeUnit(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize)
      : OnDemandUnit(product::kLightChange), change_(context, arena, maxSize) {}
  std::string_view name() const override { return "light_change"; }
  std::vector<ImageSet*> imageSets() override { return {&change_.images()}; }

 private:
  std::vector<std::string> takes() const override {
    return {std::string(product::kSurface), std::string(product::kPreviousSurface)};
  }
  void build(const FrameState& frame) override {
    change_.record(frame.recorder, frame.group, frame.engine, frame.products.image(product::kPreviousSurface),
                   frame.products.image(product::kSurface), frame.nearestSampler, frame.frameIndex, frame.renderSize);
    frame.products.put(product::kLightChange, change_.verdict(frame.frameIndex));
  }

  LightChange change_;
};

}  // namespace

UnitRegistration lightChangeUnit() {
  return sizedUnit<LightChangeUnit>("light_change", {std::string(product::kLightChange)}, &LightChange::memoryBytes);
}

}  // namespace bounce::gi
