// The memory a command plans for the images it reads and makes, checked
// before it decodes a pixel: a small file can declare a huge image (a 261 KB
// PNG of 16384 x 16384 zeros), and decoding it first would let the kernel
// end the process, or another one, instead of an error naming the file.
// docs/reliability.md says what each command counts.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace bounce::app {

// The most a command's images may need at once: 2 GiB. Commands that read
// images work out their peak from the files' headers (io::readImageInfo)
// and refuse beyond it.
inline constexpr std::uint64_t kImageMemoryLimit = std::uint64_t(2) << 30;

// Bytes as people read them: "1.3 GiB", "640 MiB", "12 KiB".
std::string memoryText(std::uint64_t bytes);

// Throws std::runtime_error "FILE: WHAT needs about 9.6 GiB of memory, more
// than the limit of 2 GiB (docs/reliability.md)" when bytes is over
// kImageMemoryLimit; `what` says what the memory is for ("comparing two
// 16384x16384 images").
void refuseOverMemoryLimit(const std::filesystem::path& file, std::uint64_t bytes, const std::string& what);

}  // namespace bounce::app
