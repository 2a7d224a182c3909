// The image formats Bounce uses, and what the host needs to know about each.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

namespace bounce::gpu {

struct FormatInfo {
  VkFormat format;
  const char* name;  // the GLSL layout qualifier: "rgba16f"
  std::uint32_t channels;
  std::uint32_t bytesPerPixel;
  std::uint32_t spirvImageFormat;  // spv::ImageFormat, to check against shaders
};

// Throws GpuError for a format Bounce does not support.
const FormatInfo& formatInfo(VkFormat format);
const FormatInfo* findFormatBySpirv(std::uint32_t spirvImageFormat);

// Texel bytes <-> floats (one float per channel), for upload, readback and dumps.
void texelsToFloats(VkFormat format, const void* texels, std::size_t pixelCount, float* out);
std::vector<std::uint8_t> floatsToTexels(VkFormat format, const float* values, std::size_t pixelCount);

}  // namespace bounce::gpu
