// What the commands write, checked before the work that makes it: a render
// that runs for minutes must not find at the end that its output folder is
// read-only, nor replace an input or a file the user put in its folder.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <set>
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

// A folder a command fills with several files (render's OUT: render.png,
// frames/, stages/, aov/...), and OUT/.bounce-written, its record of the
// files in it that a Bounce run wrote. Only those are ever replaced or
// removed: a file the user put there (their notes, a texture of the scene,
// frames of their own) is refused, not touched, unless --overwrite.
//
// Nothing outside the folder is ever touched, whatever the folder holds:
// the record's entries are names inside it, looked up part by part without
// following a symbolic link (an entry through a link, or a link itself, is
// reported and left as it is); a link where this run writes a file, or in
// the path to it, is refused by name, also with --overwrite; the record is
// read only when it is a small regular file (a FIFO, a device, a link or a
// huge file is refused by name, never opened in a way that blocks or
// reads without end); a malformed line is reported and ignored.
class OutputFolder {
 public:
  static constexpr const char* kRecordName = ".bounce-written";
  // A record is a line per file: 16 MiB holds a 100,000-frame render with
  // every HDR image (about 130 bytes a frame), and is read in well under a
  // second.
  static constexpr std::uintmax_t kMaxRecordBytes = std::uintmax_t(16) << 20;

  // Whose folder it is. Owned (render's OUT): this run's files replace the
  // earlier run's, whose files this run does not write again are removed.
  // Shared (the folder of reference's OUT.exr, which may hold anything):
  // the record gains this run's files, keeps the earlier ones and nothing
  // is removed.
  enum class Use { Owned, Shared };

  // `option` names the folder in messages ("--out"); `overwrite`: files
  // that no Bounce run wrote may be replaced.
  OutputFolder(std::filesystem::path dir, std::string option, bool overwrite, Use use = Use::Owned);

  // Before the work. `files`: what this run will write, relative to the
  // folder. `folders`: subfolders it fills with files named by the work
  // (stages/). `inputs`: what it reads. Throws UsageError, naming the file,
  // when an output is an input, an input lies in a folder this run fills or
  // among the earlier run's files it would remove, a symbolic link (or a
  // file where a folder should be) lies where this run writes, or (without
  // --overwrite) an output or a file in `folders` exists and no Bounce run
  // wrote it; std::runtime_error when the record is not a small regular file.
  // Then removes the earlier run's files this one will not write again, so
  // two runs never mix (returns how many; none for a Shared folder), and
  // records this run's files.
  std::size_t prepare(const std::vector<std::filesystem::path>& files,
                      const std::vector<std::filesystem::path>& folders,
                      const std::vector<std::filesystem::path>& inputs);

  // Records files written whose names were not known before the work
  // (paths inside the folder, as written).
  void wrote(const std::vector<std::filesystem::path>& files);

  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::string relative(const std::filesystem::path& file) const;
  std::set<std::string> readRecord() const;
  void save() const;

  std::filesystem::path dir_;
  std::string option_;
  bool overwrite_;
  Use use_;
  std::set<std::string> record_;  // generic relative paths
};

// Nor may an input lie in `folder`, which the run fills with its files (a
// stage dump, a G-buffer): throws UsageError naming the input, the folder
// and `flag`.
void refuseInputsInside(const std::filesystem::path& folder, const std::string& flag,
                        const std::vector<std::filesystem::path>& inputs);

// Creates `dir` when missing and proves it writable by creating and removing
// a probe file in it (exclusively, under an unpredictable name: a link
// planted in the folder is never written through). Throws
// std::runtime_error naming `option` (e.g. "--out"), the folder and the
// reason.
void checkWritableDirectory(const std::filesystem::path& dir, const std::string& option);

// Checks that `file` can be written: it is not a folder, a symbolic link or
// anything but a regular file (none of which a write replaces), and its
// folder (created when missing) is writable. The file itself is not touched.
// Throws UsageError for a link, std::runtime_error otherwise.
void checkWritableFile(const std::filesystem::path& file, const std::string& option);

// Writes `text` beside `file` and renames it into place
// (io::writeFileAtomically), so a failed write never leaves half a file and
// a link is never written through or replaced. Throws std::runtime_error.
void writeTextFile(const std::filesystem::path& file, const std::string& text);

}  // namespace bounce::app
