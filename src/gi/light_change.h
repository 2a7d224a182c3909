// The light change: how much of the light the engine hands over changed
// since last frame, and so how much of its history every temporal history
// keeps this frame (shaders/gi/light_change/light_change.glsl; docs/gi.md
// "When the light changes"). Recorded before the cache and the branches
// in every frame that runs a branch or the denoiser, from the engine's
// direct light and emission.
//
// Images (an ImageSet of its own):
//   gi.light_change.direct  full, history: each surface pixel's direct light (luminance), for the next frame
//   gi.light_change.tiles   one texel per 16x16 tile: the summed changes of its 4x4 blocks, the light, pixels compared
//   gi.light_change         one texel, history: the share of the light that changed, last frame's share,
//                           the share of history kept, the most frames a screen history may hold
// Passes (shaders in shaders/gi/light_change/):
//   gi.light_change.tiles   one workgroup a tile, summed as a tree
//   gi.light_change.frame   one workgroup for the frame, summed in a fixed order
// (the same bits every run).
#pragma once

#include <span>
#include <vector>

#include "gi/engine_images.h"
#include "gi/frame_constants.h"
#include "gi/image_table.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"

namespace bounce::gi {

gpu::PassDesc lightChangeTilesPass();
gpu::PassDesc lightChangeFramePass();
// gIn_LightChange as a pass whose history follows a change of light declares it.
gpu::ResourceDecl lightChangeDecl();
std::span<const ImageSpec> lightChangeImageTable();

class LightChange {
 public:
  LightChange(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize);
  static std::uint64_t memoryBytes(Extent maxSize);

  // Records both passes for frame `frameIndex` (the history images' index):
  // `group` the frame's constants and surfaces; `previousSurface` and
  // `currentSurface` last frame's and this frame's gi.history_surface (its
  // material ids); the engine's direct light, emission (bound in its place
  // when the engine gives none) and motion.
  void record(gpu::Recorder& recorder, const FrameGroup& group, EngineImages& engine, gpu::Image& previousSurface,
              gpu::Image& currentSurface, VkSampler nearest, std::uint64_t frameIndex, Extent renderSize);
  // This frame's verdict (gi.light_change), which passes bind as gIn_LightChange.
  gpu::Image& verdict(std::uint64_t frameIndex);
  ImageSet& images() { return images_; }
  // Every pass the unit may record, debug views included (gi/unit_catalog.h).
  static std::vector<gpu::PassDesc> passes();

 private:
  ImageSet images_;
  gpu::ComputePass tiles_;
  gpu::ComputePass frame_;
};

struct UnitRegistration;
// The light change as a unit (gi/units.h): product "light_change", recorded
// on the frames a later unit takes it.
UnitRegistration lightChangeUnit();

}  // namespace bounce::gi
