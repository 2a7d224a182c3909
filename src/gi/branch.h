// A GI branch: indirect diffuse or indirect specular. Each is
// a unit with its own image table (an ImageSet), its own constants and its
// own passes; GiContext records the frame's history, then each branch, then
// the composite, and knows nothing of what a branch does inside.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "gi/depth_pyramid.h"
#include "gi/engine_images.h"
#include "gi/frame_constants.h"
#include "gi/image_table.h"
#include "gi/screen_tiles.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"

namespace bounce::gi {

// What a branch gets to record one frame.
struct FrameState {
  gpu::Recorder& recorder;
  const FrameGroup& group;  // gIn_Frame, gIn_ViewZ, gIn_NormalRoughness
  EngineImages& engine;
  VkSampler environmentSampler;
  VkSampler nearestSampler;  // for the engine's images, read with texelFetch
  std::uint64_t frameIndex;
  Extent renderSize;
  bool hasHistory;     // last frame's images hold a frame (perhaps of another camera: a cut)
  bool usableHistory;  // ... and it may be reused (no cut, same render size)
  gpu::Image& previousComposite;  // last frame's composite: the light the next bounce gathers
  gpu::Image& previousSurface;    // last frame's viewZ, normals and material ids (gi.store_history)
  gpu::Image& currentSurface;     // this frame's: its material ids
  gpu::Image& marchDepth;         // this frame's viewZ as visibility marches read it (gi.store_history)
  // This frame's min-max pyramid of marchDepth, for Hi-Z traces: built when
  // a branch that traces it is on (GiContext::Impl::needsDepthPyramid).
  const DepthPyramid& depthPyramid;
  // Screen-only mode's tiles and border of this frame's direct light
  // (gi/screen_only_policy.glsl): built only where no bridge traces.
  ScreenTiles& screenTiles;
  // This frame's gi.light_change: the share of its history every temporal
  // history keeps after a change of light (gi/light_change/light_change.glsl).
  gpu::Image& lightChange;
  bool capturing;                 // this frame's stages are captured: debug passes run too
  // The denoiser takes the branches' resolved signals (resolved()): they
  // record no temporal filter of their own.
  bool denoised;
};

class Branch {
 public:
  virtual ~Branch() = default;
  virtual std::string_view name() const = 0;  // "diffuse": its passes and images are gi.diffuse.*
  virtual ImageSet& images() = 0;
  virtual void record(const FrameState& frame) = 0;
  // This frame's result, which the composite reads (demodulated radiance)
  // when the denoiser is off.
  virtual gpu::Image& result(std::uint64_t frameIndex) = 0;
  // Last frame's result (what the radiance cache is filled from when no
  // denoiser takes the signal).
  virtual gpu::Image& previousResult(std::uint64_t frameIndex) = 0;
  // Whether this frame's passes march the depth pyramid (Hi-Z traces):
  // GiContext builds it only for a branch that does.
  virtual bool marchesDepthPyramid() const { return false; }
  // This frame's resolved signal before the branch's own temporal filter
  // (rgba16f: demodulated radiance, hit distance or 0): what the denoiser
  // takes; with the denoiser on, the branch records no temporal filter.
  virtual gpu::Image& resolved(std::uint64_t frameIndex) = 0;
};

}  // namespace bounce::gi
