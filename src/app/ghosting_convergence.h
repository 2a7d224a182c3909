// bounce ghosting's events that change no pixel's history region but the
// whole frame's light: --event light (materials change at the event frame)
// and --event cut (a camera cut in place). ghosting_convergence.cpp says
// what they measure.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "bounce/gi_settings.h"
#include "gpu/frame_loop.h"
#include "render/frame_pipeline.h"
#include "render/frame_renderer.h"
#include "render/gi_bridge.h"

namespace bounce::app {

// What every ghosting event renders with: the device (its name printed),
// the renderer, its frame loop and the GI library, made after the frame's
// memory is checked, and the last frame's view (the next frame's history).
struct GhostingRig {
  GhostingRig(const GhostingOptions& options, const scene::Scene& scene,
              const render::FrameRendererOptions& rendererOptions, const gi::Settings& settings);
  // Records a frame of the renderer and the GI library; returns its index.
  std::uint64_t record(const render::FrameView& view);

  std::unique_ptr<gpu::Context> context;
  std::unique_ptr<render::FramePipeline> pipeline;
  // The pipeline's parts.
  render::FrameRenderer* renderer = nullptr;
  gpu::FrameLoop* loop = nullptr;
  render::GiBridge* gi = nullptr;
};

// Runs `bounce ghosting --event light|sun|cut`; returns the exit code.
int runConvergence(const GhostingOptions& options);

// What both kinds of event write to ghosting.json about the run: warm-up,
// frames, size, references, GI mode and the settings that differ from the
// library's defaults, device, seconds.
nlohmann::json ghostingRunJson(const GhostingOptions& options, const gi::Settings& settings, const std::string& device,
                               double seconds);

}  // namespace bounce::app
