// The host declarations of the specular branch's passes: name (timestamp
// key, debug label, dump prefix), shader, each resource with its access,
// format and purpose, and the layout of their constants, all checked
// against the shader's SPIR-V when the pass is created. The shaders are in
// shaders/gi/specular/ (folder = stage, file = pass).
#pragma once

#include <vector>

#include "gpu/pass.h"

namespace bounce::gi {

gpu::PassDesc specularTracePass();
// gi.specular.world_trace: the rays the trace left (its queue), traced
// through the bridge one thread each (with a bridge that traces).
gpu::PassDesc specularWorldTracePass();
// What the trace adds when a scene bridge traces: the radiance cache
// (SceneBridgeBinding::adapt declares those the shader uses).
std::vector<gpu::ResourceDecl> specularTraceRayResources();
gpu::PassDesc specularTemporalReusePass();
gpu::PassDesc specularSpatialReusePass();
gpu::PassDesc specularResolvePass();
gpu::PassDesc specularTemporalFilterPass();
// For --dump-stages only: reservoir M and hit distance.
gpu::PassDesc specularValidationPass();

}  // namespace bounce::gi
