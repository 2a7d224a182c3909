// Internal helpers of gi::EnvironmentPrefilter (include/bounce/gi.h), shared
// with the tools that build environments for it.
#pragma once

#include <cstdint>

namespace bounce::gi {

// Levels of the prefiltered chain for an environment `height` texels tall:
// down to a level 8 texels tall (so even roughness 1 keeps some shape), at
// most maxMipCount, at least 1.
std::uint32_t prefilteredMipCount(std::uint32_t height, std::uint32_t maxMipCount);

}  // namespace bounce::gi
