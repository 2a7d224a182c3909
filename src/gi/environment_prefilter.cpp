// gi::EnvironmentPrefilter: the engine's equirectangular environment as the
// library reads it. Passes (recorded by each record()):
//   gi.environment.downsample  the input resampled to the output's size (chain level 0),
//                              then the source's box-filtered chain, one level per dispatch
//   gi.environment.prefilter   the GGX-prefiltered chain, one level per dispatch
//
// The box-filtered chain alternates between two images: chain level 2j is
// mip 2j of source[0] and level 2j + 1 is mip 2j of source[1] (half the
// size), so that every downsample dispatch reads one image and writes
// another. A dispatch that binds one image twice (read one level, write the
// next) gets two barriers in one batch that do not order against each other
// when the image needs a layout transition (after a stage capture), which
// synchronization validation rightly reports. The odd mips of both stay unused.
#include "gi/environment_prefilter.h"

#include <algorithm>
#include <memory>
#include <string>

#include "bounce/gi.h"
#include "gi/engine_images.h"
#include "gi/gi_shaders.h"
#include "gi/library_device.h"
#include "gi/pass_log.h"
#include "gpu/constants_layout.h"
#include "gpu/error.h"
#include "gpu/format.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"

namespace bounce::gi {
namespace {

using gpu::Access;
using gpu::ResourceKind;

struct PrefilterParams {
  std::uint32_t level = 0;
  std::uint32_t mipCount = 1;
  std::uint32_t sampleCount = 1;
  std::uint32_t sourceLevels = 1;
};

gpu::PassDesc downsampleDesc() {
  return {.name = "gi.environment.downsample",
          .shader = "gi/environment/downsample",
          .shaders = shaders(),
          .resources = {{"gIn_Source", Access::Read, VK_FORMAT_UNDEFINED,
                         "the engine's equirect (for level 0), else one level of the source chain",
                         ResourceKind::SampledImage},
                        {"gOut_Destination", Access::Write, VK_FORMAT_R16G16B16A16_SFLOAT,
                         "the next level, solid-angle-weighted box filter"}}};
}

gpu::PassDesc prefilterDesc() {
  return {.name = "gi.environment.prefilter",
          .shader = "gi/environment/prefilter",
          .shaders = shaders(),
          .resources = {{"gIn_SourceEven", Access::Read, VK_FORMAT_UNDEFINED,
                         "even levels of the box-filtered source chain", ResourceKind::SampledImage},
                        {"gIn_SourceOdd", Access::Read, VK_FORMAT_UNDEFINED,
                         "odd levels of the box-filtered source chain", ResourceKind::SampledImage},
                        {"gOut_Radiance", Access::Write, VK_FORMAT_R16G16B16A16_SFLOAT,
                         "one level of the GGX-prefiltered chain"}},
          .constants = {BOUNCE_CONSTANTS_LAYOUT("", PrefilterParams, level, mipCount, sampleCount, sourceLevels)}};
}

std::uint32_t fullMipCount(std::uint32_t width, std::uint32_t height) {
  std::uint32_t levels = 1;
  while ((std::max(width, height) >> levels) > 0) ++levels;
  return levels;
}

constexpr VkFormat kEquirectFormats[] = {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT};

}  // namespace

std::vector<gpu::PassDesc> environmentPrefilterPasses() { return {downsampleDesc(), prefilterDesc()}; }

std::uint32_t prefilteredMipCount(std::uint32_t height, std::uint32_t maxMipCount) {
  std::uint32_t levels = 1;
  while ((height >> levels) >= 8 && levels < maxMipCount) ++levels;
  return std::max(1u, std::min(levels, maxMipCount));
}

struct EnvironmentPrefilter::Impl {
  PrefilterDesc desc;
  std::unique_ptr<gpu::Context> context;
  gpu::MemoryArena arena;
  VkSampler sampler = VK_NULL_HANDLE;        // linear, repeating in u: what readers sample the output with
  VkSampler sourceSampler = VK_NULL_HANDLE;  // nearest mip: the chain is read at exact levels
  std::uint32_t sourceLevels = 0;
  std::unique_ptr<gpu::Image> source[2];
  std::unique_ptr<gpu::Image> radiance;
  gpu::ComputePass downsample, prefilter;
  PassLog log;

