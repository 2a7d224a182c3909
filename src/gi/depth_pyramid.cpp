#include "gi/depth_pyramid.h"

#include <algorithm>

#include "gi/gi_shaders.h"
#include "gi/units.h"
#include "gpu/constants_layout.h"
#include "gpu/context.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

using gpu::Access;
using namespace gpu::formats;

constexpr ImageSpec kPyramidSpec{
    "gi.depth_pyramid",
    Resolution::Half,
    kRg32f,
    false,
    gpu::Visualize::Range,
    "min-max depth pyramid of gi.march_depth (level 0, read there), levels 1 and up, one mip a level: nearest "
    "surface viewZ (0: all background), farthest (0: some background); what Hi-Z traces march"};

// The pyramid image: level 1 of `maxSize` and its mips (one at least, for a 1x1 render size).
Extent imageSize(Extent maxSize) { return {std::max(1u, maxSize.width >> 1), std::max(1u, maxSize.height >> 1)}; }
std::uint32_t imageLevels(Extent maxSize) { return std::max(1u, DepthPyramid::levels(maxSize) - 1); }

gpu::ConstantsDecl paramsLayout() { return BOUNCE_CONSTANTS_LAYOUT("", DepthPyramidParams, inputSize, outputSize); }

Extent levelSize(Extent renderSize, std::uint32_t level) {
  return {std::max(1u, renderSize.width >> level), std::max(1u, renderSize.height >> level)};
}

}  // namespace

gpu::PassDesc depthPyramidPass() {
  return {.name = "gi.depth_pyramid",
          .shader = "gi/depth_pyramid",
          .shaders = shaders(),
          .resources = {{"gIn_MarchDepth", Access::Read, kR32f, "this frame's viewZ, 0 where unusable: level 0"},
                        {"gOut_DepthPyramid", Access::Write, kRg32f,
                         "level 1 (the image's mip 0): nearest and farthest surface of each 2x2 pixels (3 wide at "
                         "an odd edge)"}},
          .constants = {paramsLayout()}};
}

gpu::PassDesc depthPyramidReducePass() {
  return {.name = "gi.depth_pyramid_reduce",
          .shader = "gi/depth_pyramid_reduce",
          .shaders = shaders(),
          .resources = {{"gIn_Finer", Access::Read, kRg32f, "the level below"},
                        {"gOut_DepthPyramid", Access::Write, kRg32f,
                         "the next level: nearest and farthest surface of each 2x2 (3 wide at an odd edge)"}},
          .constants = {paramsLayout()}};
}

std::vector<gpu::ResourceDecl> depthPyramidDecls() {
  return {{"gIn_DepthPyramid", Access::Read, VK_FORMAT_UNDEFINED,
           "this frame's min-max depth pyramid (gi.depth_pyramid), levels 1 and up", gpu::ResourceKind::SampledImage},
          {"gIn_DepthPyramidLevel0", Access::Read, VK_FORMAT_UNDEFINED,
           "the pyramid's level 0: this frame's march depth", gpu::ResourceKind::SampledImage}};
}

DepthPyramid::DepthPyramid(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize)
    : context_(context),
      image_(std::make_unique<gpu::Image>(context,
                                          gpu::ImageDesc{.name = std::string(kPyramidSpec.name),
                                                         .width = imageSize(maxSize).width,
                                                         .height = imageSize(maxSize).height,
                                                         .format = kPyramidSpec.format,
                                                         .visualize = kPyramidSpec.view,
                                                         .mipLevels = imageLevels(maxSize)},
                                          &arena)),
      build_(context, depthPyramidPass()),
      reduce_(context, depthPyramidReducePass()) {}

DepthPyramid::~DepthPyramid() = default;

std::uint64_t DepthPyramid::memoryBytes(Extent maxSize) {
  const Extent size = imageSize(maxSize);
  std::uint64_t total = 0;
  for (std::uint32_t mip = 0; mip < imageLevels(maxSize); ++mip)
    total += std::uint64_t(std::max(size.width >> mip, 1u)) * std::max(size.height >> mip, 1u) *
             gpu::formatInfo(kPyramidSpec.format).bytesPerPixel;
  return total;
}

std::uint32_t DepthPyramid::levels(Extent renderSize) {
  std::uint32_t levels = 1;
  while ((std::max(renderSize.width, renderSize.height) >> levels) > 0) ++levels;
  return levels;
}

void DepthPyramid::record(gpu::Recorder& recorder, gpu::Image& marchDepth, Extent renderSize) {
  gpu::Image& pyramid = *image_;
  level0_ = &marchDepth;
  // Level k is the image's mip k - 1; a 1x1 render size has level 0 alone.
  const std::uint32_t count = levels(renderSize);
  for (std::uint32_t level = 1; level < count; ++level) {
    const Extent below = levelSize(renderSize, level - 1);
    const Extent size = levelSize(renderSize, level);
    const DepthPyramidParams params{{below.width, below.height}, {size.width, size.height}};
    if (level == 1)
      recorder.dispatch(build_, size.width, size.height,
                        {{"gIn_MarchDepth", marchDepth}, {"gOut_DepthPyramid", pyramid, gpu::MipLevel{0}}}, params);
    else
      recorder.dispatch(reduce_, size.width, size.height,
                        {{"gIn_Finer", pyramid, gpu::MipLevel{level - 2}},
                         {"gOut_DepthPyramid", pyramid, gpu::MipLevel{level - 1}}},
                        params);
  }
  // Stage copies moved it to a transfer layout; GiContext::images() promises GENERAL.
  if (recorder.capturing() && pyramid.sync().layout != VK_IMAGE_LAYOUT_GENERAL)
    recorder.handOver(pyramid, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

std::vector<gpu::Bind> DepthPyramid::binds() const {
  return {{"gIn_DepthPyramid", *image_, context_.nearestSampler()},
          {"gIn_DepthPyramidLevel0", level0_ ? *level0_ : *image_, context_.nearestSampler()}};
}

ImageSet::Listed DepthPyramid::listed() { return {std::string(kPyramidSpec.name), image_.get(), &kPyramidSpec}; }

const ImageSpec& DepthPyramid::spec() { return kPyramidSpec; }

std::vector<gpu::PassDesc> DepthPyramid::passes() { return {depthPyramidPass(), depthPyramidReducePass()}; }

namespace {

// Built on the frames a unit after it takes the pyramid (a branch's Hi-Z trace).
class DepthPyramidUnit final : public OnDemandUnit {
 public:
  DepthPyramidUnit(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize)
      : OnDemandUnit(product::kDepthPyramid), pyramid_(context, arena, maxSize) {}
  std::string_view name() const override { return "depth_pyramid"; }

 private:
  std::vector<std::string> takes() const override { return {std::string(product::kMarchDepth)}; }
  // For the specular trace with trace_steps 0, which declares it but does not march it.
  void putLastBuilt(Products& products, std::uint64_t) override {
    products.put(product::kDepthPyramid, pyramid_.binds());
  }
  void build(const FrameState& frame) override {
    pyramid_.record(frame.recorder, frame.products.image(product::kMarchDepth), frame.renderSize);
    frame.products.put(product::kDepthPyramid, pyramid_.binds());
  }
  std::vector<ImageSet::Listed> listBuilt(std::uint64_t) override { return {pyramid_.listed()}; }

  DepthPyramid pyramid_;
};

}  // namespace

UnitRegistration depthPyramidUnit() {
  return sizedUnit<DepthPyramidUnit>("depth_pyramid", {std::string(product::kDepthPyramid)},
                                     &DepthPyramid::memoryBytes);
}

}  // namespace bounce::gi
