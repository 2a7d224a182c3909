// Numbers a user typed (an option's value, a script's argument), read the
// same way everywhere: the whole token, in C locale, decimal or scientific.
#pragma once

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>

namespace bounce::util {

// `text` as a finite double, or nullopt when it is not one: empty, not all
// of it a number, NaN or infinity in any spelling, or beyond the largest
// double (1e309). A number too small for a double (1e-400) is a number and
// reads as 0, and so does a subnormal one as small as 1e-320: a user who
// writes 1e-46 for a roughness means "zero", not "not a number".
inline std::optional<double> parseFiniteNumber(std::string_view text) {
  double value = 0.0;
  const char* const end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (stop != end || text.empty()) return std::nullopt;
  if (error == std::errc::result_out_of_range) {
    // from_chars says only "out of range"; strtod tells overflow (HUGE_VAL)
    // from underflow (a value at or below the smallest subnormal).
    const std::string copy(text);
    errno = 0;
    value = std::strtod(copy.c_str(), nullptr);
    if (std::isinf(value)) return std::nullopt;
    return value;
  }
  if (error != std::errc() || !std::isfinite(value)) return std::nullopt;
  return value;
}

}  // namespace bounce::util