  Impl(const Device& device, const PrefilterDesc& d)
      : desc(d),
        context(openLibraryContext(device)),
        arena(*context, VkDeviceSize(8) << 20),
        downsample(*context, downsampleDesc()),
        prefilter(*context, prefilterDesc()),
        log(*context, true) {
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = info.minFilter = VK_FILTER_LINEAR;
    info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
    info.addressModeU = VK_SAMPLER_ADDRESS_MODE_REPEAT;
    info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    info.maxLod = VK_LOD_CLAMP_NONE;
    gpu::check(vkCreateSampler(context->device(), &info, nullptr, &sampler), "vkCreateSampler (environment)");
    info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    if (const VkResult result = vkCreateSampler(context->device(), &info, nullptr, &sourceSampler);
        result != VK_SUCCESS) {
      vkDestroySampler(context->device(), sampler, nullptr);
      gpu::check(result, "vkCreateSampler (environment source)");
    }
    try {
      const auto image = [&](const char* name, std::uint32_t width, std::uint32_t height, std::uint32_t mips) {
        return std::make_unique<gpu::Image>(*context,
                                            gpu::ImageDesc{.name = name,
                                                           .width = width,
                                                           .height = height,
                                                           .format = VK_FORMAT_R16G16B16A16_SFLOAT,
                                                           .visualize = gpu::Visualize::Radiance,
                                                           .mipLevels = mips},
                                            &arena);
      };
      radiance = image("gi.environment.radiance", d.width, d.height, prefilteredMipCount(d.height, d.maxMipLevels));
      sourceLevels = fullMipCount(d.width, d.height);
      source[0] = image("gi.environment.source_even", d.width, d.height, sourceLevels);
      source[1] = image("gi.environment.source_odd", std::max(1u, d.width / 2), std::max(1u, d.height / 2),
                        std::max(1u, sourceLevels - 1));
    } catch (...) {
      vkDestroySampler(context->device(), sampler, nullptr);
      vkDestroySampler(context->device(), sourceSampler, nullptr);
      throw;
    }
  }

  ~Impl() {
    vkDestroySampler(context->device(), sampler, nullptr);
    vkDestroySampler(context->device(), sourceSampler, nullptr);
  }

  gpu::Image& chainImage(std::uint32_t level) { return *source[level & 1u]; }
  static std::uint32_t chainMip(std::uint32_t level) { return level & ~1u; }

