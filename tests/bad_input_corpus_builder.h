// How the corpus's sections (bad_input_corpus*.cpp) add their cases: a
// case is a name, the input files it writes, bounce's arguments and what
// the one error line must say. The sections live in files by kind of input
// and are joined, in a fixed order, by badInputCorpus().
#pragma once

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "bad_input_corpus.h"

namespace bounce::testing {

namespace corpus_files {

inline void writeBytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

inline void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// Names are test names: letters, digits and underscores only.
inline std::string identifier(std::string text) {
  for (char& c : text)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return text;
}

}  // namespace corpus_files

class CorpusBuilder {
 public:
  std::vector<CorpusCase> cases;

  // A case whose one input is a text file.
  void textFile(const std::string& name, const std::string& file, std::string text, std::vector<std::string> arguments,
                const std::string& mentions, Outcome outcome = Outcome::Error) {
    add(
        name, file,
        [file, text = std::move(text)](const std::filesystem::path& dir) { corpus_files::writeText(dir / file, text); },
        std::move(arguments), mentions, outcome);
  }

  void binaryFile(const std::string& name, const std::string& file, std::vector<std::uint8_t> bytes,
                  std::vector<std::string> arguments, const std::string& mentions, Outcome outcome = Outcome::Error) {
    add(
        name, file,
        [file, bytes = std::move(bytes)](const std::filesystem::path& dir) {
          corpus_files::writeBytes(dir / file, bytes);
        },
        std::move(arguments), mentions, outcome);
  }

  // Returns the case, for a section to set its `check` and bounds.
  CorpusCase& add(const std::string& name, const std::string& file,
                  std::function<void(const std::filesystem::path&)> write, std::vector<std::string> arguments,
                  const std::string& mentions, Outcome outcome = Outcome::Error) {
    cases.push_back(
        {corpus_files::identifier(name), std::move(write), std::move(arguments), outcome, file, mentions, {}, 0.0, 0});
    return cases.back();
  }
};

// The sections of the hardening round 3 (issue 46), each in its own file.
void outputFolderCases(CorpusBuilder& corpus);  // bad_input_corpus_output.cpp: the output folder's record, links, FIFOs
void sceneMemoryCases(CorpusBuilder& corpus);   // bad_input_corpus_memory.cpp: inputs that would cost gigabytes
void ghostingCases(CorpusBuilder& corpus);      // bad_input_corpus_ghosting.cpp: ghosting's events and options
void scriptAndCompareCases(CorpusBuilder& corpus);  // bad_input_corpus_scripts.cpp: viewer scripts, compare, settings

}  // namespace bounce::testing
