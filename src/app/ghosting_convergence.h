// bounce ghosting's events that change no pixel's history region but the
// whole frame's light: --event light (materials change at the event frame)
// and --event cut (a camera cut in place). ghosting_convergence.cpp says
// what they measure.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "bounce/gi_settings.h"

namespace bounce::app {

// Runs `bounce ghosting --event light|cut`; returns the exit code.
int runConvergence(const GhostingOptions& options);

// What both kinds of event write to ghosting.json about the run: warm-up,
// frames, size, references, GI mode and the settings that differ from the
// library's defaults, device, seconds.
nlohmann::json ghostingRunJson(const GhostingOptions& options, const gi::Settings& settings, const std::string& device,
                               double seconds);

}  // namespace bounce::app
