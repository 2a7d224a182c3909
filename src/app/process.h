// Starting other programs (ffmpeg) without a shell: the arguments reach the
// program exactly as given, so a file name can never become a command.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace bounce::app {

// Runs argv[0], looked up on PATH, with argv as its arguments, stdin from
// /dev/null and stdout/stderr shared with ours, and waits for it. Returns its
// exit status (128 + N when signal N ended it), or nothing when it could not
// be started (for example, it is not installed).
std::optional<int> runProgram(const std::vector<std::string>& argv);

}  // namespace bounce::app
