#include "render/scene_bridge.h"

#include <span>

#include "render/gi_bridge.h"

namespace bounce::render {

// The GI library's shaders compiled with shaders/render/scene_bridge/ (CMakeLists.txt).
std::span<const gi::ShaderCode> sceneBridgeShaders();

namespace {

// The renderer's frame block is the library's gIn_Frame by name; in the
// bridge it is gScene_Frame (scene_bridge_impl.glsl).
std::string bridgeName(std::string_view rendererName) {
  return rendererName == "gIn_Frame" ? "gScene_Frame" : std::string(rendererName);
}

// The frame block is a storage buffer in the bridge (SCENE_FRAME_STORAGE).
gi::SceneResourceKind kindOf(gpu::ResourceKind kind) {
  return kind == gpu::ResourceKind::SampledImage ? gi::SceneResourceKind::SampledImage
                                                 : gi::SceneResourceKind::StorageBuffer;
}

}  // namespace

gi::SceneBridge bvhSceneBridge() {
  gi::SceneBridge bridge;
  bridge.name = "bvh";
  for (const gi::ShaderCode& code : sceneBridgeShaders()) bridge.shaders.push_back(code);
  for (const gpu::ResourceDecl& decl : FrameRenderer::sceneResources())
    bridge.resources.push_back({bridgeName(decl.name), kindOf(decl.kind), decl.purpose});
  bridge.resources.push_back({"gIn_Lights", gi::SceneResourceKind::StorageBuffer, "punctual lights"});
  return bridge;
}

SceneResources bvhSceneResources(FrameRenderer& renderer, std::uint64_t frameIndex) {
  std::vector<gpu::Bind> binds = renderer.sceneBinds(frameIndex);
  binds.emplace_back("gIn_Lights", renderer.lights());
  SceneResources made;
  for (const gpu::Bind& bind : binds) {
    gi::SceneResource resource;
    resource.name = bridgeName(bind.name);
    if (bind.image) {
      resource.image = imageRef(*bind.image);
      resource.sampler = bind.sampler;
    } else {
      const gpu::SyncState& state = bind.buffer->sync();
      resource.buffer = {.buffer = bind.buffer->handle(),
                         .size = bind.buffer->size(),
                         .stage = state.writeStage,
                         .access = state.writeAccess};
      made.buffers.push_back(bind.buffer);
    }
    made.resources.push_back(std::move(resource));
  }
  return made;
}

void sceneBuffersRead(const std::vector<gpu::Buffer*>& buffers) {
  for (gpu::Buffer* buffer : buffers) {
    // The library waited for the last write and read in compute shaders.
    gpu::SyncState& state = buffer->sync();
    state.readStages |= VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
  }
}

}  // namespace bounce::render
