// Runs bounce on every case of the bad-input corpus (bad_input_corpus.h):
// each malformed input must give one clear error line naming its file and
// the problem, with exit status 1 or 2, or a finite image; never a crash, a
// hang, a NaN or a silently wrong picture. Each case is its own test.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bad_input_corpus.h"
#include "io/image_io.h"
#include "process.h"

namespace bounce::testing {
namespace {

namespace fs = std::filesystem;

// A case's command line with its folders filled in, kept small: a tiny image
// and a one-frame warm-up unless the case sets them itself.
std::vector<std::string> commandLine(const CorpusCase& c, const fs::path& dir, const fs::path& out) {
  std::vector<std::string> argv = {BOUNCE_BINARY};
  for (std::string argument : c.arguments) {
    for (const auto& [placeholder, value] : {std::pair{"{dir}", dir.string()}, std::pair{"{out}", out.string()}})
      for (std::size_t at = argument.find(placeholder); at != std::string::npos; at = argument.find(placeholder))
        argument.replace(at, std::string(placeholder).size(), value);
    argv.push_back(argument);
  }
  const auto given = [&](const char* option) { return std::find(argv.begin(), argv.end(), option) != argv.end(); };
  const std::string command = c.arguments.empty() ? "" : c.arguments.front();
  if (command == "render" || command == "reference") {
    if (!given("--width")) argv.insert(argv.end(), {"--width", "16"});
    if (!given("--height")) argv.insert(argv.end(), {"--height", "12"});
  }
  if (command == "render" && !given("--gi-warmup")) argv.insert(argv.end(), {"--gi-warmup", "1"});
  if (command == "reference" && !given("--spp")) argv.insert(argv.end(), {"--spp", "1"});
  return argv;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> list;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);)
    if (!line.empty()) list.push_back(line);
  return list;
}

class BadInput : public ::testing::TestWithParam<std::size_t> {};

TEST_P(BadInput, GivesOneClearErrorOrAFiniteImage) {
  const CorpusCase& c = badInputCorpus()[GetParam()];
  const fs::path dir = fs::temp_directory_path() / ("bounce_corpus_" + std::to_string(::getpid()) + "_" + c.name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  c.write(dir);
  const fs::path out = dir / "out";
  const std::vector<std::string> argv = commandLine(c, dir, out);
  std::string shown;
  for (const std::string& a : argv) shown += " " + a;
  SCOPED_TRACE("bounce" + shown.substr(shown.find(' ', 1)));

  const ProcessResult r = runProcess(argv, {}, 100.0);
  ASSERT_FALSE(r.timedOut) << "hung:\n" << r.output;
  ASSERT_EQ(r.signal, 0) << "crashed with signal " << r.signal << ":\n" << r.output;
#if !defined(__SANITIZE_ADDRESS__)
  if (c.maxSeconds > 0.0) {
    EXPECT_LE(r.seconds, c.maxSeconds) << "took too long:\n" << r.output;
  }
  if (c.maxMegabytes > 0) {
    EXPECT_LE(r.peakMegabytes, c.maxMegabytes) << "peak memory in MB:\n" << r.output;
  }
#endif
  if (c.check) {
    const std::string wrong = c.check(dir);
    EXPECT_TRUE(wrong.empty()) << wrong << "\n" << r.output;
  }
  if (c.outcome == Outcome::Completes) {
    EXPECT_EQ(r.exitCode, 0) << r.output;
  } else if (c.outcome == Outcome::FiniteImage) {
    ASSERT_EQ(r.exitCode, 0) << r.output;
    // readImage refuses any NaN or infinity, naming the first. Every scene
    // of the corpus is lit (a sun, a sky, a light): a black frame is a
    // silently wrong picture, not a pass.
    io::ImageF image;
    ASSERT_NO_THROW(image = io::readImage(out / "render.exr")) << r.output;
    const std::size_t channels = image.channelCount();
    double brightest = 0.0;
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
      if (i % channels < 3) brightest = std::max(brightest, double(image.pixels[i]));
    EXPECT_GT(brightest, 0.0) << "an all-black frame:\n" << r.output;
  } else {
    EXPECT_TRUE(r.exitCode == 1 || r.exitCode == 2) << "exit status " << r.exitCode << ":\n" << r.output;
    const std::vector<std::string> all = lines(r.output);
    const auto errors = std::count_if(all.begin(), all.end(),
                                      [](const std::string& line) { return line.starts_with("bounce: error:"); });
    ASSERT_EQ(errors, 1) << "one error line:\n" << r.output;
    const std::string& error = all.back();
    std::cout << "    " << error << "\n";  // every message, for people reading the test log
    ASSERT_TRUE(error.starts_with("bounce: error:")) << "the error is the last line:\n" << r.output;
    if (!c.file.empty()) {
      EXPECT_NE(error.find(c.file), std::string::npos) << "names the file: " << error;
    }
    EXPECT_NE(error.find(c.mentions), std::string::npos) << "says \"" << c.mentions << "\": " << error;
    EXPECT_FALSE(fs::exists(out / "render.png")) << "wrote an image anyway";
  }
  fs::remove_all(dir);
}

std::string caseName(const ::testing::TestParamInfo<std::size_t>& info) { return badInputCorpus()[info.param].name; }

INSTANTIATE_TEST_SUITE_P(Corpus, BadInput, ::testing::Range(std::size_t(0), badInputCorpus().size()), caseName);

TEST(BadInputCorpus, HasAFewHundredUniquelyNamedCases) {
  std::vector<std::string> names;
  for (const CorpusCase& c : badInputCorpus()) names.push_back(c.name);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end()) << "two cases share a name";
  EXPECT_GE(names.size(), 200u);
}

}  // namespace
}  // namespace bounce::testing
