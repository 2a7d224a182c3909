// The radiance cache's settings, gi.cache.*: its section of the settings table (gi/settings_table.h).
#include <array>

#include "gi/cache/cache_types.glsl"
#include "gi/settings_table.h"

namespace bounce::gi::settings_table {
namespace {

constexpr std::array kEntries{
    Entry{"cache.enabled", inCache(&CacheSettings::enabled), kNoBounds,
          "the world-space radiance cache lights what world rays hit off screen (more bounces; needs a scene bridge)"},
    Entry{"cache.memory_mib", inCache(&CacheSettings::memoryMib), closed(1, 128),
          "radiance cache: device memory for its cells at most, in MiB"},
    Entry{"cache.cell_size", inCache(&CacheSettings::cellSize), closed(0.0005, 0.5),
          "radiance cache: a cell's edge as a fraction of its distance to the camera (rounded to a power of two)"},
    Entry{"cache.update_rays", inCache(&CacheSettings::updateRays), closed(0, 1 << 21),
          "radiance cache: closest-hit rays per frame of its update paths, at most"},
    Entry{"cache.update_bounces", inCache(&CacheSettings::updateBounces), closed(1, shared::kCacheMaxBounces),
          "radiance cache: surfaces each update path bounces off at most (bounces of light carried in one frame)"},
    Entry{"cache.history_samples", inCache(&CacheSettings::historySamples), closed(1, 4096),
          "radiance cache: a cell's value averages at most this many samples (fewer: follows light changes faster)"},
    Entry{"cache.max_age", inCache(&CacheSettings::maxAge), closed(1, 1 << 20),
          "radiance cache: cells nobody used for this many frames are evicted"},
    Entry{"cache.inject_stride", inCache(&CacheSettings::injectStride), closed(1, 64),
          "radiance cache: the screen fills cells from one pixel of every stride x stride block of the last frame"},
    Entry{"cache.direct_light", inCache(&CacheSettings::directLight), kNoBounds,
          "radiance cache: cells also hold the direct light at their point, and the diffuse ray candidates' hits "
          "take theirs from there instead of a shadow ray each"},
};

}  // namespace

std::span<const Entry> cacheSection() { return kEntries; }

}  // namespace bounce::gi::settings_table
