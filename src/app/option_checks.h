// Checks for command-line options. CLI11's own Range lets NaN through
// (every comparison with NaN is false, so "nan" is never out of range) and
// prints an open bound as the largest double in full, 309 digits; these
// refuse NaN and infinity and say the range in a few characters.
#pragma once

#include <CLI/CLI.hpp>
#include <limits>
#include <stdexcept>
#include <string>

namespace bounce::app {

// A command-line value refused after parsing: out of its range, contradicting
// another option, naming something the scene lacks, or an output that would
// replace an input. bounce exits with status 2 for it, as for the values
// CLI11 refuses while parsing: one rule for every mistake on the command line.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A finite number in [min, max]; a bound of +-infinity leaves that side open.
CLI::Validator finiteRange(double min, double max);

// A finite number >= min.
inline CLI::Validator finiteAtLeast(double min) { return finiteRange(min, std::numeric_limits<double>::infinity()); }

// Any finite number.
inline CLI::Validator finiteNumber() {
  return finiteRange(-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity());
}

// A finite number > 0.
CLI::Validator finitePositive();

// An output file name ending in `extension` (".png", any case), the format
// the option writes: a file named x.exr must not be given PNG bytes. `what`
// names the format in the message ("a PNG"). `also` is one more accepted
// value ("-" for standard output), or empty.
CLI::Validator outputExtension(const std::string& extension, const std::string& what, const std::string& also = "");

}  // namespace bounce::app
