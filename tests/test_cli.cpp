// The bounce command as a user runs it: exit codes, messages, files.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include "io/image_io.h"

namespace {

namespace fs = std::filesystem;

struct Result {
  int exitCode;
  std::string output;  // stdout and stderr together
};

Result run(const std::string& arguments, const std::string& environment = "") {
  const std::string command = environment + " " + BOUNCE_BINARY + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string output;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), int(buffer.size()), pipe)) output += buffer.data();
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

fs::path freshDirectory(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("bounce_cli_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

std::size_t lineCount(const std::string& text) { return std::size_t(std::count(text.begin(), text.end(), '\n')); }

TEST(Cli, BadArgumentsGiveOneLineAndExitTwo) {
  for (const char* arguments : {"render --width 0", "render --height -3", "render --frames abc",
                                "render --no-such-flag", "bench --width 99999", "frobnicate"}) {
    Result r = run(arguments);
    EXPECT_EQ(r.exitCode, 2) << arguments << ": " << r.output;
    EXPECT_EQ(lineCount(r.output), 1u) << arguments << ": " << r.output;
    EXPECT_EQ(r.output.rfind("bounce: error:", 0), 0u) << r.output;
  }
}

TEST(Cli, HelpWorksOnEveryCommand) {
  for (const char* arguments : {"--help", "render --help", "info --help", "bench --help"}) {
    Result r = run(arguments);
    EXPECT_EQ(r.exitCode, 0) << arguments;
    EXPECT_NE(r.output.find("--"), std::string::npos) << arguments;
  }
}

TEST(Cli, NoVulkanDriverIsAClearErrorNamingThePackage) {
  Result r = run("info", "VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json");
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("mesa-vulkan-drivers"), std::string::npos) << r.output;
}

TEST(Cli, UnknownDeviceIndexListsTheDevices) {
  Result r = run("render --device 42 --out " + freshDirectory("device").string());
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("device 42 does not exist"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("0: "), std::string::npos) << "the listing names device 0: " << r.output;
}

TEST(Cli, RenderWritesImagesStagesAndTimingsWithoutValidationMessages) {
  const fs::path out = freshDirectory("render");
  Result r = run("render --validate --width 64 --height 48 --frames 3 --dump-stages --out " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("validation"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("render.analytic_gbuffer"), std::string::npos) << "timing table: " << r.output;
  EXPECT_NE(r.output.find("render.direct_sun"), std::string::npos) << r.output;

  bounce::io::ImageF png = bounce::io::readImage(out / "render.png");
  EXPECT_EQ(png.width, 64);
  EXPECT_EQ(png.height, 48);
  bounce::io::ImageF exr = bounce::io::readImage(out / "render.exr");
  EXPECT_EQ(exr.width, 64);
  // Stage dumps of the last frame: every pass output, as EXR and PNG.
  for (const char* stem : {"frame0002.render.analytic_gbuffer.gOut_ViewZ", "frame0002.render.direct_sun.gOut_Radiance",
                           "frame0002.render.analytic_gbuffer.gOut_NormalRoughness",
                           "frame0002.render.analytic_gbuffer.gOut_BaseColorMetallic"}) {
    EXPECT_TRUE(fs::exists(out / "stages" / (std::string(stem) + ".exr"))) << stem;
    EXPECT_TRUE(fs::exists(out / "stages" / (std::string(stem) + ".png"))) << stem;
  }
  fs::remove_all(out);
}

TEST(Cli, DumpFramePastTheEndIsRefused) {
  const fs::path out = freshDirectory("dumpframes");
  Result r = run("render --frames 2 --dump-stages --dump-frames 5 --out " + out.string());
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("--dump-frames 5"), std::string::npos) << r.output;
}

TEST(Cli, BenchPrintsTimingsAndBandwidth) {
  Result r = run("bench --width 32 --height 32 --frames 3 --warmup 1 --copy-mb 1");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("gpu.copy_bandwidth"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("copy bandwidth:"), std::string::npos) << r.output;
}

}  // namespace
