#include "gi/scene_bridge.h"

#include <algorithm>
#include <set>

#include "gi/engine_images.h"
#include "gpu/error.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

gpu::ResourceKind kindOf(SceneResourceKind kind) {
  switch (kind) {
    case SceneResourceKind::StorageBuffer: return gpu::ResourceKind::StorageBuffer;
    case SceneResourceKind::SampledImage: return gpu::ResourceKind::SampledImage;
  }
  return gpu::ResourceKind::StorageBuffer;
}

std::string where(const std::string& bridge) { return "gi: scene bridge '" + bridge + "'"; }

}  // namespace

SceneBridgeBinding::SceneBridgeBinding(gpu::Context& context, const SceneBridge& bridge)
    : context_(context), name_(bridge.name), resources_(bridge.resources) {
  for (const ShaderCode& code : bridge.shaders) {
    if (!code.name || !*code.name || !code.words || code.wordCount == 0)
      throw Error(where(name_) + ": a shader has no name or no SPIR-V words");
    shaderNames_.emplace_back(code.name);
  }
  shaders_.reserve(bridge.shaders.size());
  for (std::size_t i = 0; i < bridge.shaders.size(); ++i)
    shaders_.push_back({shaderNames_[i].c_str(), bridge.shaders[i].constantsInStorageBuffers,
                        bridge.shaders[i].words, bridge.shaders[i].wordCount});
  std::set<std::string> names;
  for (const SceneResourceDecl& resource : resources_) {
    if (resource.name.empty()) throw Error(where(name_) + ": a resource has no name");
    if (!names.insert(resource.name).second)
      throw Error(where(name_) + ": resource '" + resource.name + "' is declared twice");
    // The library's own bindings are gIn_*, gOut_*, gPrev_* of its passes;
    // the ones every pass shares must never be shadowed.
    if (resource.name == "gIn_Frame" || resource.name == "gIn_ViewZ" || resource.name == "gIn_NormalRoughness")
      throw Error(where(name_) + ": resource '" + resource.name + "' has the name of one of the library's bindings");
  }
  if (!resources_.empty() && shaders_.empty())
    throw Error(where(name_) +
                ": declares resources but no shaders; bounce_embed_shaders(... SCENE_BRIDGE) makes the shader table");
}

SceneBridgeBinding::~SceneBridgeBinding() = default;

gpu::PassDesc SceneBridgeBinding::adapt(gpu::PassDesc desc, std::span<const gpu::ResourceDecl> optional) const {
  const bool bridged = std::any_of(shaders_.begin(), shaders_.end(),
                                   [&](const gpu::EmbeddedShader& s) { return desc.shader == s.name; });
  // Without it in the bridge's table, the library's own shader runs.
  if (bridged) desc.shaders = shaders_;
  gpu::declareUsed(desc, optional, context_.constantsInStorageBuffers());
  // Layouts of optional constant blocks the shader does not have go too.
  std::erase_if(desc.constants, [&](const gpu::ConstantsDecl& layout) {
    return !layout.binding.empty() &&
           std::none_of(desc.resources.begin(), desc.resources.end(),
                        [&](const gpu::ResourceDecl& r) { return r.name == layout.binding; });
  });
  // Every shader that includes the bridge counts its rays (gi/world_ray_count.glsl).
  gpu::declareUsed(desc,
                   std::vector<gpu::ResourceDecl>{{"gOut_WorldRays", gpu::Access::ReadWrite, VK_FORMAT_UNDEFINED,
                                                   "world rays counted by purpose", gpu::ResourceKind::StorageBuffer}},
                   context_.constantsInStorageBuffers());
  if (!bridged) return desc;
  std::vector<gpu::ResourceDecl> declared;
  for (const SceneResourceDecl& resource : resources_)
    declared.push_back({resource.name, gpu::Access::Read, VK_FORMAT_UNDEFINED, "scene bridge: " + resource.purpose,
                        kindOf(resource.kind)});
  gpu::declareUsed(desc, declared, context_.constantsInStorageBuffers());
  return desc;
}

void SceneBridgeBinding::take(const FrameInputs& frame) {
  const std::string bridge = where(name_);
  for (const SceneResource& given : frame.sceneResources)
    if (std::none_of(resources_.begin(), resources_.end(),
                     [&](const SceneResourceDecl& d) { return d.name == given.name; }))
      throw Error(bridge + ": FrameInputs::sceneResources has '" + given.name + "', which the bridge does not declare");
  std::vector<std::unique_ptr<gpu::Buffer>> buffers(resources_.size());
  std::vector<std::unique_ptr<gpu::Image>> images(resources_.size());
  std::vector<VkSampler> samplers(resources_.size(), VK_NULL_HANDLE);
  for (std::size_t i = 0; i < resources_.size(); ++i) {
    const SceneResourceDecl& decl = resources_[i];
    const auto given = std::find_if(frame.sceneResources.begin(), frame.sceneResources.end(),
                                    [&](const SceneResource& r) { return r.name == decl.name; });
    const std::string what = bridge + ": resource '" + decl.name + "'";
    if (given == frame.sceneResources.end()) throw Error(what + " is not in FrameInputs::sceneResources");
    if (decl.kind == SceneResourceKind::SampledImage) {
      const ImageRef& ref = given->image;
      if (!ref.image || !ref.view || ref.width == 0 || ref.height == 0)
        throw Error(what + " is a sampled image; its image, view or size is missing");
      if (ref.layout != VK_IMAGE_LAYOUT_GENERAL && ref.layout != VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL)
        throw Error(what + " is in " + gpu::layoutName(ref.layout) +
                    "; the library samples bridge images in place, in GENERAL or SHADER_READ_ONLY_OPTIMAL");
      if (!given->sampler) throw Error(what + " has no sampler");
      images[i] = std::make_unique<gpu::Image>(context_, engineImage(ref, "bridge." + decl.name));
      images[i]->setSampledLayout(ref.layout);
      samplers[i] = given->sampler;
    } else {
      const BufferRef& ref = given->buffer;
      if (!ref.buffer || ref.size == 0) throw Error(what + " is a buffer; its handle or size is missing");
      gpu::ExternalBuffer external{.buffer = ref.buffer, .size = ref.size, .name = "bridge." + decl.name};
      external.state.writeStage = ref.stage;
      external.state.writeAccess = ref.access & gpu::kWriteAccessFlags;
      buffers[i] = std::make_unique<gpu::Buffer>(context_, external);
    }
  }
  buffers_ = std::move(buffers);
  images_ = std::move(images);
  samplers_ = std::move(samplers);
}

std::vector<gpu::Bind> SceneBridgeBinding::binds(const gpu::ComputePass& pass,
                                                 std::initializer_list<gpu::Bind> own) const {
  std::vector<gpu::Bind> bridge;
  for (std::size_t i = 0; i < resources_.size(); ++i) {
    if (images_.size() > i && images_[i])
      bridge.emplace_back(resources_[i].name, *images_[i], samplers_[i]);
    else if (buffers_.size() > i && buffers_[i])
      bridge.emplace_back(resources_[i].name, *buffers_[i]);
  }
  if (rayCounters_) bridge.emplace_back("gOut_WorldRays", *rayCounters_);
  std::vector<gpu::Bind> list(own);
  for (const gpu::Bind& bind : gpu::bindsDeclaredBy(pass, bridge)) list.push_back(bind);
  return list;
}

}  // namespace bounce::gi
