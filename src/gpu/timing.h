// Per-pass GPU times collected over frames, and the summary table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace bounce::gpu {

// What a dispatch's binds cover, each once: the least it must move, its
// traffic floor (docs/benchmarks.md, "Traffic floors"). Images count the
// levels bound (a sampled image all of them) at their full size; storage
// buffers count whole, which for buffers sized for the worst case (queues,
// the radiance cache) is more than a pass touches, so they are apart.
struct PassTraffic {
  std::uint64_t imageBytes = 0;
  std::uint64_t bufferBytes = 0;
  PassTraffic& operator+=(const PassTraffic& other) {
    imageBytes += other.imageBytes;
    bufferBytes += other.bufferBytes;
    return *this;
  }
};

struct PassTiming {
  std::string pass;
  double medianMs = 0;
  double minMs = 0;
  double maxMs = 0;
  std::size_t samples = 0;
  PassTraffic traffic;  // what its binds covered, its last frame
};

// A pass's latest time, for a live view: no sorting, cheap every frame.
struct LatestTiming {
  std::string pass;
  double ms = 0;
  std::size_t samples = 0;  // times added so far (grows by one each frame the pass runs)
};

// The median of `values` (the mean of the middle two for an even count); 0 for none.
double medianOf(std::vector<double> values);

// Memory stays bounded however long a program runs: each pass keeps its
// exact count, minimum and maximum, and a uniform random sample of at most
// kMaxSamples of its times (reservoir sampling), from which the median comes;
// the median is exact up to kMaxSamples frames.
class TimingStats {
 public:
  static constexpr std::size_t kMaxSamples = 4096;

  // `traffic`: what the pass's binds covered that frame.
  void add(const std::string& pass, double milliseconds, const PassTraffic& traffic = {});
  // One row per pass, in the order passes first ran.
  std::vector<PassTiming> summary() const;
  // Each pass's latest time, in the order passes first ran.
  std::vector<LatestTiming> latest() const;
  // The text table: pass, median ms, min, max, share of the frame.
  std::string table() const;
  bool empty() const { return order_.empty(); }
  // Times kept for `pass` (at most kMaxSamples), to show the bound holds.
  std::size_t keptSamples(const std::string& pass) const;

 private:
  struct PassSamples {
    std::vector<double> kept;  // at most kMaxSamples
    std::size_t count = 0;
    double min = 0.0;
    double max = 0.0;
    double last = 0.0;
    PassTraffic traffic;                           // the last frame's
    std::uint64_t random = 0x9E3779B97F4A7C15ull;  // fixed seed: the same run keeps the same samples
  };
  std::vector<std::string> order_;
  std::map<std::string, PassSamples> samples_;
};

}  // namespace bounce::gpu
