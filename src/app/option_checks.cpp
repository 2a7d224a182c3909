#include "app/option_checks.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace bounce::app {
namespace {

std::string shortNumber(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

// The text as a double when all of it is one number; NaN otherwise.
double parsed(const std::string& text) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  return end != begin && *end == '\0' ? value : std::numeric_limits<double>::quiet_NaN();
}

std::string rangeText(double min, double max) {
  if (std::isinf(min) && std::isinf(max)) return "a finite number";
  if (std::isinf(max)) return "a finite number >= " + shortNumber(min);
  if (std::isinf(min)) return "a finite number <= " + shortNumber(max);
  return "a finite number in [" + shortNumber(min) + ", " + shortNumber(max) + "]";
}

}  // namespace

CLI::Validator finiteRange(double min, double max) {
  const std::string expected = rangeText(min, max);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        const double value = parsed(text);
        if (std::isfinite(value) && value >= min && value <= max) return {};
        return "got " + text + ", expected " + expected;
      },
      expected);
}

CLI::Validator finitePositive() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const double value = parsed(text);
        if (std::isfinite(value) && value > 0.0) return {};
        return "got " + text + ", expected a finite number > 0";
      },
      "a finite number > 0");
}

}  // namespace bounce::app
