// Per-pass GPU times collected over frames, and the summary table.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace bounce::gpu {

struct PassTiming {
  std::string pass;
  double medianMs = 0;
  double minMs = 0;
  double maxMs = 0;
  std::size_t samples = 0;
};

class TimingStats {
 public:
  void add(const std::string& pass, double milliseconds);
  // One row per pass, in the order passes first ran.
  std::vector<PassTiming> summary() const;
  // The text table: pass, median ms, min, max, share of the frame.
  std::string table() const;
  bool empty() const { return order_.empty(); }

 private:
  std::vector<std::string> order_;
  std::map<std::string, std::vector<double>> samples_;
};

}  // namespace bounce::gpu
