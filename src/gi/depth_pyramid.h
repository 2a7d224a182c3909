// The frame's min-max depth pyramid, which Hi-Z traces march
// (shaders/gi/hiz_trace.glsl): built once a frame from gi.march_depth, after
// gi.store_history, and shared by every pass that traces this frame's depth.
//
// Level 0 is the render size, each next level max(1, floor(size / 2)) (as
// Vulkan's mips), down to 1x1; texel (i, j) of level k covers pixels
// [i 2^k, (i + 1) 2^k) x [j 2^k, (j + 1) 2^k), the last of a row or column
// reaching to the screen's edge. Per texel, over the pixels it covers:
//   x: the nearest surface's viewZ, 0 when all are background;
//   y: the farthest surface's viewZ, 0 when any is background.
// Level 0 is the march depth itself, (viewZ, viewZ) or (0, 0): the trace
// reads it there. Levels 1 and up are one rg32f image with a mip chain,
// "gi.depth_pyramid" (mip k - 1 for level k), sized for the largest render
// size; a render size uses levels(renderSize) - 1 of its mips.
//
// Passes (shaders in shaders/gi/):
//   gi.depth_pyramid         level 1 from gi.march_depth
//   gi.depth_pyramid_reduce  each further level from the one below (one dispatch a level)
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "gi/image_table.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"

namespace bounce::gi {

// Push constants of both passes: how much of the level read and of the
// level written this frame's render size fills.
struct DepthPyramidParams {
  std::uint32_t inputSize[2];
  std::uint32_t outputSize[2];
};

gpu::PassDesc depthPyramidPass();
gpu::PassDesc depthPyramidReducePass();
// gIn_DepthPyramid and gIn_DepthPyramidLevel0 as a tracing pass declares
// them (gi/hiz_trace.glsl).
std::vector<gpu::ResourceDecl> depthPyramidDecls();

class DepthPyramid {
 public:
  DepthPyramid(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize);
  ~DepthPyramid();
  // The bytes of device memory one made for `maxSize` holds (every mip level).
  static std::uint64_t memoryBytes(Extent maxSize);
  DepthPyramid(const DepthPyramid&) = delete;
  DepthPyramid& operator=(const DepthPyramid&) = delete;

  // Records the passes that build the pyramid of this frame's march depth
  // (gi.store_history's gOut_MarchDepth, r32f) at `renderSize`. Leaves the
  // image in GENERAL, also on frames whose stages are captured.
  void record(gpu::Recorder& recorder, gpu::Image& marchDepth, Extent renderSize);

  // Levels 1 and up (mip k - 1 for level k).
  gpu::Image& pyramid() { return *image_; }
  // What a tracing pass binds, nearest sampler: gIn_DepthPyramid (every
  // mip) and gIn_DepthPyramidLevel0, the march depth the last record()
  // built from (before any, the pyramid image, which a pass bound then
  // never reads: the specular trace with no steps).
  std::vector<gpu::Bind> binds() const;
  // Levels a render size uses, level 0 included: floor(log2(max(width, height))) + 1.
  static std::uint32_t levels(Extent renderSize);
  // The image as GiContext::images() lists it (its spec: name, format, how to view, purpose).
  ImageSet::Listed listed();
  static const ImageSpec& spec();
  // Every pass record() may record (for docs and tests).
  // Every pass the unit may record, debug views included (gi/unit_catalog.h).
  static std::vector<gpu::PassDesc> passes();

 private:
  gpu::Context& context_;
  std::unique_ptr<gpu::Image> image_;
  gpu::Image* level0_ = nullptr;  // the march depth of the last record()
  gpu::ComputePass build_;
  gpu::ComputePass reduce_;
};

struct UnitRegistration;
// The pyramid as a unit (gi/units.h): product "depth_pyramid", built on
// the frames a later unit takes it.
UnitRegistration depthPyramidUnit();

}  // namespace bounce::gi
