#include "gpu/spirv_reflect.h"

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <spirv/unified1/spirv.hpp>

#include "gpu/error.h"

namespace bounce::gpu {
namespace {

struct TypeInfo {
  spv::Op op = spv::OpNop;
  std::vector<std::uint32_t> operands;  // the instruction's words after the result id
};

std::string readString(std::span<const std::uint32_t> words) {
  std::string text;
  for (std::uint32_t word : words) {
    for (int i = 0; i < 4; ++i) {
      char c = char((word >> (8 * i)) & 0xffu);
      if (c == '\0') return text;
      text.push_back(c);
    }
  }
  return text;
}

}  // namespace

const char* kindName(ResourceKind kind) {
  switch (kind) {
    case ResourceKind::StorageImage:
      return "storage image";
    case ResourceKind::SampledImage:
      return "sampled image";
    case ResourceKind::StorageBuffer:
      return "storage buffer";
    case ResourceKind::UniformBuffer:
      return "uniform buffer";
  }
  return "?";
}

ShaderReflection reflectShader(std::span<const std::uint32_t> spirv, const std::string& shaderName) {
  auto fail = [&](const std::string& why) -> GpuError { return GpuError("shader '" + shaderName + "': " + why); };
  if (spirv.size() < 5 || spirv[0] != spv::MagicNumber) throw fail("not SPIR-V");

  std::map<std::uint32_t, std::string> names;
  std::map<std::uint32_t, std::map<std::uint32_t, std::string>> memberNames;
  std::map<std::uint32_t, std::map<spv::Decoration, std::uint32_t>> decorations;
  std::map<std::uint32_t, std::map<std::uint32_t, std::map<spv::Decoration, std::uint32_t>>> memberDecorations;
  std::map<std::uint32_t, TypeInfo> types;
  std::map<std::uint32_t, std::uint32_t> constants;
  struct Variable {
    std::uint32_t id, pointerType;
    spv::StorageClass storage;
  };
  std::vector<Variable> variables;
  std::array<std::uint32_t, 3> localSizeIds{};
  ShaderReflection result;

  for (std::size_t at = 5; at < spirv.size();) {
    const std::uint32_t count = spirv[at] >> 16;
    const auto op = spv::Op(spirv[at] & 0xffffu);
    if (count == 0 || at + count > spirv.size()) throw fail("truncated instruction");
    std::span<const std::uint32_t> w = spirv.subspan(at + 1, count - 1);
    switch (op) {
      case spv::OpName:
        names[w[0]] = readString(w.subspan(1));
        break;
      case spv::OpMemberName:
        memberNames[w[0]][w[1]] = readString(w.subspan(2));
        break;
      case spv::OpDecorate:
        decorations[w[0]][spv::Decoration(w[1])] = w.size() > 2 ? w[2] : 1;
        break;
      case spv::OpMemberDecorate:
        memberDecorations[w[0]][w[1]][spv::Decoration(w[2])] = w.size() > 3 ? w[3] : 1;
        break;
      case spv::OpExecutionMode:
        if (spv::ExecutionMode(w[1]) == spv::ExecutionModeLocalSize) std::copy_n(w.begin() + 2, 3, result.localSize);
        break;
      case spv::OpExecutionModeId:
        // glslc's optimizer for Vulkan 1.3 states the size as constant ids;
        // resolved below, once the constants have been read.
        if (spv::ExecutionMode(w[1]) == spv::ExecutionModeLocalSizeId)
          std::copy_n(w.begin() + 2, 3, localSizeIds.begin());
        break;
      case spv::OpTypeInt:
      case spv::OpTypeFloat:
      case spv::OpTypeVector:
      case spv::OpTypeMatrix:
      case spv::OpTypeImage:
      case spv::OpTypeSampler:
      case spv::OpTypeSampledImage:
      case spv::OpTypeArray:
      case spv::OpTypeRuntimeArray:
      case spv::OpTypeStruct:
      case spv::OpTypePointer:
        types[w[0]] = {op, std::vector<std::uint32_t>(w.begin() + 1, w.end())};
        break;
      case spv::OpConstant:
        constants[w[1]] = w[2];
        break;
      case spv::OpVariable:
        variables.push_back({w[1], w[0], spv::StorageClass(w[2])});
        break;
      default:
        break;
    }
    at += count;
  }

  if (localSizeIds[0]) {
    for (int axis = 0; axis < 3; ++axis) {
      auto constant = constants.find(localSizeIds[axis]);
      if (constant == constants.end()) throw fail("workgroup size is not a constant");
      result.localSize[axis] = constant->second;
    }
  }

  // Byte size of a type inside a block, from the offsets and strides the
  // compiler decorated it with.
  auto sizeOf = [&](auto&& self, std::uint32_t typeId) -> std::uint32_t {
    const TypeInfo& t = types.at(typeId);
    switch (t.op) {
      case spv::OpTypeInt:
      case spv::OpTypeFloat:
        return t.operands[0] / 8;
      case spv::OpTypeVector:
        return t.operands[1] * self(self, t.operands[0]);
      case spv::OpTypeMatrix:
        return t.operands[1] * self(self, t.operands[0]);
      case spv::OpTypeArray:
        return constants.at(t.operands[1]) * decorations[typeId][spv::DecorationArrayStride];
      case spv::OpTypeStruct: {
        std::uint32_t size = 0;
        for (std::uint32_t m = 0; m < t.operands.size(); ++m) {
          auto& member = memberDecorations[typeId][m];
          std::uint32_t memberSize = member.count(spv::DecorationMatrixStride)
                                         ? types.at(t.operands[m]).operands[1] * member[spv::DecorationMatrixStride]
                                         : self(self, t.operands[m]);
          size = std::max(size, member[spv::DecorationOffset] + memberSize);
        }
        return size;
      }
      default:
        throw fail("unsupported type in a buffer or push-constant block");
    }
  };
  auto memberSizeOf = [&](std::uint32_t structId, std::uint32_t member) {
    auto& decorated = memberDecorations[structId][member];
    const std::uint32_t memberType = types.at(structId).operands[member];
    return decorated.count(spv::DecorationMatrixStride)
               ? types.at(memberType).operands[1] * decorated[spv::DecorationMatrixStride]
               : sizeOf(sizeOf, memberType);
  };
  // The members of a block type, or of its only member when that is a struct.
  auto layoutOf = [&](std::uint32_t blockId) {
    std::uint32_t structId = blockId;
    const TypeInfo& block = types.at(blockId);
    if (block.operands.size() == 1 && types.at(block.operands[0]).op == spv::OpTypeStruct)
      structId = block.operands[0];
    std::vector<BlockMember> members;
    const TypeInfo& type = types.at(structId);
    for (std::uint32_t m = 0; m < type.operands.size(); ++m)
      members.push_back({memberNames[structId][m], memberDecorations[structId][m][spv::DecorationOffset],
                         memberSizeOf(structId, m)});
    return members;
  };

  for (const Variable& v : variables) {
    const TypeInfo& pointer = types.at(v.pointerType);
    std::uint32_t typeId = pointer.operands[1];
    if (v.storage == spv::StorageClassPushConstant) {
      result.pushConstantSize = sizeOf(sizeOf, typeId);
      result.pushConstantMembers = layoutOf(typeId);
      continue;
    }
    if (v.storage != spv::StorageClassUniformConstant && v.storage != spv::StorageClassUniform &&
        v.storage != spv::StorageClassStorageBuffer)
      continue;

    ReflectedBinding binding;
    binding.name = names[v.id];
    binding.set = decorations[v.id][spv::DecorationDescriptorSet];
    binding.binding = decorations[v.id][spv::DecorationBinding];
    const TypeInfo* type = &types.at(typeId);
    if (type->op == spv::OpTypeArray || type->op == spv::OpTypeRuntimeArray)
      throw fail("binding '" + binding.name + "' is an array of descriptors, which Bounce does not support");
    auto& varDecorations = decorations[v.id];
    binding.writable = !varDecorations.count(spv::DecorationNonWritable);
    binding.readable = !varDecorations.count(spv::DecorationNonReadable);

    if (type->op == spv::OpTypeImage) {
      // operands: sampled type, dim, depth, arrayed, ms, sampled, format
      if (type->operands[5] != 2)
        throw fail("binding '" + binding.name + "' is a separate texture; use a combined sampler2D");
      binding.kind = ResourceKind::StorageImage;
      binding.spirvImageFormat = type->operands[6];
    } else if (type->op == spv::OpTypeSampledImage) {
      binding.kind = ResourceKind::SampledImage;
      binding.writable = false;
    } else if (type->op == spv::OpTypeSampler) {
      throw fail("binding '" + binding.name + "' is a separate sampler; use a combined sampler2D");
    } else if (type->op == spv::OpTypeStruct) {
      bool bufferBlock = decorations[typeId].count(spv::DecorationBufferBlock) > 0;
      binding.kind = (v.storage == spv::StorageClassStorageBuffer || bufferBlock) ? ResourceKind::StorageBuffer
                                                                                  : ResourceKind::UniformBuffer;
      if (binding.name.empty()) binding.name = names[typeId];
      // readonly / writeonly on a buffer block is decorated on every member.
      auto& members = memberDecorations[typeId];
      const std::size_t memberCount = type->operands.size();
      auto allMembersHave = [&](spv::Decoration d) {
        for (std::uint32_t m = 0; m < memberCount; ++m)
          if (!members[m].count(d)) return false;
        return memberCount > 0;
      };
      if (allMembersHave(spv::DecorationNonWritable)) binding.writable = false;
      if (allMembersHave(spv::DecorationNonReadable)) binding.readable = false;
      if (binding.kind == ResourceKind::UniformBuffer) binding.writable = false;
      if (std::none_of(type->operands.begin(), type->operands.end(), [&](std::uint32_t member) {
            return types.at(member).op == spv::OpTypeRuntimeArray;
          })) {
        binding.members = layoutOf(typeId);
        binding.blockSize = sizeOf(sizeOf, typeId);
      }
    } else {
      continue;
    }
    if (binding.name.empty()) throw fail("a binding has no name (compile shaders with names kept)");
    result.bindings.push_back(binding);
  }
  std::sort(result.bindings.begin(), result.bindings.end(),
            [](const ReflectedBinding& a, const ReflectedBinding& b) { return a.binding < b.binding; });
  return result;
}

}  // namespace bounce::gpu
