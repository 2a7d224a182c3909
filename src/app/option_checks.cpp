#include "app/option_checks.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

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

CLI::Validator outputExtension(const std::string& extension, const std::string& what, const std::string& also) {
  const std::string description = "a file name ending in " + extension;
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        if (!also.empty() && text == also) return {};
        std::string ending = std::filesystem::path(text).extension().string();
        for (char& c : ending) c = char(std::tolower(static_cast<unsigned char>(c)));
        if (ending == extension) return {};
        const bool vowel = std::string_view("aeiou").find(extension.substr(1, 1)) != std::string_view::npos;
        return text + " must name " + (vowel ? "an " : "a ") + extension + " file: it is written as " + what;
      },
      description);
}

}  // namespace bounce::app
