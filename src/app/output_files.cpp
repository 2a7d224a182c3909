#include "app/output_files.h"

#include "app/option_checks.h"
#include "io/image_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <string_view>
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
  const io::TemporaryFile probe = io::createTemporaryBeside(dir / ".bounce-write-probe");
  if (probe.fd < 0) throw std::runtime_error(where + "cannot write into this folder (" + std::strerror(probe.error) + ")");
  const bool written = ::write(probe.fd, "probe", 5) == 5;
  const int reason = errno;
  const bool closed = ::close(probe.fd) == 0;
  const int closeReason = errno;
  ::unlink(probe.path.c_str());
  if (!written || !closed)
    throw std::runtime_error(where + "cannot write into this folder (" +
                             std::strerror(!written ? reason : closeReason) + ")");
}

void checkWritableFile(const fs::path& file, const std::string& option) {
  struct stat status {};
  if (::lstat(file.c_str(), &status) == 0) {
    const std::string where = option + " " + file.string() + ": ";
    if (S_ISDIR(status.st_mode)) throw std::runtime_error(where + "is a folder, expected a file name");
    // The command line names a link: the same mistake as naming a file
    // that no Bounce run wrote (OutputFolder), and the same exit status.
    if (S_ISLNK(status.st_mode))
      throw UsageError(where + "is a symbolic link; not replaced (Bounce writes regular files only, never "
                               "through or over a link): remove it or choose another name");
    if (!S_ISREG(status.st_mode))
      throw std::runtime_error(where + "is not a regular file; not replaced: choose another name");
  }
  checkWritableDirectory(file.parent_path().empty() ? fs::path(".") : file.parent_path(), option);
}

