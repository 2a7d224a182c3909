#include "gpu/transfer.h"

#include <cstring>
#include <string>

#include "gpu/context.h"
#include "gpu/error.h"
#include "gpu/format.h"
#include "gpu/recorder.h"

namespace bounce::gpu {

std::vector<std::string> channelNames(VkFormat format) {
  switch (formatInfo(format).channels) {
    case 1:
      return {"Y"};
    case 2:
      return {"R", "G"};
    case 3:
      return {"R", "G", "B"};
    default:
      return {"R", "G", "B", "A"};
  }
}

void uploadImage(Context& context, Image& image, const void* texels, std::size_t bytes) {
  if (bytes != image.byteSize())
    throw GpuError("upload to '" + image.name() + "': " + std::to_string(bytes) + " bytes given, " +
                   std::to_string(image.byteSize()) + " needed");
  Buffer staging(context, "staging.upload." + image.name(), bytes, BufferUsage::Upload);
  std::memcpy(staging.mapped(), texels, bytes);
  context.submitAndWait([&](Recorder& r) { r.copyBufferToImage(staging, image); });
}

std::vector<std::uint8_t> readbackImageBytes(Context& context, Image& image) {
  Buffer staging(context, "staging.readback." + image.name(), image.byteSize(), BufferUsage::Readback);
  context.submitAndWait([&](Recorder& r) {
    r.copyImageToBuffer(image, staging);
    r.makeHostReadable(staging);
  });
  const auto* bytes = static_cast<const std::uint8_t*>(staging.mapped());
  return std::vector<std::uint8_t>(bytes, bytes + image.byteSize());
}

void uploadBuffer(Context& context, Buffer& buffer, const void* data, std::size_t bytes) {
  if (bytes > buffer.size())
    throw GpuError("upload of " + std::to_string(bytes) + " bytes to buffer '" + buffer.name() + "' of " +
                   std::to_string(buffer.size()));
  if (buffer.mapped()) {
    std::memcpy(buffer.mapped(), data, bytes);
    return;
  }
  Buffer staging(context, "staging.upload." + buffer.name(), bytes, BufferUsage::Upload);
  std::memcpy(staging.mapped(), data, bytes);
  context.submitAndWait([&](Recorder& r) { r.copyBuffer(staging, buffer, bytes); });
}

std::vector<std::uint8_t> readbackBuffer(Context& context, Buffer& buffer) {
  Buffer staging(context, "staging.readback." + buffer.name(), buffer.size(), BufferUsage::Readback);
  context.submitAndWait([&](Recorder& r) {
    r.copyBuffer(buffer, staging, buffer.size());
    r.makeHostReadable(staging);
  });
  const auto* bytes = static_cast<const std::uint8_t*>(staging.mapped());
  return {bytes, bytes + buffer.size()};
}

}  // namespace bounce::gpu
