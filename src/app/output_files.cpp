#include "app/output_files.h"

#include "app/option_checks.h"

#include <unistd.h>

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

namespace {

// Whether `file` is `folder` or lies inside it, compared as canonical paths
// (symbolic links and "..", resolved as far as the files exist).
bool isInside(const fs::path& file, const fs::path& folder) {
  std::error_code error;
  const fs::path f = fs::weakly_canonical(fs::absolute(file), error);
  const fs::path d = fs::weakly_canonical(fs::absolute(folder), error);
  auto fi = f.begin();
  for (auto di = d.begin(); di != d.end(); ++di, ++fi) {
    if (di->empty()) continue;  // the trailing "" of a path ending in '/'
    if (fi == f.end() || *fi != *di) return false;
  }
  return true;
}

}  // namespace

void refuseInputsInside(const fs::path& folder, const std::string& flag, const std::vector<fs::path>& inputs) {
  for (const fs::path& input : inputs)
    if (isInside(input, folder))
      throw UsageError(input.string() + " is an input, and " + flag + " fills " + folder.string() +
                       " with this run's files: choose another " + flag);
}

OutputFolder::OutputFolder(fs::path dir, std::string option, bool overwrite)
    : dir_(std::move(dir)), option_(std::move(option)), overwrite_(overwrite) {}

// Paths inside the folder come as the folder joined with a name (what the
// writers return) or as the name alone (what the commands plan).
std::string OutputFolder::relative(const fs::path& file) const {
  const fs::path inside =
      file.is_absolute() ? file.lexically_relative(fs::absolute(dir_)) : file.lexically_relative(dir_);
  const bool joined = !inside.empty() && *inside.begin() != "..";
  return (joined ? inside : file).lexically_normal().generic_string();
}

std::size_t OutputFolder::prepare(const std::vector<fs::path>& files, const std::vector<fs::path>& folders,
                                  const std::vector<fs::path>& inputs) {
  const fs::path recordFile = dir_ / kRecordName;
  // The earlier run's record. Lines that could lead out of the folder (an
  // absolute path, "..") are not Bounce's and are ignored: removal follows
  // the record, so it must never name a file elsewhere.
  std::set<std::string> earlier;
  {
    std::ifstream in(recordFile);
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line.front() == '#') continue;
      const fs::path entry = fs::path(line).lexically_normal();
      if (entry.is_absolute() || entry.empty() || *entry.begin() == "..") continue;
      earlier.insert(entry.generic_string());
    }
  }
  std::set<std::string> planned;
  for (const fs::path& file : files) planned.insert(relative(file));

  const auto where = [&](const std::string& file) { return (dir_ / file).string(); };
  for (const std::string& file : planned) refuseToOverwriteInputs(dir_ / file, option_, inputs);
  refuseToOverwriteInputs(recordFile, option_, inputs);
  for (const fs::path& folder : folders) refuseInputsInside(dir_ / folder, option_, inputs);
  std::vector<std::string> stale;
  std::error_code error;
  for (const std::string& file : earlier)
    if (!planned.count(file) && fs::exists(fs::symlink_status(dir_ / file, error))) stale.push_back(file);
  for (const std::string& file : stale)
    for (const fs::path& input : inputs)
      if (sameFile(dir_ / file, input))
        throw UsageError(input.string() + " is an input, and an earlier run wrote it in " + dir_.string() +
                         ": this run would remove it; choose another " + option_);

  if (!overwrite_) {
    const auto refuseForeign = [&](const std::string& file) {
      throw UsageError(where(file) + " exists and no Bounce run wrote it (" + kRecordName +
                       " does not list it): not replaced; choose another " + option_ + ", or --overwrite");
    };
    for (const std::string& file : planned)
      if (!earlier.count(file) && fs::exists(fs::symlink_status(dir_ / file, error))) refuseForeign(file);
    for (const fs::path& folder : folders) {
      if (!fs::is_directory(dir_ / folder, error)) continue;
      for (auto entry = fs::recursive_directory_iterator(dir_ / folder, error);
           !error && entry != fs::recursive_directory_iterator(); entry.increment(error))
        if (!entry->is_directory(error) && !earlier.count(relative(entry->path())))
          refuseForeign(relative(entry->path()));
    }
  }

  for (const std::string& file : stale) {
    fs::remove(dir_ / file, error);
    if (error)
      throw std::runtime_error(where(file) + ": cannot remove this file of an earlier run (" + error.message() + ")");
    // A subfolder the earlier run made (frames/, stages/) goes when it is left empty.
    for (fs::path parent = fs::path(file).parent_path(); !parent.empty(); parent = parent.parent_path())
      if (!fs::remove(dir_ / parent, error)) break;  // not empty: it stays
  }
  record_ = planned;
  save();
  return stale.size();
}

void OutputFolder::wrote(const std::vector<fs::path>& files) {
  for (const fs::path& file : files) record_.insert(relative(file));
  save();
}

void OutputFolder::save() const {
  std::string text = "# The files in this folder that Bounce wrote; a later run replaces or removes only these.\n";
  for (const std::string& file : record_) text += file + "\n";
  writeTextFile(dir_ / kRecordName, text);
}

}  // namespace bounce::app
