#include "app/copy_bandwidth.h"

#include <algorithm>

#include "gpu/constants_layout.h"
#include "gpu/context.h"
#include "gpu/error.h"

namespace bounce::app {
namespace {

using namespace gpu;

struct CopyParams {
  std::uint32_t rowLength;
  std::uint32_t count;
};
constexpr std::uint32_t kRowLength = 65536;  // vec4 per dispatch row

}  // namespace

// Clamped to what one storage-buffer binding may span (128 MiB on lavapipe).
CopyBandwidthProbe::CopyBandwidthProbe(Context& context, VkDeviceSize bytes)
    : bytes_(std::min<VkDeviceSize>(bytes, context.properties().limits.maxStorageBufferRange) / 16 * 16) {
  if (bytes_ == 0) throw GpuError("copy bandwidth probe: size must be at least 16 bytes");
  source_ = std::make_unique<Buffer>(context, "copy_bandwidth.source", bytes_, BufferUsage::DeviceLocal);
  destination_ = std::make_unique<Buffer>(context, "copy_bandwidth.destination", bytes_, BufferUsage::DeviceLocal);
  // Defined contents (1.0f everywhere), so the copy is not of uninitialised memory.
  context.submitAndWait([&](Recorder& r) { r.fillBuffer(*source_, 0x3f800000u); });
  pass_ = std::make_unique<ComputePass>(
      context, PassDesc{.name = kPassName,
                        .shader = "bench/copy_bandwidth",
                        .shaders = app::shaders(),
                        .resources = {{"gIn_Source", Access::Read, VK_FORMAT_UNDEFINED, "bytes to read",
                                       ResourceKind::StorageBuffer},
                                      {"gOut_Destination", Access::Write, VK_FORMAT_UNDEFINED, "bytes written",
                                       ResourceKind::StorageBuffer}},
                        .constants = {BOUNCE_CONSTANTS_LAYOUT("", CopyParams, rowLength, count)}});
}

void CopyBandwidthProbe::record(Recorder& recorder) {
  const auto count = std::uint32_t(bytes_ / 16);
  const std::uint32_t rows = (count + kRowLength - 1) / kRowLength;
  recorder.dispatch(*pass_, std::min(count, kRowLength), rows,
                    {{"gIn_Source", *source_}, {"gOut_Destination", *destination_}}, CopyParams{kRowLength, count});
}

}  // namespace bounce::app
