#include "app/memory_limit.h"

#include <cstdio>
#include <stdexcept>

namespace bounce::app {

std::string memoryText(std::uint64_t bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  double value = double(bytes);
  int unit = 0;
  while (value >= 1024.0 && unit < 4) {
    value /= 1024.0;
    ++unit;
  }
  char text[32];
  if (unit == 0)
    std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
  else
    std::snprintf(text, sizeof text, value < 10.0 ? "%.1f %s" : "%.0f %s", value, units[unit]);
  return text;
}

void refuseOverMemoryLimit(const std::filesystem::path& file, std::uint64_t bytes, const std::string& what) {
  if (bytes <= kImageMemoryLimit) return;
  throw std::runtime_error(file.string() + ": " + what + " needs about " + memoryText(bytes) +
                           " of memory, more than the limit of " + memoryText(kImageMemoryLimit) +
                           " (docs/reliability.md)");
}

}  // namespace bounce::app
