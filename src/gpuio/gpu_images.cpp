#include "gpuio/gpu_images.h"

#include <string>
#include <vector>

#include "gpu/error.h"
#include "gpu/format.h"
#include "gpu/recorder.h"
#include "gpu/transfer.h"

namespace bounce::gpuio {

void uploadImage(gpu::Context& context, gpu::Image& image, const io::ImageF& pixels) {
  const gpu::FormatInfo& format = gpu::formatInfo(image.format());
  if (pixels.width != int(image.width()) || pixels.height != int(image.height()) ||
      pixels.channelCount() != format.channels)
    throw gpu::GpuError("upload to '" + image.name() + "': a " + std::to_string(pixels.width) + "x" +
                   std::to_string(pixels.height) + "x" + std::to_string(pixels.channelCount()) +
                   " image does not fit " + std::to_string(image.width()) + "x" + std::to_string(image.height()) + " " +
                   format.name);
  std::vector<std::uint8_t> texels =
      gpu::floatsToTexels(image.format(), pixels.pixels.data(), std::size_t(pixels.width) * pixels.height);
  gpu::uploadImage(context, image, texels.data(), texels.size());
}

io::ImageF texelsToImage(const gpu::ImageDesc& desc, const void* texels) {
  io::ImageF out(int(desc.width), int(desc.height), gpu::channelNames(desc.format));
  gpu::texelsToFloats(desc.format, texels, std::size_t(desc.width) * desc.height, out.pixels.data());
  return out;
}

io::ImageF readbackImage(gpu::Context& context, gpu::Image& image) {
  gpu::Buffer staging(context, "staging.readback." + image.name(), image.byteSize(), gpu::BufferUsage::Readback);
  context.submitAndWait([&](gpu::Recorder& r) {
    r.copyImageToBuffer(image, staging);
    r.makeHostReadable(staging);
  });
  return texelsToImage(image.desc(), staging.mapped());
}

}  // namespace bounce::gpuio
