// The renderer's scene bridge for the GI library (bounce::gi::SceneBridge,
// shaders/render/scene_bridge/scene_bridge_impl.glsl): the library's rays
// traced through the renderer's BVH and shaded with its materials, textures
// and lights. The worked example of docs/integration.md, "A scene bridge".
#pragma once

#include <cstdint>
#include <vector>

#include "bounce/gi.h"
#include "gpu/resources.h"
#include "render/frame_renderer.h"

namespace bounce::render {

// "bvh": every GI shader compiled with the renderer's bridge, and the
// resources it reads (the renderer's scene access and lights, its frame
// block as gScene_Frame).
gi::SceneBridge bvhSceneBridge();

// The bridge's resources for frame `frameIndex` of `renderer`, and the
// renderer's buffers behind them (whose states sceneBuffersRead() updates
// once the library has read them).
struct SceneResources {
  std::vector<gi::SceneResource> resources;
  std::vector<gpu::Buffer*> buffers;
};
SceneResources bvhSceneResources(FrameRenderer& renderer, std::uint64_t frameIndex);

// After the library's record(): the buffers were read by compute shaders,
// so the renderer's next write waits for those reads.
void sceneBuffersRead(const std::vector<gpu::Buffer*>& buffers);

}  // namespace bounce::render
