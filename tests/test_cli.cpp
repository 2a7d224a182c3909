// The bounce command as a user runs it: exit codes, messages, files.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "io/image_io.h"
#include "process.h"

namespace {

namespace fs = std::filesystem;

struct Result {
  int exitCode;
  std::string output;  // stdout and stderr together
};

// Runs bounce with `arguments` split at spaces (no shell in between) and
// `environment` ("NAME=value ...") added to this process's.
Result run(const std::string& arguments, const std::string& environment = "") {
  std::vector<std::string> argv = {BOUNCE_BINARY};
  for (std::string& word : bounce::testing::splitWords(arguments)) argv.push_back(std::move(word));
  const bounce::testing::ProcessResult r = bounce::testing::runProcess(argv, bounce::testing::splitWords(environment));
  return {r.exitCode, r.output};
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
  for (const char* arguments : {"--help", "render --help", "info --help", "bench --help", "reference --help"}) {
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
  Result r =
      run("render cornell --validate --width 64 --height 48 --frames 3 --dump-stages --hdr "
          "--aov viewZ,roughness,motion --out " +
          out.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("validation message"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("render.gbuffer"), std::string::npos) << "timing table: " << r.output;
  EXPECT_NE(r.output.find("render.direct_light"), std::string::npos) << r.output;

  bounce::io::ImageF png = bounce::io::readImage(out / "render.png");
  EXPECT_EQ(png.width, 64);
  EXPECT_EQ(png.height, 48);
  bounce::io::ImageF exr = bounce::io::readImage(out / "render.exr");
  EXPECT_EQ(exr.width, 64);
  // Every frame as PNG (and, with --hdr, linear EXR).
  for (const char* frame : {"frame0000", "frame0001", "frame0002"}) {
    EXPECT_TRUE(fs::exists(out / "frames" / (std::string(frame) + ".png"))) << frame;
    EXPECT_TRUE(fs::exists(out / "frames" / (std::string(frame) + ".exr"))) << frame;
  }
  // The asked-for AOVs of the last frame, EXR and false colour.
  for (const char* aov : {"viewZ", "roughness", "motion"}) {
    EXPECT_TRUE(fs::exists(out / "aov" / (std::string(aov) + ".exr"))) << aov;
    EXPECT_TRUE(fs::exists(out / "aov" / (std::string(aov) + ".png"))) << aov;
  }
  EXPECT_FALSE(fs::exists(out / "aov" / "normal.exr")) << "only what was asked for";
  EXPECT_TRUE(fs::exists(out / "animation.png")) << "animated PNG of the 3 frames";
  EXPECT_EQ(bounce::io::readImage(out / "animation.png").width, 64) << "its first frame is a plain PNG";
  // Stage dumps of the last frame: every pass output, as EXR and PNG.
  for (const char* stem : {"frame0002.render.gbuffer.gOut_ViewZ", "frame0002.render.direct_light.gOut_Radiance",
                           "frame0002.render.gbuffer.gOut_NormalRoughness", "frame0002.render.gbuffer.gOut_Motion",
                           "frame0002.render.gbuffer.gOut_BaseColorMetallic"}) {
    EXPECT_TRUE(fs::exists(out / "stages" / (std::string(stem) + ".exr"))) << stem;
    EXPECT_TRUE(fs::exists(out / "stages" / (std::string(stem) + ".png"))) << stem;
  }
  fs::remove_all(out);
}

TEST(Cli, BadScenesCamerasAndAovsAreOneClearLine) {
  const fs::path out = freshDirectory("badinput");
  Result unknown = run("render no-such-scene --out " + out.string());
  EXPECT_EQ(unknown.exitCode, 1);
  EXPECT_NE(unknown.output.find("neither a built-in scene"), std::string::npos) << unknown.output;
  EXPECT_NE(unknown.output.find("cornell"), std::string::npos) << "lists the built-ins: " << unknown.output;

  Result missing = run("render " + (out / "missing.gltf").string() + " --out " + out.string());
  EXPECT_EQ(missing.exitCode, 1);
  EXPECT_NE(missing.output.find("missing.gltf"), std::string::npos) << missing.output;

  const fs::path keyframes = out / "path.json";
  std::ofstream(keyframes) << "{\"keyframes\": [{\"time\": 0, \"position\": [0, 1]}]}";
  Result camera = run("render cornell --camera " + keyframes.string() + " --out " + out.string());
  EXPECT_EQ(camera.exitCode, 1);
  EXPECT_NE(camera.output.find("path.json"), std::string::npos) << camera.output;

  Result aov = run("render cornell --aov colour --out " + out.string());
  EXPECT_EQ(aov.exitCode, 1);
  EXPECT_NE(aov.output.find("unknown image 'colour'"), std::string::npos) << aov.output;
  fs::remove_all(out);
}

TEST(Cli, RenderWithGiSettingsDumpsEveryGiStageAndItsValidationSheet) {
  const fs::path out = freshDirectory("gi");
  const fs::path settings = freshDirectory("gi_settings_file").string() + ".json";
  std::ofstream(settings) << R"({"diffuse": {"spatial_radius": 4, "visibility_steps": 6}})";
  Result r = run("render cornell --validate --width 48 --height 32 --frames 2 --gi-warmup 2 --gi-settings " +
                 settings.string() + " --gi.diffuse.spatial_samples 3 --dump-stages --aov indirect-diffuse --out " +
                 out.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("validation message"), std::string::npos) << r.output;
  for (const char* pass :
       {"gi.store_history", "gi.diffuse.gather", "gi.diffuse.temporal_reuse", "gi.diffuse.spatial_reuse",
        "gi.diffuse.resolve", "gi.diffuse.temporal_filter", "gi.composite"})
    EXPECT_NE(r.output.find(pass), std::string::npos) << "timing table lists " << pass << ": " << r.output;
  for (const char* stem :
       {"frame0001.gi.diffuse.reservoir_view.spatial_reuse2.gOut_M",
        "frame0001.gi.diffuse.reservoir_view.gather.gOut_W", "frame0001.gi.diffuse.resolve.gOut_Diffuse",
        "frame0001.gi.diffuse.temporal_filter.gOut_Filtered", "frame0001.gi.composite.gOut_Composite"})
    EXPECT_TRUE(fs::exists(out / "stages" / (std::string(stem) + ".png"))) << stem;
  EXPECT_TRUE(fs::exists(out / "stages" / "frame0001.validation.png"));
  EXPECT_TRUE(fs::exists(out / "aov" / "indirect-diffuse.exr"));
  EXPECT_EQ(bounce::io::readImage(out / "aov" / "indirect-diffuse.exr").width, 48);
  fs::remove_all(out);
  fs::remove(settings);
}

TEST(Cli, GiOffAndTheNoReuseBaselineRecordOnlyTheirPasses) {
  const fs::path out = freshDirectory("gi_off");
  Result off = run("render cornell --width 32 --height 24 --gi off --out " + out.string());
  ASSERT_EQ(off.exitCode, 0) << off.output;
  EXPECT_EQ(off.output.find("gi."), std::string::npos) << "no GI pass runs: " << off.output;
  Result baseline = run("render cornell --width 32 --height 24 --gi-warmup 1 --gi.restir off --out " + out.string());
  ASSERT_EQ(baseline.exitCode, 0) << baseline.output;
  EXPECT_NE(baseline.output.find("gi.diffuse.resolve"), std::string::npos) << baseline.output;
  EXPECT_EQ(baseline.output.find("gi.diffuse.temporal_reuse"), std::string::npos) << baseline.output;
  EXPECT_EQ(baseline.output.find("gi.diffuse.spatial_reuse"), std::string::npos) << baseline.output;
  fs::remove_all(out);
}

TEST(Cli, BadGiSettingsAreOneLineNamingTheKeyOrFile) {
  const fs::path out = freshDirectory("gi_bad");
  fs::create_directories(out);
  const fs::path malformed = out / "malformed.json";
  std::ofstream(malformed) << R"({"diffuse": {"spatial_radius": }})";
  const fs::path unknownKey = out / "unknown.json";
  std::ofstream(unknownKey) << R"({"diffuse": {"spatial_radios": 3}})";
  struct Case {
    std::string arguments;
    int exitCode;
    std::string mentions;
  };
  const std::vector<Case> cases = {
      {"--gi.diffuse.spatial_radios 3", 2, "did you mean gi.diffuse.spatial_radius"},
      {"--gi.diffuse.spatial_radius 300", 1, "expected a number in [0, 256]"},
      {"--gi.diffuse.jacobian maybe", 1, "gi.diffuse.jacobian"},
      {"--gi sideways", 2, "--gi"},
      {"--gi-settings " + (out / "missing.json").string(), 2, "missing.json"},
      {"--gi-settings " + malformed.string(), 1, "malformed.json: parse error at line 1"},
      {"--gi-settings " + unknownKey.string(), 1, "unknown.json"},
      {"--gi.diffuse.screen_candidates 0 --gi.diffuse.bright_candidates 0 --gi.diffuse.environment_candidates 0", 1,
       "all 0"},
  };
  for (const Case& c : cases) {
    Result r = run("render cornell --width 16 --height 16 " + c.arguments + " --out " + (out / "render").string());
    EXPECT_EQ(r.exitCode, c.exitCode) << c.arguments << ": " << r.output;
    const std::size_t error = r.output.find("bounce: error:");
    ASSERT_NE(error, std::string::npos) << c.arguments << ": " << r.output;
    EXPECT_EQ(lineCount(r.output.substr(error)), 1u) << c.arguments << ": " << r.output;
    EXPECT_NE(r.output.find(c.mentions), std::string::npos) << c.arguments << ": " << r.output;
    EXPECT_FALSE(fs::exists(out / "render" / "render.png")) << c.arguments << " wrote an image anyway";
  }
  fs::remove_all(out);
}

// The frame count an APNG announces in its acTL chunk (0 if none).
std::uint32_t apngFrameCount(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const std::size_t at = bytes.find("acTL");
  if (at == std::string::npos || at + 8 > bytes.size()) return 0;
  std::uint32_t count = 0;
  for (int i = 0; i < 4; ++i) count = (count << 8) | std::uint8_t(bytes[at + 4 + std::size_t(i)]);
  return count;
}

TEST(Cli, BrdfVizWritesLabelledAnimations) {
  const fs::path out = freshDirectory("brdfviz");
  Result r = run("brdf-viz --frames 5 --size 64 --out " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* name : {"roughness_sweep.png", "view_sweep.png"}) {
    EXPECT_EQ(apngFrameCount(out / name), 5u) << name;
    EXPECT_GT(bounce::io::readImage(out / name).height, 64) << "plot plus its labels";
  }
  Result bad = run("brdf-viz --base-color 1,2 --out " + out.string());
  EXPECT_EQ(bad.exitCode, 2) << bad.output;
  fs::remove_all(out);
}

TEST(Cli, DumpFramePastTheEndIsRefused) {
  const fs::path out = freshDirectory("dumpframes");
  Result r = run("render --frames 2 --dump-stages --dump-frames 5 --out " + out.string());
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("--dump-frames 5"), std::string::npos) << r.output;
}

TEST(Cli, BenchPrintsTimingsAndBandwidth) {
  Result r = run("bench cornell --validate --width 32 --height 32 --frames 3 --warmup 1 --copy-mb 1 --rays 256");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("render.bvh_trace_rays"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("incoherent closest-hit"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("gpu.copy_bandwidth"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("copy bandwidth:"), std::string::npos) << r.output;
}

}  // namespace

namespace {

TEST(Cli, ReferenceWritesTheFrameItsPartsAndItsGBuffer) {
  const fs::path dir = freshDirectory("reference");
  Result r =
      run("reference cornell --width 24 --height 16 --spp 4 --halves --validate --out " + (dir / "ref.exr").string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* name :
       {"ref.exr", "ref.png", "ref.direct.exr", "ref.indirect-diffuse.exr", "ref.indirect-specular.exr",
        "ref.indirect-diffuse.png", "ref.halfA.exr", "ref.halfB.exr", "ref.json", "ref.sheet.png",
        "ref.gbuffer/viewZ.exr", "ref.gbuffer/normal.exr", "ref.gbuffer/sheet.png", "ref.gbuffer/normals.png"})
    EXPECT_TRUE(fs::exists(dir / name)) << name << "\n" << r.output;
  const bounce::io::ImageF image = bounce::io::readImage(dir / "ref.exr");
  EXPECT_EQ(image.width, 24);
  EXPECT_EQ(image.height, 16);
  std::ifstream json(dir / "ref.json");
  const std::string meta((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_NE(meta.find("\"spp\": 4"), std::string::npos) << meta;
  EXPECT_NE(meta.find("\"interrupted\": false"), std::string::npos) << meta;
  EXPECT_NE(r.output.find("relMSE between the two halves"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

TEST(Cli, ReferenceStopsAtTheTargetRelMse) {
  const fs::path dir = freshDirectory("reference_target");
  // A loose target is met at the first check (16 spp), long before --spp.
  Result r =
      run("reference cornell --width 16 --height 12 --spp 4096 --target-relmse 10 --out " + (dir / "ref.exr").string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("reached --target-relmse 10 at 16 spp"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

TEST(Cli, ReferenceBadArgumentsAreOneClearLine) {
  const fs::path dir = freshDirectory("reference_bad");
  const std::vector<std::string> cases = {"reference cornell --spp 0",
                                          "reference cornell --out " + (dir / "ref.png").string(),
                                          "reference no-such-scene --out " + (dir / "ref.exr").string(),
                                          "reference cornell --max-bounces 0", "reference cornell --target-relmse -1"};
  for (const std::string& arguments : cases) {
    Result r = run(arguments);
    EXPECT_NE(r.exitCode, 0) << arguments;
    EXPECT_EQ(lineCount(r.output), 1u) << arguments << ": " << r.output;
    EXPECT_EQ(r.output.rfind("bounce: error:", 0), 0u) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "ref.exr"));
  fs::remove_all(dir);
}

TEST(Cli, ReferenceKeepsWhatItAccumulatedOnCtrlC) {
  const fs::path dir = freshDirectory("reference_interrupt");
  fs::create_directories(dir);
  const fs::path log = dir / "log.txt";
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const std::string out = (dir / "ref.exr").string();
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    execl(BOUNCE_BINARY, BOUNCE_BINARY, "reference", "cornell", "--width", "16", "--height", "12", "--spp", "1000000",
          "--out", out.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait until it is sampling (the progress is in its json only at the end,
  // so watch for the scene line), then interrupt.
  for (int i = 0; i < 600; ++i) {
    std::ifstream in(log);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (text.find("scene: cornell") != std::string::npos) break;
    usleep(100000);
  }
  usleep(1500000);
  kill(child, SIGINT);
  int status = 0;
  waitpid(child, &status, 0);
  std::ifstream in(log);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_TRUE(WIFEXITED(status)) << text;
  EXPECT_EQ(WEXITSTATUS(status), 130) << text;
  EXPECT_NE(text.find("interrupted: wrote the"), std::string::npos) << text;
  EXPECT_TRUE(fs::exists(dir / "ref.exr")) << text;
  std::ifstream json(dir / "ref.json");
  const std::string meta((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
  EXPECT_NE(meta.find("\"interrupted\": true"), std::string::npos) << meta;
  fs::remove_all(dir);
}

// --- Lights too bright for 32-bit floats (issue 10, item 6): a glTF sun of
// 3e38 and --env-intensity 1e38 made the sky NaN and exited 0. Such inputs
// are refused up front, naming the light or the option and the limit; just
// within the limit the frame renders, saturated but finite.

// A 4 m floor under a KHR_lights_punctual directional light named Sun, which
// the CLI adopts as the sun.
fs::path writeSunlitFloor(const fs::path& dir, const std::string& intensity) {
  fs::create_directories(dir);
  const fs::path file = dir / ("sun-" + intensity + ".gltf");
  std::ofstream(file) << R"({"asset": {"version": "2.0"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "name": "Sun", "intensity": )"
                      << intensity << R"(}]}},
    "buffers": [{"byteLength": 60, "uri": "data:application/octet-stream;base64,)"
                      << "AAAAwAAAAAAAAADAAAAAQAAAAAAAAADAAAAAQAAAAAAAAABAAAAAwAAAAAAAAABAAAACAAEAAAADAAIA"
                      << R"("}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-2, 0, -2], "max": [2, 0, 2]},
                  {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "nodes": [{"mesh": 0}, {"rotation": [-0.3826834, 0, 0, 0.9238795], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
    "scenes": [{"nodes": [0, 1]}], "scene": 0})";
  return file;
}

// Renders `arguments` into `out` and returns the largest value of the EXR,
// after checking that it exited 0 and that every value is finite.
float renderFiniteFrame(const std::string& arguments, const fs::path& out) {
  Result r = run(arguments + " --width 32 --height 24 --frames 1 --gi-warmup 2 --out " + out.string());
  EXPECT_EQ(r.exitCode, 0) << arguments << ": " << r.output;
  if (r.exitCode != 0) return 0.0f;
  const bounce::io::ImageF exr = bounce::io::readImage(out / "render.exr");
  float largest = 0.0f;
  std::size_t nonFinite = 0;
  for (float value : exr.pixels) {
    nonFinite += !std::isfinite(value);
    if (std::isfinite(value)) largest = std::max(largest, value);
  }
  EXPECT_EQ(nonFinite, 0u) << arguments;
  return largest;
}

// Expects `arguments` refused in one line naming `what` and the limit, and no image written.
void expectRefused(const std::string& arguments, const std::string& what, const fs::path& out) {
  Result r = run(arguments + " --width 32 --height 24 --frames 1 --out " + out.string());
  EXPECT_EQ(r.exitCode, 1) << arguments << ": " << r.output;
  EXPECT_EQ(lineCount(r.output), 1u) << arguments << ": " << r.output;
  EXPECT_EQ(r.output.rfind("bounce: error:", 0), 0u) << r.output;
  EXPECT_NE(r.output.find(what), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("above 1e+20"), std::string::npos) << "names the limit: " << r.output;
  EXPECT_FALSE(fs::exists(out / "render.exr")) << arguments;
}

TEST(Cli, AGltfSunBeyondFloatRangeIsRefusedAndOneAtTheLimitRendersFinite) {
  const fs::path dir = freshDirectory("bright_sun");
  expectRefused("render " + writeSunlitFloor(dir, "3e38").string(), "light 0 'Sun': intensity 3e+38", dir / "refused");
  // At the limit the sunlit floor is far brighter than a half float holds:
  // it saturates at the largest finite one.
  EXPECT_EQ(renderFiniteFrame("render " + writeSunlitFloor(dir, "1e20").string(), dir / "limit"), 65504.0f);
  fs::remove_all(dir);
}

TEST(Cli, AnEnvironmentIntensityBeyondFloatRangeIsRefusedAndOneWithinItRendersFinite) {
  const fs::path dir = freshDirectory("bright_environment");
  expectRefused("render cornell --env-intensity 1e38", "--env-intensity 1e+38", dir / "cornell");
  expectRefused("render sun-room --env-intensity 1e38", "--env-intensity 1e+38", dir / "sun-room");
  // The sky is the intensity times the sun's illuminance (10 in sun-room).
  expectRefused("render sun-room --env-intensity 1e20", "times the sun's illuminance 10", dir / "product");
  EXPECT_EQ(renderFiniteFrame("render sun-room --env-intensity 5e18", dir / "within"), 65504.0f);
  fs::remove_all(dir);
}

}  // namespace