void writeTextFile(const fs::path& file, const std::string& text) {
  io::writeFileAtomically(file, text.data(), text.size());
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

namespace {

// Why a line of the record is not the name of a file inside the folder, ""
// when it is: a relative path whose every part is a name. "." or "frames/.."
// name the folder itself (removing it fails, every later run with it), ".."
// and absolute paths lead out of it.
std::string recordEntryProblem(std::string_view entry) {
  if (entry.find('\0') != std::string_view::npos) return "a NUL character";
  if (entry.starts_with('/')) return "an absolute path";
  if (entry == OutputFolder::kRecordName) return "the record itself";
  for (std::size_t begin = 0;;) {
    const std::size_t end = std::min(entry.find('/', begin), entry.size());
    const std::string_view part = entry.substr(begin, end - begin);
    if (part.empty()) return "an empty part ('//' or a '/' at an end)";
    if (part == "." || part == "..") return "a '" + std::string(part) + "' part";
    if (end == entry.size()) return "";
    begin = end + 1;
  }
}

// A line of the record as a message shows it: control characters (a
// terminal's escapes) as '?', and not without end.
std::string shownRecordLine(std::string_view line) {
  std::string text;
  for (char c : line.substr(0, 200)) text += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
  return line.size() > 200 ? text + "..." : text;
}

std::string fileKindOf(mode_t mode) {
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// What lies at `entry` (a checked relative name) inside `dir`, each part
// looked at with lstat, so that no link is followed: the walk stops at the
// first part that is not a real folder. `at` is that part, or the entry
// itself; `inPath` says it is a folder of the entry's path.
struct PlaceInside {
  enum class Kind { Missing, File, Folder, Link, Other } kind = Kind::Missing;
  fs::path at;
  bool inPath = false;
};

PlaceInside lookUpInside(const fs::path& dir, const std::string& entry) {
  fs::path path = dir == "." ? fs::path() : dir;  // "v.json", not "./v.json", in messages
  const fs::path parts(entry);
  for (auto part = parts.begin(); part != parts.end(); ++part) {
    path /= *part;
    const bool last = std::next(part) == parts.end();
    struct stat status {};
    if (::lstat(path.c_str(), &status) != 0) return {PlaceInside::Kind::Missing, path, !last};
    const PlaceInside::Kind kind = S_ISLNK(status.st_mode)   ? PlaceInside::Kind::Link
                             : S_ISDIR(status.st_mode) ? PlaceInside::Kind::Folder
                             : S_ISREG(status.st_mode) ? PlaceInside::Kind::File
                                                       : PlaceInside::Kind::Other;
    if (last || kind != PlaceInside::Kind::Folder) return {kind, path, !last};
  }
  return {PlaceInside::Kind::Missing, path, false};
}

// Descriptors of the folders on an entry's path, closed together.
struct OpenFolders {
  std::vector<int> fds;
  ~OpenFolders() {
    for (int fd : fds) ::close(fd);
  }
};

// Removes the regular file `entry` inside `dir`, then the folders of its
// path that it leaves empty. Each folder is opened with O_NOFOLLOW from the
// one above and the file removed relative to its folder, so a link put in
// the path after lookUpInside looked is never followed. "" or why not.
std::string removeRecordedFile(const fs::path& dir, const std::string& entry) {
  std::vector<std::string> parts;
  for (const fs::path& part : fs::path(entry)) parts.push_back(part.string());
  OpenFolders folders;
  folders.fds.push_back(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  for (std::size_t i = 0; folders.fds.back() >= 0 && i + 1 < parts.size(); ++i)
    folders.fds.push_back(::openat(folders.fds.back(), parts[i].c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
  if (folders.fds.back() < 0) return std::strerror(errno);
  struct stat status {};
  if (::fstatat(folders.fds.back(), parts.back().c_str(), &status, AT_SYMLINK_NOFOLLOW) != 0)
    return std::strerror(errno);
  if (!S_ISREG(status.st_mode)) return "it is " + fileKindOf(status.st_mode) + " now";
  if (::unlinkat(folders.fds.back(), parts.back().c_str(), 0) != 0) return std::strerror(errno);
  // A subfolder the earlier run made (frames/, stages/) goes when it is left empty.
  for (std::size_t i = parts.size() - 1; i-- > 0;)
    if (::unlinkat(folders.fds[i], parts[i].c_str(), AT_REMOVEDIR) != 0) break;  // not empty: it stays
  return "";
}

}  // namespace

OutputFolder::OutputFolder(fs::path dir, std::string option, bool overwrite, Use use)
    : dir_(std::move(dir)), option_(std::move(option)), overwrite_(overwrite), use_(use) {}

// Paths inside the folder come as the folder joined with a name (what the
// writers return) or as the name alone (what the commands plan).
std::string OutputFolder::relative(const fs::path& file) const {
  const fs::path inside =
      file.is_absolute() ? file.lexically_relative(fs::absolute(dir_)) : file.lexically_relative(dir_);
  const bool joined = !inside.empty() && *inside.begin() != "..";
  std::string name = (joined ? inside : file).lexically_normal().generic_string();
  if (const std::string problem = recordEntryProblem(name); !problem.empty())
    throw std::logic_error("OutputFolder: '" + name + "' is not a file inside " + dir_.string() + " (" + problem + ")");
  return name;
}

std::set<std::string> OutputFolder::readRecord() const {
  const fs::path file = dir_ / kRecordName;
  const std::string remedy = ": remove it, or choose another " + option_;
  // Looked at before it is opened, and opened without following a link or
  // waiting for a writer: a FIFO would block the open, /dev/zero never
  // ends, and a link may lead anywhere.
  struct stat status {};
  if (::lstat(file.c_str(), &status) != 0) {
    if (errno == ENOENT) return {};
    throw std::runtime_error(file.string() + ": cannot read this record of the files Bounce wrote (" +
                             std::strerror(errno) + ")");
  }
  const auto refuse = [&](const struct stat& s) {
    if (!S_ISREG(s.st_mode))
      throw std::runtime_error(file.string() + ": is " + fileKindOf(s.st_mode) +
                               ", not Bounce's record of the files it wrote there (a small regular file)" + remedy);
    if (std::uintmax_t(s.st_size) > kMaxRecordBytes)
      throw std::runtime_error(file.string() + ": is " + std::to_string(s.st_size) + " bytes, more than the " +
                               std::to_string(kMaxRecordBytes >> 20) + " MiB a record of the files Bounce wrote holds" +
                               remedy);
  };
  refuse(status);
  const int fd = ::open(file.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0)
    throw std::runtime_error(file.string() + ": cannot read this record of the files Bounce wrote (" +
                             std::strerror(errno) + ")");
  std::string text;
  {
    const OpenFolders closing{{fd}};
    // What was opened is checked again: the file may have been swapped since lstat.
    if (::fstat(fd, &status) != 0)
      throw std::runtime_error(file.string() + ": cannot read (" + std::string(std::strerror(errno)) + ")");
    refuse(status);
    text.resize(std::size_t(status.st_size));
    std::size_t got = 0;
    while (got < text.size()) {
      const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0)
        throw std::runtime_error(file.string() + ": cannot read (" + std::string(std::strerror(errno)) + ")");
      if (n == 0) break;
      got += std::size_t(n);
    }
    text.resize(got);
  }

  std::set<std::string> entries;
  std::size_t number = 0;
  for (std::size_t begin = 0; begin < text.size();) {
    const std::size_t end = std::min(text.find('\n', begin), text.size());
    const std::string_view line = std::string_view(text).substr(begin, end - begin);
    begin = end + 1;
    ++number;
    if (line.empty() || line.front() == '#') continue;
    // A line no Bounce run writes is reported and ignored: removal follows
    // the record, so it must never name a file elsewhere, nor fail every
    // later run on a name it cannot remove.
    if (const std::string problem = recordEntryProblem(line); !problem.empty()) {
      std::fprintf(stderr, "warning: %s:%zu: \"%s\" is not the name of a file inside the folder (%s); ignored\n",
                   file.c_str(), number, shownRecordLine(line).c_str(), problem.c_str());
      continue;
    }
    entries.insert(std::string(line));
  }
  return entries;
}

std::size_t OutputFolder::prepare(const std::vector<fs::path>& files, const std::vector<fs::path>& folders,
                                  const std::vector<fs::path>& inputs) {
  const fs::path recordFile = dir_ / kRecordName;
  const std::set<std::string> earlier = readRecord();
  std::set<std::string> planned;
  for (const fs::path& file : files) planned.insert(relative(file));

  const auto where = [&](const std::string& file) { return (dir_ == "." ? fs::path(file) : dir_ / file).string(); };
  for (const std::string& file : planned) refuseToOverwriteInputs(dir_ / file, option_, inputs);
  refuseToOverwriteInputs(recordFile, option_, inputs);
  for (const fs::path& folder : folders) refuseInputsInside(dir_ / folder, option_, inputs);

  const std::string remedy = ": remove it, or choose another " + option_;
  const auto refuseForeign = [&](const std::string& file) {
    throw UsageError(where(file) + " exists and no Bounce run wrote it (" + kRecordName +
                     " does not list it): not replaced; choose another " + option_ + ", or --overwrite");
  };
  // A link is never written through, nor replaced (it is the user's, even
  // where a Bounce run once wrote a file): not with --overwrite either.
  const auto refuseLink = [&](const PlaceInside& place) {
    if (place.kind == PlaceInside::Kind::Missing) return;
    if (place.kind == PlaceInside::Kind::Link)
      throw UsageError(place.at.string() + " is a symbolic link: " +
                       (place.inPath ? "Bounce does not write through a link in its output folder"
                                     : "not replaced, even with --overwrite (Bounce writes regular files only)") +
                       remedy);
    if (place.inPath)
      throw UsageError(place.at.string() + " is not a folder, and this run writes files in it" + remedy);
  };
  for (const std::string& file : planned) {
    const PlaceInside place = lookUpInside(dir_, file);
    refuseLink(place);
    if (place.kind == PlaceInside::Kind::Folder)
      throw UsageError(place.at.string() + " is a folder, and this run writes a file there" + remedy);
    if (place.kind == PlaceInside::Kind::Other)
      throw UsageError(place.at.string() + " is not a regular file; not replaced" + remedy);
    if (place.kind == PlaceInside::Kind::File && !overwrite_ && !earlier.count(file)) refuseForeign(file);
  }
  for (const fs::path& folder : folders) {
    const PlaceInside place = lookUpInside(dir_, relative(folder));
    refuseLink(place);
    if (place.kind == PlaceInside::Kind::File || place.kind == PlaceInside::Kind::Other)
      throw UsageError(place.at.string() + " is not a folder, and this run fills it with files" + remedy);
    if (place.kind != PlaceInside::Kind::Folder) continue;
    // The iterator does not follow links; a link inside is refused, since
    // the names the work gives its files are not known yet.
    std::error_code error;
    for (auto entry = fs::recursive_directory_iterator(dir_ / folder, error);
         !error && entry != fs::recursive_directory_iterator(); entry.increment(error)) {
      const fs::file_type type = entry->symlink_status(error).type();
      if (type == fs::file_type::directory) continue;
      if (type == fs::file_type::symlink)
        throw UsageError(entry->path().string() + " is a symbolic link in " + where(relative(folder)) +
                         ", which this run fills with files: not replaced, even with --overwrite" + remedy);
      if (!overwrite_ && !earlier.count(relative(entry->path()))) refuseForeign(relative(entry->path()));
    }
  }

  // The earlier run's files: those this run does not write again go (in a
  // folder of its own), those still there stay recorded (in a shared one).
  // An entry that is no longer a regular file reached through real folders
  // is not what Bounce wrote: reported, left as it is, and forgotten.
  std::vector<std::string> stale, kept;
  for (const std::string& file : earlier) {
    if (planned.count(file)) continue;
    const PlaceInside place = lookUpInside(dir_, file);
    if (place.kind == PlaceInside::Kind::Missing) continue;
    if (place.kind != PlaceInside::Kind::File) {
      std::fprintf(stderr, "warning: %s lists %s, but %s is %s, not a file Bounce wrote; left as it is\n",
                   recordFile.c_str(), file.c_str(), place.at.c_str(),
                   place.kind == PlaceInside::Kind::Link     ? "a symbolic link"
                   : place.kind == PlaceInside::Kind::Folder ? "a folder"
                                                       : "not a regular file");
      continue;
    }
    (use_ == Use::Owned ? stale : kept).push_back(file);
  }
  for (const std::string& file : stale)
    for (const fs::path& input : inputs)
      if (sameFile(dir_ / file, input))
        throw UsageError(input.string() + " is an input, and an earlier run wrote it in " + dir_.string() +
                         ": this run would remove it; choose another " + option_);

  for (const std::string& file : stale)
    if (const std::string reason = removeRecordedFile(dir_, file); !reason.empty())
      throw std::runtime_error(where(file) + ": cannot remove this file of an earlier run (" + reason + ")");
  record_ = planned;
  record_.insert(kept.begin(), kept.end());
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
