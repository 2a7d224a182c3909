#include "gpu/timing.h"

#include <algorithm>
#include <cstdio>

namespace bounce::gpu {

void TimingStats::add(const std::string& pass, double milliseconds, const PassTraffic& traffic) {
  auto [it, inserted] = samples_.try_emplace(pass);
  if (inserted) order_.push_back(pass);
  PassSamples& s = it->second;
  s.min = s.count == 0 ? milliseconds : std::min(s.min, milliseconds);
  s.max = s.count == 0 ? milliseconds : std::max(s.max, milliseconds);
  ++s.count;
  s.last = milliseconds;
  s.traffic = traffic;
  if (s.kept.size() < kMaxSamples) {
    s.kept.push_back(milliseconds);
    return;
  }
  // Algorithm R: the count-th sample replaces a kept one with probability kMaxSamples / count.
  s.random ^= s.random << 13;
  s.random ^= s.random >> 7;
  s.random ^= s.random << 17;
  const std::uint64_t slot = s.random % s.count;
  if (slot < kMaxSamples) s.kept[slot] = milliseconds;
}

std::vector<PassTiming> TimingStats::summary() const {
  std::vector<PassTiming> rows;
  for (const std::string& pass : order_) {
    const PassSamples& s = samples_.at(pass);
    rows.push_back({pass, medianOf(s.kept), s.min, s.max, s.count, s.traffic});
  }
  return rows;
}

std::vector<LatestTiming> TimingStats::latest() const {
  std::vector<LatestTiming> rows;
  for (const std::string& pass : order_) {
    const PassSamples& s = samples_.at(pass);
    rows.push_back({pass, s.last, s.count});
  }
  return rows;
}

double medianOf(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::size_t TimingStats::keptSamples(const std::string& pass) const {
  const auto found = samples_.find(pass);
  return found == samples_.end() ? 0 : found->second.kept.size();
}

std::string TimingStats::table() const {
  std::vector<PassTiming> rows = summary();
  double total = 0;
  std::size_t width = 5;
  for (const PassTiming& r : rows) {
    total += r.medianMs;
    width = std::max(width, r.pass.size());
  }
  std::string text;
  char line[512];
  std::snprintf(line, sizeof line, "%-*s  %10s  %10s  %10s  %6s  %7s\n", int(width), "pass", "median ms", "min ms",
                "max ms", "share", "frames");
  text += line;
  for (const PassTiming& r : rows) {
    std::snprintf(line, sizeof line, "%-*s  %10.4f  %10.4f  %10.4f  %5.1f%%  %7zu\n", int(width), r.pass.c_str(),
                  r.medianMs, r.minMs, r.maxMs, total > 0 ? 100.0 * r.medianMs / total : 0.0, r.samples);
    text += line;
  }
  std::snprintf(line, sizeof line, "%-*s  %10.4f\n", int(width), "total", total);
  text += line;
  return text;
}

}  // namespace bounce::gpu
