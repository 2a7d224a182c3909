// The image formats Bounce uses, and what the host needs to know about each.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

namespace bounce::gpu {

// Short names for the formats passes declare and images are made in, each
// named after its GLSL layout qualifier. A file that declares passes says
// `using namespace gpu::formats;` instead of keeping its own list.
namespace formats {
inline constexpr VkFormat kR32f = VK_FORMAT_R32_SFLOAT;
inline constexpr VkFormat kR32ui = VK_FORMAT_R32_UINT;
inline constexpr VkFormat kRg16f = VK_FORMAT_R16G16_SFLOAT;
inline constexpr VkFormat kRg32f = VK_FORMAT_R32G32_SFLOAT;
inline constexpr VkFormat kRg32ui = VK_FORMAT_R32G32_UINT;
inline constexpr VkFormat kRgba8 = VK_FORMAT_R8G8B8A8_UNORM;
inline constexpr VkFormat kRgba16f = VK_FORMAT_R16G16B16A16_SFLOAT;
inline constexpr VkFormat kRgba32f = VK_FORMAT_R32G32B32A32_SFLOAT;
inline constexpr VkFormat kRgba32ui = VK_FORMAT_R32G32B32A32_UINT;
}  // namespace formats

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
