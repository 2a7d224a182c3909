// The host declarations of the diffuse branch's passes: name (timestamp
// key, debug label, dump prefix), shader, each resource with its access,
// format and purpose, and the layouts of their constants, all checked
// against the shader's SPIR-V when the pass is created. The shaders are in
// shaders/gi/diffuse/ (folder = stage, file = pass).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "gi/diffuse/diffuse_common.glsl"
#include "gpu/pass.h"

namespace bounce::gi {

gpu::PassDesc brightPixelsPass();
gpu::PassDesc brightPixelsReducePass();
gpu::PassDesc gatherPass();
// What the gather's ray candidates add when a scene bridge traces: the
// march depth and the radiance cache (SceneBridgeBinding::adapt declares
// those the shader uses).
std::vector<gpu::ResourceDecl> gatherRayResources();
// gi.diffuse.world_candidates: the gather's ray candidates the march left,
// traced through the bridge one thread per pixel (with a bridge that traces).
gpu::PassDesc worldCandidatesPass();
gpu::PassDesc temporalReusePass();
gpu::PassDesc spatialReusePass();
// What spatial reuse adds when a scene bridge traces: the visibility tests
// it queues (gi/diffuse/neighbour_tests.glsl).
std::vector<gpu::ResourceDecl> neighbourTestResources();
// gi.diffuse.neighbour_visibility: those tests, one ray per invocation, and
// gi.diffuse.spatial_normalize: their verdicts counted into the reservoirs
// (with a bridge that traces).
gpu::PassDesc neighbourVisibilityPass();
gpu::PassDesc spatialNormalizePass();
// With gi.diffuse.visibility hybrid and a bridge that traces: each
// reservoir's sample tested from its own surface, hidden ones dropped.
gpu::PassDesc sampleVisibilityPass();
gpu::PassDesc sampleMarchPass();
gpu::PassDesc resolvePass();
gpu::PassDesc temporalFilterPass();
// For --dump-stages only; `after` names the reservoir pass it shows
// (the pass is then called gi.diffuse.reservoir_view.<after>).
gpu::PassDesc reservoirViewPass(const std::string& after);

// Push constants of gi.diffuse.spatial_reuse, neighbour_visibility and
// spatial_normalize (gi/diffuse/neighbour_tests.glsl).
struct SpatialReuseParams {
  float radius;
  std::uint32_t samples;
  std::uint32_t passIndex;
  std::uint32_t slotsPerPixel;
};

// Push constants of gi.diffuse.bright_pixels_reduce: how much of each level
// this frame's render size fills.
struct BrightReduceParams {
  std::uint32_t inputSize[2];
  std::uint32_t outputSize[2];
};

}  // namespace bounce::gi
