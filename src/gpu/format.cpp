#include "gpu/format.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include <glm/gtc/packing.hpp>
#include <spirv/unified1/spirv.hpp>

#include "gpu/error.h"

namespace bounce::gpu {
namespace {

const FormatInfo kFormats[] = {
    {VK_FORMAT_R32_SFLOAT, "r32f", 1, 4, spv::ImageFormatR32f},
    {VK_FORMAT_R16G16_SFLOAT, "rg16f", 2, 4, spv::ImageFormatRg16f},
    {VK_FORMAT_R32G32_SFLOAT, "rg32f", 2, 8, spv::ImageFormatRg32f},
    {VK_FORMAT_R16G16B16A16_SFLOAT, "rgba16f", 4, 8, spv::ImageFormatRgba16f},
    {VK_FORMAT_R32G32B32A32_SFLOAT, "rgba32f", 4, 16, spv::ImageFormatRgba32f},
    {VK_FORMAT_R32_UINT, "r32ui", 1, 4, spv::ImageFormatR32ui},
    {VK_FORMAT_R16_UINT, "r16ui", 1, 2, spv::ImageFormatR16ui},
    {VK_FORMAT_R8_UINT, "r8ui", 1, 1, spv::ImageFormatR8ui},
    {VK_FORMAT_R32G32_UINT, "rg32ui", 2, 8, spv::ImageFormatRg32ui},
    {VK_FORMAT_R32G32B32A32_UINT, "rgba32ui", 4, 16, spv::ImageFormatRgba32ui},
    {VK_FORMAT_R8G8B8A8_UNORM, "rgba8", 4, 4, spv::ImageFormatRgba8},
    {VK_FORMAT_R16_SFLOAT, "r16f", 1, 2, spv::ImageFormatR16f},
    {VK_FORMAT_R8G8B8A8_SRGB, "rgba8 sRGB", 4, 4, 0},
    {VK_FORMAT_A2B10G10R10_UNORM_PACK32, "rgb10_a2", 4, 4, spv::ImageFormatRgb10A2},
    {VK_FORMAT_B10G11R11_UFLOAT_PACK32, "r11f_g11f_b10f", 3, 4, spv::ImageFormatR11fG11fB10f},
};

float srgbToLinear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }
float linearToSrgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}
std::uint8_t unorm8(float v) { return std::uint8_t(std::floor(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f)); }
std::uint32_t unorm(float v, float max) { return std::uint32_t(std::floor(std::clamp(v, 0.0f, 1.0f) * max + 0.5f)); }

}  // namespace

const FormatInfo& formatInfo(VkFormat format) {
  for (const FormatInfo& info : kFormats)
    if (info.format == format) return info;
  throw GpuError("image format " + formatName(format) + " is not supported by Bounce");
}

std::string formatName(VkFormat format) {
  if (const char* name = vulkanFormatName(format)) return name;
  return "VkFormat " + std::to_string(std::int64_t(format));
}

std::string layoutName(VkImageLayout layout) {
  if (const char* name = vulkanImageLayoutName(layout)) return name;
  return "VkImageLayout " + std::to_string(std::int64_t(layout));
}

const FormatInfo* findFormatBySpirv(std::uint32_t spirvImageFormat) {
  if (spirvImageFormat == 0) return nullptr;
  for (const FormatInfo& info : kFormats)
    if (info.spirvImageFormat == spirvImageFormat) return &info;
  return nullptr;
}

