#include "app/output_files.h"

#include "app/option_checks.h"

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace bounce::app {

namespace fs = std::filesystem;

bool sameFile(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(fs::absolute(a), ec) == fs::weakly_canonical(fs::absolute(b), ec);
}

void refuseToOverwriteInputs(const fs::path& output, const std::string& flag, const std::vector<fs::path>& inputs) {
  for (const fs::path& input : inputs)
    if (sameFile(output, input))
      throw UsageError(output.string() + ": refusing to write " + flag + " over the input " + input.string());
}

void checkWritableDirectory(const fs::path& dir, const std::string& option) {
  const std::string where = option + " " + dir.string() + ": ";
  std::error_code error;
  if (fs::exists(dir, error) && !fs::is_directory(dir, error))
    throw std::runtime_error(where + "exists and is not a folder");
  fs::create_directories(dir, error);
  if (error) throw std::runtime_error(where + "cannot create the folder (" + error.message() + ")");
  // Permissions alone do not tell (root ignores them, read-only mounts do
  // not show in them): writing is the only proof.
  const fs::path probe = dir / (".bounce-write-probe-" + std::to_string(::getpid()));
  {
    std::ofstream file(probe, std::ios::binary | std::ios::trunc);
    if (!file || !(file << "probe") || !file.flush()) {
      const std::string reason = std::strerror(errno);
      fs::remove(probe, error);
      throw std::runtime_error(where + "cannot write into this folder (" + reason + ")");
    }
  }
  fs::remove(probe, error);
}

void checkWritableFile(const fs::path& file, const std::string& option) {
  std::error_code error;
  if (fs::is_directory(file, error))
    throw std::runtime_error(option + " " + file.string() + ": is a folder, expected a file name");
  checkWritableDirectory(file.parent_path().empty() ? fs::path(".") : file.parent_path(), option);
}

void writeTextFile(const fs::path& file, const std::string& text) {
  const fs::path temporary = file.string() + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out || !(out << text) || !out.flush()) {
      const std::string reason = std::strerror(errno);
      std::error_code ignored;
      fs::remove(temporary, ignored);
      throw std::runtime_error(file.string() + ": cannot write (" + reason + ")");
    }
  }
  std::error_code error;
  fs::rename(temporary, file, error);
  if (error) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw std::runtime_error(file.string() + ": cannot write (" + error.message() + ")");
  }
}

bool isNumberedFrameFile(const std::string& name) {
  constexpr std::size_t kPrefix = 5;  // "frame"
  if (name.rfind("frame", 0) != 0) return false;
  std::size_t digits = 0;
  while (kPrefix + digits < name.size() && std::isdigit(static_cast<unsigned char>(name[kPrefix + digits]))) ++digits;
  if (digits < 4 || kPrefix + digits >= name.size() || name[kPrefix + digits] != '.') return false;
  const auto endsWith = [&](const char* suffix) {
    const std::size_t length = std::strlen(suffix);
    return name.size() >= length && name.compare(name.size() - length, length, suffix) == 0;
  };
  return endsWith(".png") || endsWith(".exr");
}

std::size_t removeNumberedFrameFiles(const fs::path& dir) {
  std::error_code error;
  if (!fs::is_directory(dir, error)) return 0;
  std::size_t removed = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, error)) {
    if (!entry.is_regular_file(error) || !isNumberedFrameFile(entry.path().filename().string())) continue;
    if (!fs::remove(entry.path(), error) || error)
      throw std::runtime_error(entry.path().string() + ": cannot remove this frame of an earlier render (" +
                               error.message() + ")");
    ++removed;
  }
  return removed;
}

}  // namespace bounce::app
