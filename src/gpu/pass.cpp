#include "gpu/pass.h"

#include <algorithm>
#include <set>
#include <string>

#include "gpu/context.h"
#include "gpu/embedded_shaders.h"
#include "gpu/error.h"
#include "gpu/format.h"

namespace bounce::gpu {
namespace {

VkDescriptorType descriptorType(ResourceKind kind) {
  switch (kind) {
    case ResourceKind::StorageImage:
      return VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    case ResourceKind::SampledImage:
      return VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    case ResourceKind::StorageBuffer:
      return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    case ResourceKind::UniformBuffer:
      return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  }
  return VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
}

const char* accessName(Access access) {
  switch (access) {
    case Access::Read:
      return "read";
    case Access::Write:
      return "write";
    case Access::ReadWrite:
      return "read-write";
  }
  return "?";
}

// Checks the host declaration against the reflected shader and returns the
// reflected binding of each declared resource, in declaration order. In the
// shader variant whose constant blocks are storage buffers, a declared
// uniform buffer is one (read-only) storage buffer.
std::vector<ReflectedBinding> matchDeclarations(const PassDesc& desc, const ShaderReflection& reflection,
                                                bool constantsInStorageBuffers) {
  auto fail = [&](const std::string& why) { return GpuError("pass '" + desc.name + "': " + why); };
  auto shaderNames = [&] {
    std::string list;
    for (const ReflectedBinding& b : reflection.bindings) list += (list.empty() ? "" : ", ") + b.name;
    return list.empty() ? std::string("none") : list;
  };

  std::vector<ReflectedBinding> matched;
  std::set<std::string> declared;
  for (const ResourceDecl& decl : desc.resources) {
    if (!declared.insert(decl.name).second) throw fail("resource '" + decl.name + "' is declared twice");
    const ReflectedBinding* found = nullptr;
    for (const ReflectedBinding& b : reflection.bindings)
      if (b.name == decl.name) found = &b;
    if (!found)
      throw fail("binding '" + decl.name + "' is declared on the host but shader '" + desc.shader +
                 "' has no such binding (shader bindings: " + shaderNames() + ")");
    if (found->set != 0) throw fail("binding '" + decl.name + "' must be in descriptor set 0");
    const ResourceKind expected =
        constantsInStorageBuffers && decl.kind == ResourceKind::UniformBuffer ? ResourceKind::StorageBuffer : decl.kind;
    if (found->kind != expected)
      throw fail("binding '" + decl.name + "' is declared as a " + kindName(decl.kind) + " but the shader has a " +
                 kindName(found->kind));
    if (decl.kind == ResourceKind::StorageImage) {
      const FormatInfo& hostFormat = formatInfo(decl.format);
      if (hostFormat.spirvImageFormat != found->spirvImageFormat) {
        const FormatInfo* shaderFormat = findFormatBySpirv(found->spirvImageFormat);
        throw fail("binding '" + decl.name + "' is declared " + hostFormat.name + " but the shader says " +
                   (shaderFormat ? shaderFormat->name : "an unsupported format"));
      }
    }
    // The shader's readonly/writeonly qualifiers must agree with the
    // declared access, so the declaration can be trusted for barriers.
    const bool hostReads = decl.access != Access::Write;
    const bool hostWrites = decl.access != Access::Read;
    if (hostWrites != found->writable || (decl.kind != ResourceKind::UniformBuffer &&
                                          decl.kind != ResourceKind::SampledImage && hostReads != found->readable))
      throw fail("binding '" + decl.name + "' is declared " + accessName(decl.access) + " but the shader declares it " +
                 (found->writable ? (found->readable ? "read-write" : "writeonly") : "readonly") +
                 " (mark shader inputs readonly and pure outputs writeonly)");
    matched.push_back(*found);
  }
  for (const ReflectedBinding& b : reflection.bindings)
    if (!declared.count(b.name)) throw fail("shader binding '" + b.name + "' is not declared on the host");
  return matched;
}

// Checks each declared constant layout against the shader's, and that every
// uniform block and the push constants have one.
void matchConstantLayouts(const PassDesc& desc, const ShaderReflection& reflection,
                          const std::vector<ReflectedBinding>& matched) {
  auto fail = [&](const std::string& why) { return GpuError("pass '" + desc.name + "': " + why); };
  auto declared = [&](const std::string& binding) {
    return std::find_if(desc.constants.begin(), desc.constants.end(),
                        [&](const ConstantsDecl& c) { return c.binding == binding; });
  };
  for (std::size_t i = 0; i < desc.resources.size(); ++i)
    if (desc.resources[i].kind == ResourceKind::UniformBuffer && declared(desc.resources[i].name) == desc.constants.end())
      throw fail("uniform buffer '" + desc.resources[i].name + "' has no declared layout (BOUNCE_CONSTANTS_LAYOUT)");
  if (reflection.pushConstantSize > 0 && declared("") == desc.constants.end())
    throw fail("the push constants have no declared layout (BOUNCE_CONSTANTS_LAYOUT with binding \"\")");

  for (const ConstantsDecl& constants : desc.constants) {
    const std::vector<BlockMember>* shaderMembers = nullptr;
    std::uint32_t shaderSize = 0;
    const std::string block = constants.binding.empty() ? "the push constants" : "'" + constants.binding + "'";
    if (constants.binding.empty()) {
      shaderMembers = &reflection.pushConstantMembers;
      shaderSize = reflection.pushConstantSize;
    } else {
      for (std::size_t i = 0; i < desc.resources.size(); ++i)
        if (desc.resources[i].name == constants.binding) {
          shaderMembers = &matched[i].members;
          shaderSize = matched[i].blockSize;
        }
      if (!shaderMembers) throw fail("a layout is declared for '" + constants.binding + "', which is not a resource");
    }
    const std::vector<BlockMember>& members = *shaderMembers;
    const std::string where = block + " (" + constants.type + ")";
    for (std::size_t m = 0; m < std::max(members.size(), constants.members.size()); ++m) {
      if (m >= members.size())
        throw fail(where + ": member '" + constants.members[m].name + "' is not in the shader's block");
      if (m >= constants.members.size())
        throw fail(where + ": the shader's member '" + members[m].name + "' is not declared on the host");
      const MemberLayout& host = constants.members[m];
      const BlockMember& shader = members[m];
      if (host.name != shader.name)
        throw fail(where + ": member " + std::to_string(m) + " is '" + host.name + "' on the host but '" +
                   shader.name + "' in the shader");
      if (host.offset != shader.offset || host.size != shader.size)
        throw fail(where + ": member '" + host.name + "' is at byte " + std::to_string(host.offset) + " (" +
                   std::to_string(host.size) + " bytes) on the host but at byte " + std::to_string(shader.offset) +
                   " (" + std::to_string(shader.size) + " bytes) in the shader");
    }
    if (constants.size < shaderSize)
      throw fail(where + ": the host struct has " + std::to_string(constants.size) + " bytes, the shader reads " +
                 std::to_string(shaderSize));
    // The pipeline's push-constant range is the host struct: it must be the shader's block exactly.
    if (constants.binding.empty() && constants.size != shaderSize)
      throw fail("push constants are declared as " + std::to_string(constants.size) +
                 " bytes but the shader's block is " + std::to_string(shaderSize) + " bytes");
  }
  if (reflection.pushConstantSize == 0 && desc.pushConstantSize() > 0)
    throw fail("push constants are declared as " + std::to_string(desc.pushConstantSize()) +
               " bytes but the shader has none");
}

}  // namespace

std::uint32_t PassDesc::pushConstantSize() const {
  for (const ConstantsDecl& c : constants)
    if (c.binding.empty()) return std::uint32_t(c.size);
  return 0;
}

void declareUsed(PassDesc& desc, std::span<const ResourceDecl> optional, bool constantsInStorageBuffers) {
  const ShaderReflection reflection =
      reflectShader(findShader(desc.shaders, desc.shader, constantsInStorageBuffers), desc.shader);
  for (const ResourceDecl& resource : optional) {
    const bool used = std::any_of(reflection.bindings.begin(), reflection.bindings.end(),
                                  [&](const ReflectedBinding& b) { return b.name == resource.name; });
    if (used) desc.resources.push_back(resource);
  }
}

ComputePass::ComputePass(Context& context, PassDesc desc) : context_(context), desc_(std::move(desc)) {
  std::span<const std::uint32_t> spirv = findShader(desc_.shaders, desc_.shader, context.constantsInStorageBuffers());
  reflection_ = reflectShader(spirv, desc_.shader);
  bindings_ = matchDeclarations(desc_, reflection_, context.constantsInStorageBuffers());
  matchConstantLayouts(desc_, reflection_, bindings_);

  VkDevice device = context.device();
  std::vector<VkDescriptorSetLayoutBinding> layoutBindings;
  for (std::size_t i = 0; i < bindings_.size(); ++i) {
    VkDescriptorSetLayoutBinding b{};
    b.binding = bindings_[i].binding;
    b.descriptorType = descriptorType(bindings_[i].kind);
    b.descriptorCount = 1;
    b.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    layoutBindings.push_back(b);
  }
  VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  // Push descriptors: bindings are written into the command buffer at
  // dispatch, so there are no descriptor pools or per-frame allocations.
  setInfo.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  setInfo.bindingCount = std::uint32_t(layoutBindings.size());
  setInfo.pBindings = layoutBindings.data();
  check(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &setLayout_), "vkCreateDescriptorSetLayout");

  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, desc_.pushConstantSize()};
  VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layoutInfo.setLayoutCount = 1;
  layoutInfo.pSetLayouts = &setLayout_;
  layoutInfo.pushConstantRangeCount = desc_.pushConstantSize() ? 1 : 0;
  layoutInfo.pPushConstantRanges = &range;
  check(vkCreatePipelineLayout(device, &layoutInfo, nullptr, &layout_), "vkCreatePipelineLayout");

  VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  moduleInfo.codeSize = spirv.size() * sizeof(std::uint32_t);
  moduleInfo.pCode = spirv.data();
  VkShaderModule module = VK_NULL_HANDLE;
  check(vkCreateShaderModule(device, &moduleInfo, nullptr, &module), "vkCreateShaderModule");
  VkComputePipelineCreateInfo pipelineInfo{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  pipelineInfo.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  pipelineInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  pipelineInfo.stage.module = module;
  pipelineInfo.stage.pName = "main";
  pipelineInfo.layout = layout_;
  VkResult result = vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipelineInfo, nullptr, &pipeline_);
  vkDestroyShaderModule(device, module, nullptr);
  check(result, ("creating the pipeline of pass '" + desc_.name + "'").c_str());
  context.nameObject(VK_OBJECT_TYPE_PIPELINE, std::uint64_t(pipeline_), desc_.name);
}

ComputePass::~ComputePass() {
  VkDevice device = context_.device();
  vkDestroyPipeline(device, pipeline_, nullptr);
  vkDestroyPipelineLayout(device, layout_, nullptr);
  vkDestroyDescriptorSetLayout(device, setLayout_, nullptr);
}

}  // namespace bounce::gpu