void texelsToFloats(VkFormat format, const void* texels, std::size_t pixelCount, float* out) {
  const FormatInfo& info = formatInfo(format);
  const std::size_t values = pixelCount * info.channels;
  switch (format) {
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32G32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_SFLOAT:
      std::memcpy(out, texels, values * sizeof(float));
      return;
    case VK_FORMAT_R16_SFLOAT:
    case VK_FORMAT_R16G16_SFLOAT:
    case VK_FORMAT_R16G16B16A16_SFLOAT: {
      const auto* halves = static_cast<const std::uint16_t*>(texels);
      for (std::size_t i = 0; i < values; ++i) out[i] = glm::unpackHalf1x16(halves[i]);
      return;
    }
    // Colour as shaders read it: sRGB decoded to linear (alpha stays linear).
    case VK_FORMAT_R8G8B8A8_SRGB: {
      const auto* bytes = static_cast<const std::uint8_t*>(texels);
      for (std::size_t i = 0; i < values; ++i)
        out[i] = i % 4 == 3 ? float(bytes[i]) / 255.0f : srgbToLinear(float(bytes[i]) / 255.0f);
      return;
    }
    case VK_FORMAT_A2B10G10R10_UNORM_PACK32: {
      const auto* words = static_cast<const std::uint32_t*>(texels);
      for (std::size_t p = 0; p < pixelCount; ++p) {
        for (int c = 0; c < 3; ++c) out[4 * p + c] = float((words[p] >> (10 * c)) & 0x3ffu) / 1023.0f;
        out[4 * p + 3] = float(words[p] >> 30) / 3.0f;
      }
      return;
    }
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32: {
      const auto* words = static_cast<const std::uint32_t*>(texels);
      for (std::size_t p = 0; p < pixelCount; ++p) {
        const glm::vec3 rgb = glm::unpackF2x11_1x10(words[p]);
        for (int c = 0; c < 3; ++c) out[3 * p + c] = rgb[c];
      }
      return;
    }
    // Packed data (reservoirs, history surfaces) as the integers they are,
    // exact below 2^24; the shader's own unpacking is what gives them meaning.
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_R32G32_UINT:
    case VK_FORMAT_R32G32B32A32_UINT: {
      const auto* words = static_cast<const std::uint32_t*>(texels);
      for (std::size_t i = 0; i < values; ++i) out[i] = float(words[i]);
      return;
    }
    case VK_FORMAT_R16_UINT: {
      const auto* shorts = static_cast<const std::uint16_t*>(texels);
      for (std::size_t i = 0; i < values; ++i) out[i] = float(shorts[i]);
      return;
    }
    case VK_FORMAT_R8_UINT: {
      const auto* bytes = static_cast<const std::uint8_t*>(texels);
      for (std::size_t i = 0; i < values; ++i) out[i] = float(bytes[i]);
      return;
    }
    case VK_FORMAT_R8G8B8A8_UNORM: {
      const auto* bytes = static_cast<const std::uint8_t*>(texels);
      for (std::size_t i = 0; i < values; ++i) out[i] = float(bytes[i]) / 255.0f;
      return;
    }
    default:
      throw GpuError(std::string("no texel conversion for format ") + info.name);
  }
}

std::vector<std::uint8_t> floatsToTexels(VkFormat format, const float* values, std::size_t pixelCount) {
  const FormatInfo& info = formatInfo(format);
  const std::size_t count = pixelCount * info.channels;
  std::vector<std::uint8_t> bytes(pixelCount * info.bytesPerPixel);
  switch (format) {
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32G32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_SFLOAT:
      std::memcpy(bytes.data(), values, count * sizeof(float));
      break;
    case VK_FORMAT_R16_SFLOAT:
    case VK_FORMAT_R16G16_SFLOAT:
    case VK_FORMAT_R16G16B16A16_SFLOAT: {
      auto* halves = reinterpret_cast<std::uint16_t*>(bytes.data());
      for (std::size_t i = 0; i < count; ++i) halves[i] = glm::packHalf1x16(values[i]);
      break;
    }
    case VK_FORMAT_R32_UINT: {
      auto* words = reinterpret_cast<std::uint32_t*>(bytes.data());
      for (std::size_t i = 0; i < count; ++i) words[i] = std::uint32_t(std::max(0.0f, values[i]));
      break;
    }
    case VK_FORMAT_R16_UINT: {
      auto* shorts = reinterpret_cast<std::uint16_t*>(bytes.data());
      for (std::size_t i = 0; i < count; ++i) shorts[i] = std::uint16_t(std::clamp(values[i], 0.0f, 65535.0f));
      break;
    }
    case VK_FORMAT_R8_UINT:
      for (std::size_t i = 0; i < count; ++i) bytes[i] = std::uint8_t(std::clamp(values[i], 0.0f, 255.0f));
      break;
    case VK_FORMAT_R8G8B8A8_UNORM:
      for (std::size_t i = 0; i < count; ++i) bytes[i] = unorm8(values[i]);
      break;
    case VK_FORMAT_R8G8B8A8_SRGB:
      for (std::size_t i = 0; i < count; ++i) bytes[i] = unorm8(i % 4 == 3 ? values[i] : linearToSrgb(values[i]));
      break;
    case VK_FORMAT_A2B10G10R10_UNORM_PACK32: {
      auto* words = reinterpret_cast<std::uint32_t*>(bytes.data());
      for (std::size_t p = 0; p < pixelCount; ++p)
        words[p] = unorm(values[4 * p], 1023.0f) | unorm(values[4 * p + 1], 1023.0f) << 10 |
                   unorm(values[4 * p + 2], 1023.0f) << 20 | unorm(values[4 * p + 3], 3.0f) << 30;
      break;
    }
    case VK_FORMAT_B10G11R11_UFLOAT_PACK32: {
      auto* words = reinterpret_cast<std::uint32_t*>(bytes.data());
      for (std::size_t p = 0; p < pixelCount; ++p)
        words[p] = glm::packF2x11_1x10(glm::vec3(values[3 * p], values[3 * p + 1], values[3 * p + 2]));
      break;
    }
    default:
      throw GpuError(std::string("no texel conversion for format ") + info.name);
  }
  return bytes;
}

}  // namespace bounce::gpu
