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
    {VK_FORMAT_R32G32_UINT, "rg32ui", 2, 8, spv::ImageFormatRg32ui},
    {VK_FORMAT_R32G32B32A32_UINT, "rgba32ui", 4, 16, spv::ImageFormatRgba32ui},
    {VK_FORMAT_R8G8B8A8_UNORM, "rgba8", 4, 4, spv::ImageFormatRgba8},
};

}  // namespace

const FormatInfo& formatInfo(VkFormat format) {
  for (const FormatInfo& info : kFormats)
    if (info.format == format) return info;
  throw GpuError("image format " + std::to_string(int(format)) + " is not supported by Bounce");
}

const FormatInfo* findFormatBySpirv(std::uint32_t spirvImageFormat) {
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
    case VK_FORMAT_R16G16_SFLOAT:
    case VK_FORMAT_R16G16B16A16_SFLOAT: {
      const auto* halves = static_cast<const std::uint16_t*>(texels);
      for (std::size_t i = 0; i < values; ++i) out[i] = glm::unpackHalf1x16(halves[i]);
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
    case VK_FORMAT_R8G8B8A8_UNORM:
      for (std::size_t i = 0; i < count; ++i)
        bytes[i] = std::uint8_t(std::floor(std::clamp(values[i], 0.0f, 1.0f) * 255.0f + 0.5f));
      break;
    default:
      throw GpuError(std::string("no texel conversion for format ") + info.name);
  }
  return bytes;
}

}  // namespace bounce::gpu
