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
    Resolution::Full,
    kRg32f,
    false,
    gpu::Visualize::Range,
    "min-max depth pyramid of gi.march_depth, one mip a level: nearest surface viewZ (0: all background), "
    "farthest (0: some background); what Hi-Z traces march"};

gpu::ConstantsDecl paramsLayout() { return BOUNCE_CONSTANTS_LAYOUT("", DepthPyramidParams, inputSize, outputSize); }

Extent levelSize(Extent renderSize, std::uint32_t level) {
  return {std::max(1u, renderSize.width >> level), std::max(1u, renderSize.height >> level)};
}

}  // namespace

gpu::PassDesc depthPyramidPass() {
  return {.name = "gi.depth_pyramid",
          .shader = "gi/depth_pyramid",
          .shaders = shaders(),
          .resources = {{"gIn_MarchDepth", Access::Read, kR32f, "this frame's viewZ, 0 where unusable"},
                        {"gOut_DepthPyramid", Access::Write, kRg32f,
                         "level 0: (viewZ, viewZ) of each pixel, (0, 0) for background"}},
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

gpu::ResourceDecl depthPyramidDecl() {
  return {"gIn_DepthPyramid", Access::Read, VK_FORMAT_UNDEFINED,
          "this frame's min-max depth pyramid (gi.depth_pyramid), every level", gpu::ResourceKind::SampledImage};
}

DepthPyramid::DepthPyramid(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize)
    : context_(context),
      image_(std::make_unique<gpu::Image>(context,
                                          gpu::ImageDesc{.name = std::string(kPyramidSpec.name),
                                                         .width = maxSize.width,
                                                         .height = maxSize.height,
                                                         .format = kPyramidSpec.format,
                                                         .visualize = kPyramidSpec.view,
                                                         .mipLevels = levels(maxSize)},
                                          &arena)),
      build_(context, depthPyramidPass()),
      reduce_(context, depthPyramidReducePass()) {}

DepthPyramid::~DepthPyramid() = default;

std::uint64_t DepthPyramid::memoryBytes(Extent maxSize) {
  std::uint64_t total = 0;
  for (std::uint32_t level = 0; level < levels(maxSize); ++level)
    total += std::uint64_t(std::max(maxSize.width >> level, 1u)) * std::max(maxSize.height >> level, 1u) *
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
  recorder.dispatch(build_, renderSize.width, renderSize.height,
                    {{"gIn_MarchDepth", marchDepth}, {"gOut_DepthPyramid", pyramid, gpu::MipLevel{0}}},
                    DepthPyramidParams{{renderSize.width, renderSize.height}, {renderSize.width, renderSize.height}});
  const std::uint32_t count = levels(renderSize);
  for (std::uint32_t level = 1; level < count; ++level) {
    const Extent below = levelSize(renderSize, level - 1);
    const Extent size = levelSize(renderSize, level);
    recorder.dispatch(
        reduce_, size.width, size.height,
        {{"gIn_Finer", pyramid, gpu::MipLevel{level - 1}}, {"gOut_DepthPyramid", pyramid, gpu::MipLevel{level}}},
        DepthPyramidParams{{below.width, below.height}, {size.width, size.height}});
  }
  // Stage copies moved it to a transfer layout; GiContext::images() promises GENERAL.
  if (recorder.capturing() && pyramid.sync().layout != VK_IMAGE_LAYOUT_GENERAL)
    recorder.handOver(pyramid, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

gpu::Bind DepthPyramid::bind() const { return {"gIn_DepthPyramid", *image_, context_.nearestSampler()}; }

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
    products.put(product::kDepthPyramid, std::vector<gpu::Bind>{pyramid_.bind()});
  }
  void build(const FrameState& frame) override {
    pyramid_.record(frame.recorder, frame.products.image(product::kMarchDepth), frame.renderSize);
    frame.products.put(product::kDepthPyramid, std::vector<gpu::Bind>{pyramid_.bind()});
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
