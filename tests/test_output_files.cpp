// What the commands write (app/output_files.h, io::writeFileAtomically):
// nothing outside the output folder is touched through a link planted in
// it, and nothing in it that no Bounce run wrote is replaced (issue 46).
//
// The write probe and the temporary files used to be named after the
// process id, so a link planted at "<name>.tmp-<pid>" was written through
// (D3, D4): these tests plant a link at exactly that name, with this test
// process's id, and call the writers in this process.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "app/option_checks.h"
#include "app/output_files.h"
#include "io/image_io.h"

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

std::string contents(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeText(const fs::path& file, const std::string& text) { std::ofstream(file, std::ios::binary) << text; }

std::string pid() { return std::to_string(::getpid()); }

// A fresh folder with an output folder `out` in it and, beside it (outside
// the output folder), a victim file holding "x".
class OutputFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("bounce_output_files_" + pid() + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(out());
    writeText(victim(), "x");
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path out() const { return root_ / "out"; }
  fs::path victim() const { return root_ / "victim"; }

  fs::path root_;
};

TEST_F(OutputFiles, TheWriteProbeIsNotWrittenThroughALinkAtItsOldName) {
  const fs::path link = out() / (".bounce-write-probe-" + pid());
  fs::create_symlink(victim(), link);
  checkWritableDirectory(out(), "--out");
  EXPECT_EQ(contents(victim()), "x");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
}

TEST_F(OutputFiles, AWriteGoesNeitherThroughALinkAtTheOldTemporaryNameNorLeavesItInPlace) {
  const fs::path link = out() / ("render.png.tmp-" + pid());
  fs::create_symlink(victim(), link);
  io::writeFileAtomically(out() / "render.png", "PNG", 3);
  writeTextFile(out() / "notes.json", "{}");  // the text writer goes the same way
  EXPECT_EQ(contents(victim()), "x");
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(out() / "render.png")));
  EXPECT_EQ(contents(out() / "render.png"), "PNG");
  EXPECT_EQ(contents(out() / "notes.json"), "{}");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
}

TEST_F(OutputFiles, TheRecordIsNotWrittenThroughALinkAtItsOldTemporaryName) {
  fs::create_symlink(victim(), out() / (std::string(OutputFolder::kRecordName) + ".tmp-" + pid()));
  OutputFolder(out(), "--out", false).prepare({"render.png"}, {}, {});
  EXPECT_EQ(contents(victim()), "x");
  const fs::path record = out() / OutputFolder::kRecordName;
  ASSERT_TRUE(fs::is_regular_file(fs::symlink_status(record)));
  EXPECT_NE(contents(record).find("\nrender.png\n"), std::string::npos) << contents(record);
}

TEST_F(OutputFiles, ALinkWhereAFileGoesIsRefusedNotReplaced) {
  const fs::path link = out() / "out.json";
  fs::create_symlink(victim(), link);
  try {
    io::writeFileAtomically(link, "{}", 2);
    FAIL() << "replaced the link";
  } catch (const io::ImageIoError& error) {
    EXPECT_NE(std::string(error.what()).find("is a symbolic link"), std::string::npos) << error.what();
  }
  EXPECT_THROW(checkWritableFile(link, "--json"), std::runtime_error);
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_EQ(contents(victim()), "x");
  // Nor is a temporary file left behind.
  for (const fs::directory_entry& entry : fs::directory_iterator(out()))
    EXPECT_EQ(entry.path().filename(), "out.json") << "left " << entry.path();
}

TEST_F(OutputFiles, TheRecordIsReadOnlyAsASmallRegularFile) {
  const fs::path record = out() / OutputFolder::kRecordName;
  ASSERT_EQ(::mkfifo(record.c_str(), 0600), 0);
  try {
    OutputFolder(out(), "--out", false).prepare({"render.png"}, {}, {});
    FAIL() << "read a FIFO as the record";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(record.string() + ": is a FIFO"), std::string::npos) << error.what();
  }
  fs::remove(record);
  fs::create_symlink(victim(), record);
  EXPECT_THROW(OutputFolder(out(), "--out", true).prepare({"render.png"}, {}, {}), std::runtime_error);
  EXPECT_EQ(contents(victim()), "x");
}

TEST_F(OutputFiles, AnEntryThroughALinkIsLeftAsItIsAndForgotten) {
  fs::create_directories(root_ / "elsewhere");
  writeText(root_ / "elsewhere" / "keep.txt", "x");
  fs::create_directory_symlink(root_ / "elsewhere", out() / "frames");
  writeText(out() / OutputFolder::kRecordName, "frames/keep.txt\nnotes.txt\n");
  writeText(out() / "notes.txt", "an earlier run's");
  // The earlier run's notes.txt goes; frames/keep.txt, reached through a link, stays.
  EXPECT_EQ(OutputFolder(out(), "--out", false).prepare({"render.png"}, {}, {}), 1u);
  EXPECT_EQ(contents(root_ / "elsewhere" / "keep.txt"), "x");
  EXPECT_FALSE(fs::exists(out() / "notes.txt"));
  EXPECT_EQ(contents(out() / OutputFolder::kRecordName).find("keep.txt"), std::string::npos);
  // And a run that writes into frames/ is refused, naming the link.
  try {
    OutputFolder(out(), "--out", true).prepare({"frames/frame0000.png"}, {}, {});
    FAIL() << "wrote through frames/";
  } catch (const UsageError& error) {
    EXPECT_NE(std::string(error.what()).find((out() / "frames").string() + " is a symbolic link"), std::string::npos)
        << error.what();
  }
}

TEST_F(OutputFiles, ASharedFolderKeepsEveryRunsFilesAndReplacesOnlyThose) {
  // reference's OUT.exr: its folder holds other things too.
  writeText(out() / "mine.exr", "mine");
  OutputFolder(out(), "--out", false, OutputFolder::Use::Shared).prepare({"a.exr"}, {}, {});
  writeText(out() / "a.exr", "a");
  EXPECT_EQ(OutputFolder(out(), "--out", false, OutputFolder::Use::Shared).prepare({"b.exr"}, {}, {}), 0u);
  writeText(out() / "b.exr", "b");
  EXPECT_EQ(contents(out() / "a.exr"), "a") << "a shared folder removes nothing";
  // A rerun of either replaces its own files; the user's file is refused.
  EXPECT_NO_THROW(OutputFolder(out(), "--out", false, OutputFolder::Use::Shared).prepare({"a.exr"}, {}, {}));
  EXPECT_THROW(OutputFolder(out(), "--out", false, OutputFolder::Use::Shared).prepare({"mine.exr"}, {}, {}),
               UsageError);
  const std::string record = contents(out() / OutputFolder::kRecordName);
  EXPECT_NE(record.find("\na.exr\n"), std::string::npos) << record;
  EXPECT_NE(record.find("\nb.exr\n"), std::string::npos) << record;
  EXPECT_EQ(contents(out() / "mine.exr"), "mine");
}

TEST_F(OutputFiles, AMalformedRecordLineIsIgnoredNotAReasonEveryLaterRunFails) {
  writeText(out() / OutputFolder::kRecordName, ".\nframes/..\n../victim\n" + victim().string() + "\n");
  for (const bool overwrite : {false, true})
    EXPECT_NO_THROW(OutputFolder(out(), "--out", overwrite).prepare({"render.png"}, {}, {}));
  EXPECT_EQ(contents(victim()), "x");
  EXPECT_TRUE(fs::is_directory(out()));
}

}  // namespace
}  // namespace bounce::app
