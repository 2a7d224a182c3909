#include "app/checkerboard_pack.h"

#include <string>

#include "app/copy_bandwidth.h"
#include "gpu/constants_layout.h"
#include "gpu/format.h"
#include "shared/checkerboard.glsl"

namespace bounce::app {
namespace {

struct CheckerboardPackParams {
  std::uint32_t width;
  std::uint32_t height;
  std::uint32_t frameIndex;
  std::uint32_t dataParity;
};

constexpr std::array<const char*, CheckerboardPacker::kSignals> kSignalNames = {"diffuse", "specular"};
constexpr std::array<std::uint32_t, CheckerboardPacker::kSignals> kParities = {
    shared::kCheckerboardDiffuseParity, shared::kCheckerboardSpecularParity};

gpu::PassDesc packDesc(const std::string& signal) {
  return gpu::PassDesc{
      .name = "denoise.checkerboard_pack." + signal,
      .shader = "app/checkerboard_pack",
      .shaders = app::shaders(),
      .resources = {{"gIn_Full", gpu::Access::Read, gpu::formats::kRgba32f,
                     "the path tracer's noisy signal, every pixel: demodulated radiance, hit distance"},
                    {"gOut_Packed", gpu::Access::Write, gpu::formats::kRgba32f,
                     "the pixels of the signal's checkerboard parity, packed to half width"}},
      .constants = {BOUNCE_CONSTANTS_LAYOUT("", CheckerboardPackParams, width, height, frameIndex, dataParity)}};
}

}  // namespace

CheckerboardPacker::CheckerboardPacker(gpu::Context& context, std::uint32_t width, std::uint32_t height)
    : width_(width), height_(height) {
  for (std::size_t signal = 0; signal < kSignals; ++signal) {
    packed_[signal] = std::make_unique<gpu::Image>(
        context, gpu::ImageDesc{.name = std::string("denoise.checkerboard.") + kSignalNames[signal],
                                .width = shared::checkerboardPackedWidth(width),
                                .height = height,
                                .format = gpu::formats::kRgba32f});
    passes_[signal] = std::make_unique<gpu::ComputePass>(context, packDesc(kSignalNames[signal]));
  }
}

CheckerboardPacker::~CheckerboardPacker() = default;

void CheckerboardPacker::record(gpu::Recorder& recorder, std::size_t signal, gpu::Image& full,
                                std::uint64_t frameIndex) {
  const CheckerboardPackParams params{width_, height_, std::uint32_t(frameIndex), kParities[signal]};
  recorder.dispatch(*passes_[signal], shared::checkerboardPackedWidth(width_), height_,
                    {{"gIn_Full", full}, {"gOut_Packed", *packed_[signal]}}, params);
}

}  // namespace bounce::app