  void record(VkCommandBuffer commandBuffer, const ImageRef& equirect, bool captureStages) {
    const std::string input = "gi: EnvironmentPrefilter input";
    if (commandBuffer == VK_NULL_HANDLE) throw Error("gi: EnvironmentPrefilter::record() needs a command buffer");
    if (equirect.image == VK_NULL_HANDLE || equirect.view == VK_NULL_HANDLE)
      throw Error(input + " is missing (its " + (equirect.image == VK_NULL_HANDLE ? "image" : "view") +
                  " is VK_NULL_HANDLE)");
    if (std::find(std::begin(kEquirectFormats), std::end(kEquirectFormats), equirect.format) ==
        std::end(kEquirectFormats))
      throw Error(input + " has the format " + gpu::formatName(equirect.format) + "; it takes " +
                  formatList(kEquirectFormats));
    if (equirect.width == 0 || equirect.height == 0)
      throw Error(input + " is " + std::to_string(equirect.width) + "x" + std::to_string(equirect.height));
    if (equirect.layout == VK_IMAGE_LAYOUT_UNDEFINED || equirect.layout == VK_IMAGE_LAYOUT_PREINITIALIZED)
      throw Error(input + " is in " + gpu::layoutName(equirect.layout) +
                  ", whose contents are undefined to a reader; give the layout the engine's last use left it in");

    gpu::Recorder recorder(*context, commandBuffer, log.sink());
    log.begin(commandBuffer, recorder, 0, captureStages);
    gpu::ExternalImage external{.image = equirect.image,
                                .view = equirect.view,
                                .desc = {.name = "engine.environment",
                                         .width = equirect.width,
                                         .height = equirect.height,
                                         .format = equirect.format,
                                         .mipLevels = std::max(1u, equirect.mipLevels),
                                         .storage = false}};
    external.state.writeStage = equirect.stage;
    external.state.writeAccess = equirect.access;
    external.state.layout = equirect.layout;
    gpu::Image source(*context, external);
    if (equirect.layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL || equirect.layout == VK_IMAGE_LAYOUT_GENERAL ||
        equirect.layout == VK_IMAGE_LAYOUT_READ_ONLY_OPTIMAL)
      source.setSampledLayout(equirect.layout);
    else
      source.setSampledLayout(VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);

    // Level 0 of the chain: the input, resampled (a copy when the sizes agree).
    recorder.dispatch(downsample, desc.width, desc.height,
                      {{"gIn_Source", source, sourceSampler}, {"gOut_Destination", *this->source[0], gpu::MipLevel{0}}});
    for (std::uint32_t level = 1; level < sourceLevels; ++level) {
      gpu::Image& destination = chainImage(level);
      const std::uint32_t destinationMip = chainMip(level);
      recorder.dispatch(downsample, destination.mipWidth(destinationMip), destination.mipHeight(destinationMip),
                        {{"gIn_Source", chainImage(level - 1), gpu::MipLevel{chainMip(level - 1)}, sourceSampler},
                         {"gOut_Destination", destination, gpu::MipLevel{destinationMip}}});
    }
    const std::uint32_t levels = radiance->desc().mipLevels;
    for (std::uint32_t level = 0; level < levels; ++level)
      recorder.dispatch(prefilter, radiance->mipWidth(level), radiance->mipHeight(level),
                        {{"gIn_SourceEven", *this->source[0], sourceSampler},
                         {"gIn_SourceOdd", *this->source[1], sourceSampler},
                         {"gOut_Radiance", *radiance, gpu::MipLevel{level}}},
                        PrefilterParams{level, levels, desc.samplesPerTexel, sourceLevels});
    // The input back as it came; the output as output() says.
    const VkPipelineStageFlags2 stage =
        equirect.stage == VK_PIPELINE_STAGE_2_NONE ? VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT : equirect.stage;
    if (source.sync().layout != equirect.layout ||
        !(stage & (VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT)))
      recorder.handOver(source, equirect.layout, stage, equirect.access);
    // A captured frame's copies leave the output in TRANSFER_SRC_OPTIMAL;
    // output() promises GENERAL after a compute write, and its readers
    // start their barriers from that promise.
    if (radiance->sync().layout != VK_IMAGE_LAYOUT_GENERAL)
      recorder.handOver(*radiance, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    recorder.flush();
  }
};

EnvironmentPrefilter::EnvironmentPrefilter(const Device& device, const PrefilterDesc& desc) {
  const auto outside = [](const char* what, std::uint32_t value, std::uint32_t low, std::uint32_t high) {
    if (value < low || value > high)
      throw Error(std::string("gi: PrefilterDesc::") + what + " " + std::to_string(value) + " is outside " +
                  std::to_string(low) + ".." + std::to_string(high));
  };
  outside("width", desc.width, 8, 16384);
  outside("height", desc.height, 4, 8192);
  outside("maxMipLevels", desc.maxMipLevels, 1, 16);
  outside("samplesPerTexel", desc.samplesPerTexel, 1, 65536);
  try {
    impl_ = std::make_unique<Impl>(device, desc);
  } catch (const gpu::GpuError& e) {
    throw Error(std::string("gi: ") + e.what());
  }
}

EnvironmentPrefilter::~EnvironmentPrefilter() = default;

void EnvironmentPrefilter::record(VkCommandBuffer commandBuffer, const ImageRef& equirect, bool captureStages) {
  try {
    impl_->record(commandBuffer, equirect, captureStages);
  } catch (const gpu::GpuError& e) {
    throw Error(std::string("gi: ") + e.what());
  }
}

FrameResults EnvironmentPrefilter::collect() {
  FrameResults results;
  impl_->log.collectInto(results, "gi: EnvironmentPrefilter::collect()");
  return results;
}

ImageRef EnvironmentPrefilter::output() const { return libraryRef(*impl_->radiance); }

VkSampler EnvironmentPrefilter::sampler() const { return impl_->sampler; }
std::uint32_t EnvironmentPrefilter::mipLevels() const { return impl_->radiance->desc().mipLevels; }
std::uint64_t EnvironmentPrefilter::memoryBytes() const { return impl_->arena.bytes(); }

}  // namespace bounce::gi
