// Internal helpers of gi::EnvironmentPrefilter (include/bounce/gi.h), shared
// with the tools that build environments for it.
#pragma once

#include <cstdint>
#include <vector>

#include "gpu/pass.h"

namespace bounce::gi {

// Levels of the prefiltered chain for an environment `height` texels tall:
// down to a level 8 texels tall (so even roughness 1 keeps some shape), at
// most maxMipCount, at least 1.
std::uint32_t prefilteredMipCount(std::uint32_t height, std::uint32_t maxMipCount);

// Both passes of the prefilter (gi/unit_catalog.h).
std::vector<gpu::PassDesc> environmentPrefilterPasses();

}  // namespace bounce::gi
