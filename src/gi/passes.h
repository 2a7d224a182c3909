// The host declarations of every GI pass: name (timestamp key, debug label,
// dump prefix), shader, and each resource with its access, format and
// purpose, checked against the shader's SPIR-V when the pass is created.
// The shaders are in shaders/gi/ (folder = stage, file = pass).
#pragma once

#include <string>

#include "gpu/pass.h"

namespace bounce::gi {

gpu::PassDesc storeHistoryPass();
gpu::PassDesc brightPixelsPass();
gpu::PassDesc brightPixelsReducePass();
gpu::PassDesc gatherPass();
gpu::PassDesc temporalReusePass();
gpu::PassDesc spatialReusePass();
gpu::PassDesc resolvePass();
gpu::PassDesc temporalFilterPass();
gpu::PassDesc compositePass();
// For --dump-stages only; `after` names the reservoir pass it shows
// (the pass is then called gi.diffuse.reservoir_view.<after>).
gpu::PassDesc reservoirViewPass(const std::string& after);

// Push constants of gi.diffuse.spatial_reuse.
struct SpatialReuseParams {
  float radius;
  std::uint32_t samples;
  std::uint32_t passIndex;
};

}  // namespace bounce::gi
