// The scene bridge as the library runs it (ContextDesc::sceneBridge,
// shaders/gi/scene_bridge.glsl): the shaders compiled with the engine's
// bridge take the place of the library's own, each pass declares the
// bridge's resources its shader uses (found by name in its SPIR-V, like
// every other binding), and every frame the engine's buffers and images
// behind them are checked and wrapped, then bound to the passes that
// declare them.
#pragma once

#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "bounce/gi.h"
#include "gpu/context.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"

namespace bounce::gi {

class SceneBridgeBinding {
 public:
  // Throws Error for a bridge that cannot be run: a shader without name or
  // words, a resource without a name or named twice, a resource named like
  // one of the library's own bindings (gIn_Frame, ...).
  SceneBridgeBinding(gpu::Context& context, const SceneBridge& bridge);
  ~SceneBridgeBinding();

  const std::string& name() const { return name_; }
  // Whether rays reach the scene (false for "none": screen space only).
  bool traces() const { return !shaders_.empty(); }

  // `desc` as this bridge runs it: its shader from the bridge's table (when
  // it has one of that name), plus the bridge's resources and those of
  // `optional` (resources of shared include files) that shader uses.
  gpu::PassDesc adapt(gpu::PassDesc desc, std::span<const gpu::ResourceDecl> optional = {}) const;

  // This frame's resources: every declared one bound, nothing else, each of
  // the kind declared (throws Error naming the resource otherwise).
  void take(const FrameInputs& frame);
  // The buffer this frame's passes count their world rays in
  // (gi/world_ray_count.glsl's gOut_WorldRays), bound with the bridge's resources.
  void countRaysInto(gpu::Buffer& counters) { rayCounters_ = &counters; }

  // `own` and the bridge resources `pass` declares, for one dispatch.
  std::vector<gpu::Bind> binds(const gpu::ComputePass& pass, std::initializer_list<gpu::Bind> own) const;

 private:
  gpu::Context& context_;
  std::string name_;
  std::vector<std::string> shaderNames_;  // owns what shaders_ points to
  std::vector<gpu::EmbeddedShader> shaders_;
  std::vector<SceneResourceDecl> resources_;
  // This frame's wrappers, one per resource, in resources_ order.
  std::vector<std::unique_ptr<gpu::Buffer>> buffers_;
  std::vector<std::unique_ptr<gpu::Image>> images_;
  std::vector<VkSampler> samplers_;
  gpu::Buffer* rayCounters_ = nullptr;
};

}  // namespace bounce::gi
