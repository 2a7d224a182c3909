// Shaders compiled by glslc at build time and linked into the binary
// (cmake/EmbedShaders.cmake): each library embeds the shaders it runs in a
// table of its own (gi::shaders(), render::shaders(), ...), which its passes
// name in their PassDesc.
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

// The shader of that name and variant in `library`; throws GpuError listing
// the library's names if absent.
std::span<const std::uint32_t> findShader(std::span<const EmbeddedShader> library, std::string_view name,
                                          bool constantsInStorageBuffers = false);

}  // namespace bounce::gpu
