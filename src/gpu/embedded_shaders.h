// The SPIR-V of every shader under shaders/, compiled by glslc at build time
// and linked into the binary (see cmake/EmbedShaders.cmake).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace bounce::gpu {

struct EmbeddedShader {
  const char* name;  // path below shaders/ without extension: "render/direct_light"
  const std::uint32_t* words;
  std::size_t wordCount;
};

std::span<const EmbeddedShader> embeddedShaders();

// The shader of that name; throws GpuError listing the known names if absent.
std::span<const std::uint32_t> findShader(std::string_view name);

}  // namespace bounce::gpu
