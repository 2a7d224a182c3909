// The screen's tiles and border: what screen-only mode (no scene bridge
// that traces) gives a ray that leaves the screen before screen space can
// decide it (shaders/gi/screen_only_policy.glsl, docs/gi.md "Screen-only
// mode"). Built from the engine's direct light before the branches;
// recorded only where no bridge traces.
//
// Images (an ImageSet of its own):
//   gi.screen_tiles   one texel per 16x16 tile: mean direct light of its surface pixels (rgb), their count (a)
//   gi.screen_border  one texel: mean direct light of the surface pixels of the screen's outermost ring (rgb),
//                     the share of the ring that shows the sky (a)
// Passes (shaders in shaders/gi/):
//   gi.screen_tiles   one workgroup a tile, summed as a tree
//   gi.screen_border  one workgroup for the ring, summed in a fixed order
// (the same bits every run).
#pragma once

#include <span>
#include <vector>

#include "gi/frame_constants.h"
#include "gi/image_table.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"

namespace bounce::gi {

gpu::PassDesc screenTilesPass();
gpu::PassDesc screenBorderPass();
// gIn_ScreenTiles and gIn_ScreenBorder as a pass that applies the screen-only policy declares them.
std::vector<gpu::ResourceDecl> screenTilesDecls();
std::span<const ImageSpec> screenTilesImageTable();

class ScreenTiles {
 public:
  ScreenTiles(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize);
  static std::uint64_t memoryBytes(Extent maxSize);

  // Records both passes over the engine's direct light (`direct`, read with
  // `nearest`); `group`: the frame's constants and depth (which pixels show
  // a surface).
  void record(gpu::Recorder& recorder, const FrameGroup& group, gpu::Image& direct, VkSampler nearest,
              Extent renderSize);
  // What a pass applying the policy binds: gIn_ScreenTiles, gIn_ScreenBorder.
  std::vector<gpu::Bind> binds();
  ImageSet& images() { return images_; }
  // Every pass record() records (for docs and tests).
  // Every pass the unit may record, debug views included (gi/unit_catalog.h).
  static std::vector<gpu::PassDesc> passes();

 private:
  ImageSet images_;
  gpu::ComputePass tiles_;
  gpu::ComputePass border_;
};

struct UnitRegistration;
// The tiles as a unit (gi/units.h): product "screen_tiles", built on the
// frames a later unit takes them.
UnitRegistration screenTilesUnit();

}  // namespace bounce::gi
