// The image formats Bounce uses, and what the host needs to know about each.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace bounce::gpu {

// Short names for the formats passes declare and images are made in, each
// named after its GLSL layout qualifier. A file that declares passes says
// `using namespace gpu::formats;` instead of keeping its own list.
namespace formats {
inline constexpr VkFormat kR16f = VK_FORMAT_R16_SFLOAT;
inline constexpr VkFormat kR32f = VK_FORMAT_R32_SFLOAT;
inline constexpr VkFormat kR32ui = VK_FORMAT_R32_UINT;
inline constexpr VkFormat kRg16f = VK_FORMAT_R16G16_SFLOAT;
inline constexpr VkFormat kRg32f = VK_FORMAT_R32G32_SFLOAT;
inline constexpr VkFormat kRg32ui = VK_FORMAT_R32G32_UINT;
inline constexpr VkFormat kRgba8 = VK_FORMAT_R8G8B8A8_UNORM;
inline constexpr VkFormat kRgba8Srgb = VK_FORMAT_R8G8B8A8_SRGB;  // sampled only: no storage qualifier
inline constexpr VkFormat kRgb10A2 = VK_FORMAT_A2B10G10R10_UNORM_PACK32;
inline constexpr VkFormat kR11G11B10f = VK_FORMAT_B10G11R11_UFLOAT_PACK32;
inline constexpr VkFormat kRgba16f = VK_FORMAT_R16G16B16A16_SFLOAT;
inline constexpr VkFormat kRgba32f = VK_FORMAT_R32G32B32A32_SFLOAT;
inline constexpr VkFormat kRgba32ui = VK_FORMAT_R32G32B32A32_UINT;
}  // namespace formats

struct FormatInfo {
  VkFormat format;
  const char* name;  // the GLSL layout qualifier: "rgba16f" ("rgba8 sRGB" for the one without)
  std::uint32_t channels;
  std::uint32_t bytesPerPixel;
  std::uint32_t spirvImageFormat;  // spv::ImageFormat, to check against shaders; 0: not a storage format
};

// Throws GpuError naming the format (vulkanFormatName) for one Bounce does not support.
const FormatInfo& formatInfo(VkFormat format);
// The Vulkan name of any format the headers know ("VK_FORMAT_R16_SFLOAT"),
// else "VkFormat <number>"; never a bare number where a name exists.
std::string formatName(VkFormat format);
// Generated from vulkan_core.h (cmake/VulkanEnumNames.cmake); null for an unknown value.
const char* vulkanFormatName(VkFormat format);
const char* vulkanImageLayoutName(VkImageLayout layout);
// "VK_IMAGE_LAYOUT_GENERAL", else "VkImageLayout <number>".
std::string layoutName(VkImageLayout layout);
const FormatInfo* findFormatBySpirv(std::uint32_t spirvImageFormat);

// Texel bytes <-> floats (one float per channel), for upload, readback and dumps.
void texelsToFloats(VkFormat format, const void* texels, std::size_t pixelCount, float* out);
std::vector<std::uint8_t> floatsToTexels(VkFormat format, const float* values, std::size_t pixelCount);

}  // namespace bounce::gpu
