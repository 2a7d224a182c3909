// A compute pass: one shader, one host declaration.
//
// The declaration names every resource the shader touches, with how it is
// accessed, its format and a one-line purpose, and the layout of its
// constant blocks. At creation the declaration is checked against the
// shader's own SPIR-V: a missing, extra, misspelled, wrongly-typed or
// wrongly-formatted binding, or a constant block whose members sit elsewhere
// than the C++ struct's, is an error that names the pass and the binding,
// never a silent mismatch by binding order or byte offset.
//
//   const gpu::PassDesc kDirectSun{
//       .name = "render.direct_light",
//       .shader = "render/direct_light",
//       .shaders = render::shaders(),
//       .resources = {
//           {"gIn_ViewZ", gpu::Access::Read, VK_FORMAT_R32_SFLOAT, "linear view depth"},
//           {"gOut_Radiance", gpu::Access::Write, VK_FORMAT_R16G16B16A16_SFLOAT, "direct light"},
//       },
//       .constants = {BOUNCE_CONSTANTS_LAYOUT("", DirectLightParams, sunDirection, sunColor)},
//   };
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/constants_layout.h"
#include "gpu/embedded_shaders.h"
#include "gpu/spirv_reflect.h"

namespace bounce::gpu {

class Context;

enum class Access { Read, Write, ReadWrite };

struct ResourceDecl {
  std::string name;  // the shader's variable name: gIn_*, gOut_*, gPrev_*, gHistory_*
  Access access = Access::Read;
  // For storage images, the format; VK_FORMAT_UNDEFINED for buffers and
  // sampled images (which accept any format).
  VkFormat format = VK_FORMAT_UNDEFINED;
  std::string purpose;
  // Buffers and sampled images say so; everything else is a storage image.
  ResourceKind kind = ResourceKind::StorageImage;
};

struct PassDesc {
  std::string name;    // stable: GPU timestamp key, debug label, dump file prefix
  std::string shader;  // embedded shader path, e.g. "render/direct_light"
  std::span<const EmbeddedShader> shaders;  // the library the shader is embedded in (render::shaders(), ...)
  std::vector<ResourceDecl> resources;
  // The layout of every uniform block and of the push constants
  // (BOUNCE_CONSTANTS_LAYOUT; binding "" for the push constants), checked
  // member by member against the shader.
  std::vector<ConstantsDecl> constants;

  // The size of the push-constant struct (0: none).
  std::uint32_t pushConstantSize() const;
};

// Resources a shared shader file declares but a given pass's shader may not
// use (SPIR-V keeps no unused binding, and a declaration without a binding
// is refused): appends to `desc` those of `optional` the shader has.
// `constantsInStorageBuffers`: the variant whose bindings are looked at.
void declareUsed(PassDesc& desc, std::span<const ResourceDecl> optional, bool constantsInStorageBuffers);

class ComputePass {
 public:
  ComputePass(Context& context, PassDesc desc);
  ~ComputePass();
  ComputePass(const ComputePass&) = delete;
  ComputePass& operator=(const ComputePass&) = delete;

  const PassDesc& desc() const { return desc_; }
  const std::string& name() const { return desc_.name; }
  VkPipeline pipeline() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  const std::uint32_t* localSize() const { return reflection_.localSize; }

  // The reflected binding behind a declared resource (same order as desc().resources).
  const ReflectedBinding& binding(std::size_t resourceIndex) const { return bindings_[resourceIndex]; }

 private:
  Context& context_;
  PassDesc desc_;
  ShaderReflection reflection_;
  std::vector<ReflectedBinding> bindings_;
  VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

}  // namespace bounce::gpu
