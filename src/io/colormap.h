// Colour maps for pictures of scalar data (error maps, false-colour stage
// dumps, plots): one table, used by metrics/, gpu/ and app/ alike.
#pragma once

#include <array>
#include <cstdint>

namespace bounce::io {

// The magma colour map (matplotlib's, which the FLIP tool uses for its error
// maps) as 8-bit sRGB, for a value in [0,1] (clamped; NaN shows as 0).
std::array<std::uint8_t, 3> magma(float value);

}  // namespace bounce::io
