// The frame's settings: gi.input.* (how the engine's images are read) and gi.restir, gi.seed, gi.world_ray_budget: its
// section of the settings table (gi/settings_table.h).
#include <array>

#include "gi/settings_table.h"

namespace bounce::gi::settings_table {
namespace {

constexpr std::array kEntries{
    Entry{"input.motion_units", inInput(&InputSettings::motionUnits), kNoBounds,
          "what the engine's motion vectors are in: pixels, or uv (fractions of the render size)"},
    Entry{"input.motion_scale_x", inInput(&InputSettings::motionScaleX), closed(-1e6, 1e6),
          "multiplies the motion vectors' x (after the units): -1 for engines whose x points the other way"},
    Entry{"input.motion_scale_y", inInput(&InputSettings::motionScaleY), closed(-1e6, 1e6),
          "multiplies the motion vectors' y (after the units): -1 for engines whose y points up, or that store "
          "current - previous"},
    Entry{"restir", inSettings(&Settings::restir), kNoBounds,
          "temporal and spatial reuse (off: the no-reuse baseline; gathering, resolve and filters stay)"},
    Entry{"seed", inSettings(&Settings::seed), kAnyUint, "random seed; another seed gives other, independent noise"},
    Entry{"world_ray_budget", inSettings(&Settings::worldRayBudget), aboveUpTo(0, 64),
          "world rays per pixel and frame the library may cast through a scene bridge, at most: after what the "
          "settings fix and one ray candidate, sky tests in spatial reuse, then the other ray candidates are cut to "
          "fit (cache updates and the bridge's shadow rays not counted)"},
};

}  // namespace

std::span<const Entry> frameSection() { return kEntries; }

}  // namespace bounce::gi::settings_table
