// The SPIR-V of every shader under shaders/, compiled by glslc at build time
// and linked into the binary (see cmake/EmbedShaders.cmake).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace bounce::gpu {

// Every shader is compiled twice: with its constant blocks (CONSTANT_BLOCK,
// shaders/gpu/constant_block.glsl) as uniform blocks, for GPUs, and as
// read-only storage buffers, for CPU drivers.
struct EmbeddedShader {
  const char* name;  // path below shaders/ without extension: "render/direct_light"
  bool constantsInStorageBuffers;
  const std::uint32_t* words;
  std::size_t wordCount;
};

std::span<const EmbeddedShader> embeddedShaders();

// The shader of that name and variant; throws GpuError listing the known
// names if absent.
std::span<const std::uint32_t> findShader(std::string_view name, bool constantsInStorageBuffers = false);

}  // namespace bounce::gpu
