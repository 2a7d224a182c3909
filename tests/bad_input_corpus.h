// The bad-input corpus: a few hundred malformed inputs of every kind a user
// hands bounce (glTF and GLB scenes, environment maps, GI settings files,
// camera keyframe files, option values), each with the outcome it must have.
// Nothing is committed as a blob: every case writes its files at test time,
// from code that says what is wrong with them.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace bounce::testing {

enum class Outcome {
  // One line "bounce: error: ..." naming the input file and the problem,
  // exit status 1 or 2, no image written.
  Error,
  // Exit status 0 and an image with nothing but finite values.
  FiniteImage,
  // Exit status 0 (the command did its work; the case's `check` says
  // whether it did it right: a file outside the output folder untouched).
  Completes,
};

struct CorpusCase {
  std::string name;  // unique, letters, digits and underscores (a test name)
  // Writes the case's input files into `dir` (which exists and is empty).
  std::function<void(const std::filesystem::path& dir)> write;
  // bounce's arguments. "{dir}" is replaced by the case's folder and "{out}"
  // by a fresh output folder inside it; the render is kept tiny by the test.
  std::vector<std::string> arguments;
  Outcome outcome = Outcome::Error;
  // For errors, what the one error line must contain besides the file's name
  // (empty when the case names no file: an option value).
  std::string file;      // the input's file name (the line must contain it)
  std::string mentions;  // a phrase that says what is wrong
  // After the run, whatever the outcome: what went wrong ("" when nothing
  // did), such as a file outside the output folder that changed. `dir` is
  // the case's folder.
  std::function<std::string(const std::filesystem::path& dir)> check;
  // Bounds on the run, 0 for none: an input that costs gigabytes or minutes
  // before it is refused fails its case. Not applied under the sanitizers,
  // whose shadow memory and slower code say nothing about bounce's own cost.
  double maxSeconds = 0.0;
  long maxMegabytes = 0;
};

// Every case, in a fixed order.
const std::vector<CorpusCase>& badInputCorpus();

}  // namespace bounce::testing
