// Just enough SPIR-V reflection to check a pass's host declarations against
// its shader: the name, binding, kind and format of every descriptor, the
// layout (member names, offsets, sizes) of its buffer blocks and push
// constants, and the workgroup size.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace bounce::gpu {

enum class ResourceKind { StorageImage, SampledImage, StorageBuffer, UniformBuffer };
const char* kindName(ResourceKind kind);

// One member of a block as the shader lays it out. A block whose only member
// is a struct (uniform FrameBlock { GiFrameConstants frame; }) is described
// by that struct's members.
struct BlockMember {
  std::string name;
  std::uint32_t offset = 0;
  std::uint32_t size = 0;
};

struct ReflectedBinding {
  std::string name;  // the variable's name (or the block's type name when the instance is unnamed)
  std::uint32_t set = 0;
  std::uint32_t binding = 0;
  ResourceKind kind = ResourceKind::StorageImage;
  std::uint32_t spirvImageFormat = 0;  // storage images: the layout(...) format qualifier
  bool readable = true;                // false when declared writeonly
  bool writable = true;                // false when declared readonly
  std::vector<BlockMember> members;    // buffers: the block's layout
  std::uint32_t blockSize = 0;         // buffers: the end of the last member
};

struct ShaderReflection {
  std::vector<ReflectedBinding> bindings;
  std::uint32_t pushConstantSize = 0;
  std::vector<BlockMember> pushConstantMembers;
  std::uint32_t localSize[3] = {1, 1, 1};
};

// Throws GpuError (naming `shaderName`) for malformed SPIR-V or constructs
// Bounce does not support (separate samplers, descriptor arrays).
ShaderReflection reflectShader(std::span<const std::uint32_t> spirv, const std::string& shaderName);

}  // namespace bounce::gpu
