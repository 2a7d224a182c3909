#include "viewer/pixel_inspector.h"

#include "gpu/format.h"
#include "gpu/recorder.h"

namespace bounce::viewer {
namespace {

// Bytes each inspected image's texel gets in the readback buffer: a
// multiple of every texel size, as copies to buffers need.
constexpr VkDeviceSize kInspectStride = 16;

}  // namespace

std::vector<InspectedValue> PixelInspector::inspect(std::span<const NamedImage> images, std::uint32_t x,
                                                    std::uint32_t y, std::uint32_t frameWidth,
                                                    std::uint32_t frameHeight) {
  const VkDeviceSize bytes = kInspectStride * images.size();
  if (!readback_ || readback_->size() < bytes)
    readback_ = std::make_unique<gpu::Buffer>(context_, "viewer.inspector", bytes, gpu::BufferUsage::Readback);
  const auto texelOf = [&](const gpu::Image& image) {
    return glm::uvec2(std::uint32_t(std::uint64_t(x) * image.width() / frameWidth),
                      std::uint32_t(std::uint64_t(y) * image.height() / frameHeight));
  };
  context_.submitAndWait([&](gpu::Recorder& recorder) {
    for (std::size_t i = 0; i < images.size(); ++i) {
      const glm::uvec2 texel = texelOf(*images[i].image);
      recorder.copyImageToBuffer(
          *images[i].image, *readback_,
          gpu::ImageRegion{.x = texel.x, .y = texel.y, .width = 1, .height = 1, .bufferOffset = kInspectStride * i});
    }
    recorder.makeHostReadable(*readback_);
  });
  std::vector<InspectedValue> values;
  const auto* texels = static_cast<const std::uint8_t*>(readback_->mapped());
  for (std::size_t i = 0; i < images.size(); ++i) {
    const gpu::FormatInfo& format = gpu::formatInfo(images[i].image->format());
    float value[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    gpu::texelsToFloats(format.format, texels + kInspectStride * i, 1, value);
    values.push_back({images[i].name, glm::vec4(value[0], value[1], value[2], value[3]), format.channels});
  }
  return values;
}

}  // namespace bounce::viewer
