// What the commands write, checked before the work that makes it: a render
// that runs for minutes must not find at the end that its output folder is
// read-only. Also the clean-up of an earlier render's numbered frames, so a
// folder never mixes two renders.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace bounce::app {

// Whether two paths name the same file, also when the output does not exist yet.
bool sameFile(const std::filesystem::path& a, const std::filesystem::path& b);

// Outputs never replace an input (nor each other): a mistyped command must
// not destroy the reference it was meant to check. Throws naming the output,
// the flag and the input.
void refuseToOverwriteInputs(const std::filesystem::path& output, const std::string& flag,
                             const std::vector<std::filesystem::path>& inputs);

// Creates `dir` when missing and proves it writable by creating and removing
// a probe file in it. Throws std::runtime_error naming `option` (e.g.
// "--out"), the folder and the reason.
void checkWritableDirectory(const std::filesystem::path& dir, const std::string& option);

// Checks that `file` can be written: it is not a folder, and its folder
// (created when missing) is writable. The file itself is not touched.
void checkWritableFile(const std::filesystem::path& file, const std::string& option);

// Writes `text` beside `file` and renames it into place, so a failed write
// never leaves half a file. Throws std::runtime_error.
void writeTextFile(const std::filesystem::path& file, const std::string& text);

// Whether `name` is one of the numbered files a render writes per frame:
// "frame" + at least four digits + "." ... + ".png" or ".exr" (frame0012.png,
// frame0012.indirect-diffuse.exr, frame0003.gi.composite.gOut_Composite.png).
bool isNumberedFrameFile(const std::string& name);

// Removes the numbered frame files directly inside `dir` (nothing else), and
// returns how many there were; 0 when `dir` does not exist.
std::size_t removeNumberedFrameFiles(const std::filesystem::path& dir);

}  // namespace bounce::app
