#include "gi/screen_tiles.h"

#include "gi/gi_shaders.h"
#include "gi/units.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

using gpu::Access;
using namespace gpu::formats;

enum ScreenTilesImage : std::size_t { kTiles, kBorder };

constexpr ImageSpec kImages[] = {
    {"gi.screen_tiles", Resolution::Tile, kRgba32f, false, gpu::Visualize::Radiance,
     "per 16x16 tile: the mean direct light of its pixels that show a surface, and how many there are; what "
     "screen-only mode gives rays that leave the screen there"},
    {"gi.screen_border", Resolution::Single, kRgba32f, false, gpu::Visualize::Radiance,
     "the mean direct light of the surface pixels of the screen's outermost ring, and the share of the ring that "
     "shows the sky; what screen-only mode gives rays that turn towards the camera"}};

// Both passes read the frame's depth and the engine's direct light and write `output`.
gpu::PassDesc directLightPass(const char* name, const char* shader, gpu::ResourceDecl output) {
  std::vector<gpu::ResourceDecl> resources = frameGroupDecls(GroupPart::Depth);
  resources.push_back({"gIn_Direct", Access::Read, VK_FORMAT_UNDEFINED, "the engine's direct light (and emission)",
                       gpu::ResourceKind::SampledImage});
  resources.push_back(std::move(output));
  return {.name = name,
          .shader = shader,
          .shaders = shaders(),
          .resources = std::move(resources),
          .constants = {frameConstantsLayout()}};
}

}  // namespace

gpu::PassDesc screenTilesPass() {
  return directLightPass(
      "gi.screen_tiles", "gi/screen_tiles",
      {"gOut_Tiles", Access::Write, kRgba32f, "per 16x16 tile: mean direct light of its surface pixels, their count"});
}

gpu::PassDesc screenBorderPass() {
  return directLightPass("gi.screen_border", "gi/screen_border",
                         {"gOut_Border", Access::Write, kRgba32f,
                          "one texel: the outermost ring's mean surface direct light, its sky share"});
}

std::vector<gpu::ResourceDecl> screenTilesDecls() {
  return {{"gIn_ScreenTiles", Access::Read, kRgba32f,
           "this frame's tiles (gi.screen_tiles): what screen-only mode gives rays that leave the screen"},
          {"gIn_ScreenBorder", Access::Read, kRgba32f,
           "this frame's border (gi.screen_border): what screen-only mode gives rays that turn towards the camera"}};
}

std::span<const ImageSpec> screenTilesImageTable() { return kImages; }

ScreenTiles::ScreenTiles(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize)
    : images_(context, arena, kImages, maxSize),
      tiles_(context, screenTilesPass()),
      border_(context, screenBorderPass()) {}

std::uint64_t ScreenTiles::memoryBytes(Extent maxSize) { return imageSetBytes(kImages, maxSize); }

void ScreenTiles::record(gpu::Recorder& recorder, const FrameGroup& group, gpu::Image& direct, VkSampler nearest,
                         Extent renderSize) {
  // One workgroup (16x16) a tile; one workgroup for the ring.
  recorder.dispatch(tiles_, renderSize.width, renderSize.height, group.binds(GroupPart::Depth),
                    {{"gIn_Direct", direct, nearest}, {"gOut_Tiles", images_.current(kTiles, 0)}});
  recorder.dispatch(border_, border_.localSize()[0], 1, group.binds(GroupPart::Depth),
                    {{"gIn_Direct", direct, nearest}, {"gOut_Border", images_.current(kBorder, 0)}});
}

std::vector<gpu::Bind> ScreenTiles::binds() {
  return {{"gIn_ScreenTiles", images_.current(kTiles, 0)}, {"gIn_ScreenBorder", images_.current(kBorder, 0)}};
}

std::vector<gpu::PassDesc> ScreenTiles::passes() { return {screenTilesPass(), screenBorderPass()}; }

namespace {

// Built on the frames a unit after it takes the tiles (a branch without a
// bridge that traces: screen-only mode).
class ScreenTilesUnit final : public OnDemandUnit {
 public:
  ScreenTilesUnit(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize)
      : OnDemandUnit(product::kScreenTiles), tiles_(context, arena, maxSize) {}
  std::string_view name() const override { return "screen_tiles"; }
  std::vector<ImageSet*> imageSets() override { return {&tiles_.images()}; }

 private:
  // For a pass that declares them but does not apply the policy this frame (a bridge traces).
  void putLastBuilt(Products& products, std::uint64_t) override { products.put(product::kScreenTiles, tiles_.binds()); }
  void build(const FrameState& frame) override {
    tiles_.record(frame.recorder, frame.group, frame.engine[Input::Direct], frame.nearestSampler, frame.renderSize);
    frame.products.put(product::kScreenTiles, tiles_.binds());
  }

  ScreenTiles tiles_;
};

}  // namespace

UnitRegistration screenTilesUnit() {
  return sizedUnit<ScreenTilesUnit>("screen_tiles", {std::string(product::kScreenTiles)}, &ScreenTiles::memoryBytes);
}

}  // namespace bounce::gi
