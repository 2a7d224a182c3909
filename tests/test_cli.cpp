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

#include <nlohmann/json.hpp>

#include <glm/glm.hpp>

#include "bounce/version.h"
#include "io/image_io.h"
#include "process.h"
#include "zero_png.h"

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

TEST(Cli, EveryMistakeOnTheCommandLineExitsTwoAndABadInputFileOne) {
  const fs::path dir = freshDirectory("exit_codes");
  fs::create_directories(dir);
  std::ofstream(dir / "deep.json") << std::string(100, '[') << std::string(100, ']');
  std::ofstream(dir / "range.json") << R"({"cache": {"memory_mib": 0}})";
  const std::string out = " --width 16 --height 12 --out " + (dir / "out").string();
  // Values refused after CLI11 has parsed them: their range, another
  // option, the scene's materials. docs/reliability.md: "2: the command line is wrong".
  for (const std::string arguments :
       {"render cornell --gi.cache.memory_mib 0", "render cornell --gi.diffuse.spatial_radius 1e9",
        "render sun-room --env-intensity 1e38", "render cornell --material cornell_white:roughness=0.5",
        "render cornell --no-sun --sun-elevation 30", "render cornell --aov colour",
        "render cornell --frames 2 --dump-stages --dump-frames 7", "render no-such-scene"}) {
    const Result r = run(arguments + out);
    EXPECT_EQ(r.exitCode, 2) << arguments << ": " << r.output;
    EXPECT_NE(r.output.find("bounce: error:"), std::string::npos) << r.output;
  }
  // A material name with a space cannot go through run()'s split at spaces.
  const bounce::testing::ProcessResult material = bounce::testing::runProcess(
      {BOUNCE_BINARY, "render", "cornell", "--material", "cornell white:roughness=-1", "--out", (dir / "out").string()});
  EXPECT_EQ(material.exitCode, 2) << material.output;
  EXPECT_NE(material.output.find("-1 is outside [0, 1]"), std::string::npos) << material.output;
  // A number too small for a float is a number (it is zero), not a mistake.
  const bounce::testing::ProcessResult tiny = bounce::testing::runProcess(
      {BOUNCE_BINARY, "render", "cornell", "--gi", "off", "--width", "16", "--height", "12", "--material",
       "cornell white:roughness=1e-46", "--out", (dir / "out").string()});
  EXPECT_EQ(tiny.exitCode, 0) << tiny.output;
  // A file that is wrong is bad input: 1, also when the same value on the
  // command line would be 2.
  for (const std::string& arguments : {"render cornell --gi-settings " + (dir / "deep.json").string(),
                                      "render cornell --gi-settings " + (dir / "range.json").string(),
                                      "render " + (dir / "missing.gltf").string()}) {
    const Result r = run(arguments + out);
    EXPECT_EQ(r.exitCode, 1) << arguments << ": " << r.output;
  }
  fs::remove_all(dir);
}

TEST(Cli, HelpWorksOnEveryCommand) {
  for (const char* arguments : {"--help", "render --help", "info --help", "bench --help", "reference --help",
                                "compare --help", "sheet --help", "brdf-viz --help", "denoise --help"}) {
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

// The README's first command, `bounce render --out out`, on a machine
// without a GPU: lavapipe (the tests' device, a CPU one) gets a smaller
// size and fewer warm-up frames, said on the console, for what the
// command line left unset; what it set is kept.
TEST(Cli, RenderOnACpuDeviceChoosesASmallerSizeAndWarmUpForWhatIsUnset) {
  const fs::path out = freshDirectory("render_quick_start");
  Result r = run("render --gi off --out " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("(CPU)"), std::string::npos) << "the tests run on lavapipe: " << r.output;
  EXPECT_NE(r.output.find("on a CPU device: 480x270 instead of 960x540"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warm-up frames"), std::string::npos) << "no GI, no warm-up: " << r.output;
  const bounce::io::ImageF image = bounce::io::readImage(out / "render.png");
  EXPECT_EQ(image.width, 480);
  EXPECT_EQ(image.height, 270);

  r = run("render cornell --width 32 --height 18 --out " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("on a CPU device: 8 GI warm-up frames instead of 16"), std::string::npos) << r.output;
  EXPECT_EQ(bounce::io::readImage(out / "render.png").width, 32) << "a size given is kept";

  r = run("render cornell --width 32 --height 18 --gi-warmup 2 --out " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("on a CPU device"), std::string::npos) << "everything given: " << r.output;
  fs::remove_all(out);
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
  EXPECT_EQ(unknown.exitCode, 2);  // a mistake on the command line
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
  EXPECT_EQ(aov.exitCode, 2);
  EXPECT_NE(aov.output.find("unknown image 'colour'"), std::string::npos) << aov.output;
  fs::remove_all(out);
}

TEST(Cli, RenderWithGiSettingsDumpsEveryGiStageAndItsValidationSheet) {
  const fs::path out = freshDirectory("gi");
  const fs::path settings = freshDirectory("gi_settings_file").string() + ".json";
  // The branch's own filter, as --gi.denoise.enabled off leaves it: from the settings file.
  std::ofstream(settings) << R"({"diffuse": {"spatial_radius": 4, "visibility_steps": 6}, "denoise": {"enabled": false}})";
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

// With the denoiser on (the default), every pass of it is timed and dumped, its validation
// view among the stages, the branches' filters are not recorded, and the
// validation sheet shows the denoiser's history.
TEST(Cli, RenderWithTheDenoiserDumpsItsStagesAndValidationView) {
  const fs::path out = freshDirectory("denoise");
  Result r = run("render cornell --validate --width 48 --height 32 --frames 1 --gi-warmup 2 --gi.denoise.enabled on "
                 "--dump-stages --out " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("validation message"), std::string::npos) << r.output;
  for (const char* pass :
       {"pre_pass", "temporal_accumulation", "history_fix", "blur", "post_blur", "temporal_stabilization"})
    EXPECT_NE(r.output.find(std::string("gi.denoise.") + pass), std::string::npos) << pass << ": " << r.output;
  EXPECT_EQ(r.output.find("gi.diffuse.temporal_filter"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("gi.specular.temporal_filter"), std::string::npos) << r.output;
  for (const char* stem : {"frame0000.gi.denoise.classify_tiles.gOut_Tiles",
                           "frame0000.gi.denoise.post_blur.specular.gOut_Filtered",
                           "frame0000.gi.denoise.pre_pass.diffuse.gOut_PrePassed",
                           "frame0000.gi.denoise.validation.gOut_Validation"})
    EXPECT_TRUE(fs::exists(out / "stages" / (std::string(stem) + ".png"))) << stem;
  EXPECT_TRUE(fs::exists(out / "stages" / "frame0000.validation.png"));
  fs::remove_all(out);
}

TEST(Cli, GiOffAndTheNoReuseBaselineRecordOnlyTheirPasses) {
  const fs::path out = freshDirectory("gi_off");
  Result off = run("render cornell --width 32 --height 24 --gi off --out " + out.string());
  ASSERT_EQ(off.exitCode, 0) << off.output;
  // The environment prefilter (gi.environment.*) is the renderer's too: its sky lights the direct pass.
  for (const char* pass : {"gi.store_history", "gi.diffuse.", "gi.composite"})
    EXPECT_EQ(off.output.find(pass), std::string::npos) << "no GI pass runs: " << off.output;
  Result baseline = run("render cornell --width 32 --height 24 --gi-warmup 1 --gi.restir off --out " + out.string());
  ASSERT_EQ(baseline.exitCode, 0) << baseline.output;
  EXPECT_NE(baseline.output.find("gi.diffuse.resolve"), std::string::npos) << baseline.output;
  EXPECT_EQ(baseline.output.find("gi.diffuse.temporal_reuse"), std::string::npos) << baseline.output;
  EXPECT_EQ(baseline.output.find("gi.diffuse.spatial_reuse"), std::string::npos) << baseline.output;
  fs::remove_all(out);
}

// The first frame prefilters the environment; dumping it copies the
// prefiltered image, which must still reach the GI passes in the layout
// EnvironmentPrefilter::output() promises (it did not: 10 validation errors).
TEST(Cli, DumpingTheFirstFrameWhereTheEnvironmentIsPrefilteredIsValid) {
  const fs::path out = freshDirectory("first_frame_dump");
  Result r = run("render cornell --width 32 --height 24 --frames 1 --gi-warmup 0 --dump-stages --validate --out " +
                 out.string());
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("alidation error"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(out / "stages")) << r.output;
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
      {"--gi.diffuse.spatial_radius 300", 2, "expected a number in [0, 256]"},
      {"--gi.diffuse.jacobian maybe", 2, "gi.diffuse.jacobian"},
      {"--gi sideways", 2, "--gi"},
      {"--gi-settings " + (out / "missing.json").string(), 2, "missing.json"},
      {"--gi-settings " + malformed.string(), 1, "malformed.json: parse error at line 1"},
      {"--gi-settings " + unknownKey.string(), 1, "unknown.json"},
      {"--gi.diffuse.screen_candidates 0 --gi.diffuse.bright_candidates 0 --gi.diffuse.environment_candidates 0", 2,
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

// Settings that contradict each other only with the bridge the command uses
// (every initial candidate 0: rays replace the environment's) were refused
// by the library once built, after the scene had loaded, with exit 1. The
// scene here does not exist: a check made before loading it is what speaks.
TEST(Cli, ContradictoryGiSettingsAreRefusedBeforeTheSceneLoads) {
  const fs::path dir = freshDirectory("gi_contradiction");
  fs::create_directories(dir);
  const std::string scene = (dir / "missing.gltf").string(), out = " --out " + (dir / "out").string();
  const std::string zeros =
      " --gi.diffuse.screen_candidates 0 --gi.diffuse.bright_candidates 0 --gi.diffuse.ray_candidates 0";
  for (const char* command : {"render ", "ghosting ", "bench "}) {
    const Result flags = run(command + scene + zeros + (std::string(command) == "bench " ? "" : out));
    EXPECT_EQ(flags.exitCode, 2) << command << flags.output;
    EXPECT_EQ(lineCount(flags.output), 1u) << command << flags.output;
    EXPECT_NE(flags.output.find("gi.diffuse.ray_candidates is 0"), std::string::npos) << command << flags.output;
  }
  // Without the bridge the environment candidates remain: nothing contradicts, and the missing scene is what fails.
  const Result screenOnly = run("render " + scene + zeros + " --scene-bridge none" + out);
  EXPECT_EQ(screenOnly.exitCode, 1) << screenOnly.output;
  EXPECT_NE(screenOnly.output.find("missing.gltf"), std::string::npos) << screenOnly.output;

  const fs::path file = dir / "settings.json";
  std::ofstream(file) << R"({"diffuse": {"screen_candidates": 0, "bright_candidates": 0, "ray_candidates": 0}})";
  const Result fromFile = run("render " + scene + " --gi-settings " + file.string() + out);
  EXPECT_EQ(fromFile.exitCode, 1) << fromFile.output;
  EXPECT_EQ(fromFile.output.rfind("bounce: error: " + file.string() + ": gi.diffuse.screen_candidates", 0), 0u)
      << fromFile.output;
  fs::remove_all(dir);
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
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("--dump-frames 5"), std::string::npos) << r.output;
}

TEST(Cli, BenchPrintsTimingsAndBandwidth) {
  Result r = run("bench cornell --validate --width 32 --height 32 --frames 3 --warmup 1 --copy-mb 1 --rays 256");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("render.bvh_trace_rays"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("incoherent closest-hit"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("bench.copy_bandwidth"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("copy bandwidth:"), std::string::npos) << r.output;
  // Each GI pass against its traffic floor, at the copy pass's bandwidth.
  EXPECT_NE(r.output.find("traffic floors of the GI passes"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the copy pass's bandwidth"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("all gi.*"), std::string::npos) << r.output;
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

// bounce denoise: the path tracer's 1-spp signals of a static view of
// cornell, handed to the library as an engine's own, denoised. The
// denoised error is measured against a 32-spp reference, whose own noise
// is most of what remains at this size (measured on lavapipe: 0.032
// diffuse, 0.21 specular, 0.018 the frame, from 0.73, 8.3 and 0.40 noisy):
// a tenth of the input's error takes spatial filtering as well as the six
// frames' temporal average (which alone gives a sixth), and the error must
// fall from the first frame to the last as the history grows.
TEST(Cli, DenoiseHandsThePathTracersSignalsToTheDenoiserAlone) {
  const fs::path dir = freshDirectory("denoise_command");
  Result r = run("denoise cornell --validate --width 64 --height 48 --frames 6 --reference-spp 32 --dump-stages --out " +
                 dir.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* version : {"noisy", "denoised", "reference"})
    for (const char* part : {".indirect-diffuse", ".indirect-specular", ""})
      for (const char* extension : {".exr", ".png"})
        EXPECT_TRUE(fs::exists(dir / (std::string(version) + part + extension))) << version << part << extension;
  for (const char* name : {"sheet.png", "denoise.json", "stages/frame0005.gi.engine_signal.diffuse.gOut_Signal.exr",
                           "stages/frame0005.gi.denoise.temporal_stabilization.specular.gOut_Stabilized.exr",
                           "stages/frame0005.validation.png"})
    EXPECT_TRUE(fs::exists(dir / name)) << name << "\n" << r.output;
  // The library denoised the engine's signals; its branches never ran.
  EXPECT_NE(r.output.find("gi.engine_signal.specular"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("gi.diffuse."), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("gi.specular."), std::string::npos) << r.output;

  std::ifstream file(dir / "denoise.json");
  const nlohmann::json json = nlohmann::json::parse(file);
  EXPECT_EQ(json["last_frame"], 5);
  const nlohmann::json& measured = json["measured_frames"];
  ASSERT_EQ(measured.size(), 6u) << "a static camera shows the reference's view in every frame";
  for (const char* part : {"diffuse", "specular", "frame"}) {
    const double noisy = json["relmse"][part]["noisy_relmse"], denoised = json["relmse"][part]["denoised_relmse"];
    const double first = measured.front()["relmse"][part]["denoised_relmse"];
    std::printf("%s: relMSE %.4f noisy, %.4f denoised (frame 0: %.4f)\n", part, noisy, denoised, first);
    EXPECT_LT(denoised, noisy / 10.0) << part;
    EXPECT_LT(denoised, first) << part << ": the history made no difference";
    EXPECT_GT(noisy, 0.1) << part << ": one sample a pixel is far from the reference";
  }
  fs::remove_all(dir);
}

// bounce denoise --checkerboard: the same sequence, each signal handed
// over as every other pixel packed to half width (the engine's side of
// gi.denoise.checkerboard, packed on the GPU). Against the same 32-spp
// reference (whose noise is most of what remains), the denoised error
// stays within 1.5x of the full signals' (measured on lavapipe: diffuse
// 0.037 against 0.032, specular 0.19 against 0.19, the frame 0.020
// against 0.018) and a tenth of the input's; the noisy images are every
// pixel's in both runs.
TEST(Cli, DenoiseCheckerboardHandsTheDenoiserHalfThePixels) {
  const fs::path full = freshDirectory("denoise_full"), halves = freshDirectory("denoise_checkerboard");
  const std::string common = "denoise cornell --validate --width 64 --height 48 --frames 6 --reference-spp 32 --out ";
  Result fullRun = run(common + full.string());
  ASSERT_EQ(fullRun.exitCode, 0) << fullRun.output;
  Result r = run(common + halves.string() + " --checkerboard");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* pass : {"denoise.checkerboard_pack.diffuse", "denoise.checkerboard_pack.specular",
                           "gi.denoise.pre_pass"})
    EXPECT_NE(r.output.find(pass), std::string::npos) << pass << "\n" << r.output;
  EXPECT_EQ(fullRun.output.find("checkerboard_pack"), std::string::npos) << fullRun.output;
  const auto json = [](const fs::path& dir) {
    std::ifstream file(dir / "denoise.json");
    return nlohmann::json::parse(file);
  };
  const nlohmann::json fullJson = json(full), halvesJson = json(halves);
  EXPECT_EQ(halvesJson["checkerboard"], true);
  EXPECT_EQ(halvesJson["settings"]["denoise.checkerboard"], "on");
  EXPECT_EQ(fullJson["checkerboard"], false);
  for (const char* part : {"diffuse", "specular", "frame"}) {
    const double noisy = halvesJson["relmse"][part]["noisy_relmse"];
    const double denoised = halvesJson["relmse"][part]["denoised_relmse"];
    const double fullDenoised = fullJson["relmse"][part]["denoised_relmse"];
    std::printf("%s: relMSE %.4f noisy, %.4f denoised from every pixel, %.4f from the checkerboard\n", part, noisy,
                fullDenoised, denoised);
    EXPECT_EQ(noisy, double(fullJson["relmse"][part]["noisy_relmse"])) << part << ": the same noisy sequence";
    EXPECT_LT(denoised, 1.5 * fullDenoised) << part;
    EXPECT_LT(denoised, noisy / 10.0) << part;
  }
  fs::remove_all(full);
  fs::remove_all(halves);
}

// A black scene: every relMSE is 0 against 0 (defined, by its epsilon) and
// the ratio denoised / noisy is 0 / 0, which the table printed as -nan.
// Now it says "undefined" and why, and the JSON has null.
TEST(Cli, DenoiseOfABlackSceneSaysItsRatioIsUndefined) {
  const fs::path dir = freshDirectory("denoise_black");
  Result r =
      run("denoise sun-room --no-sun --env-intensity 0 --width 32 --height 18 --frames 1 --reference-spp 1 "
          "--out " +
          dir.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find(" nan"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("-nan"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("  frame                         0            0          undefined\n"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("undefined where the noisy relMSE is 0: the reference is black"), std::string::npos)
      << r.output;
  std::ifstream file(dir / "denoise.json");
  const nlohmann::json json = nlohmann::json::parse(file);
  for (const char* part : {"diffuse", "specular", "frame"}) {
    EXPECT_EQ(json["relmse"][part]["noisy_relmse"], 0.0) << part;
    EXPECT_EQ(json["relmse"][part]["denoised_relmse"], 0.0) << part;
    EXPECT_TRUE(json["relmse"][part]["ratio"].is_null()) << part;
  }
  fs::remove_all(dir);
}

TEST(Cli, DenoiseBadArgumentsAreOneClearLine) {
  const fs::path dir = freshDirectory("denoise_bad");
  fs::create_directories(dir);
  // A settings file where an output will go: outputs never replace inputs.
  const fs::path settings = dir / "denoise.json";
  std::ofstream(settings) << "{}\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"denoise cornell --frames 0", "--frames"},
      {"denoise cornell --spp 0", "--spp"},
      {"denoise cornell --gi.denoise.enabled off --out " + dir.string(), "runs the denoiser"},
      {"denoise cornell --gi-settings " + settings.string() + " --out " + dir.string(),
       "refusing to write --out over the input"},
      {"denoise no-such-scene --out " + dir.string(), "no-such-scene"}};
  for (const auto& [arguments, words] : cases) {
    Result r = run(arguments);
    EXPECT_NE(r.exitCode, 0) << arguments;
    EXPECT_EQ(lineCount(r.output), 1u) << arguments << ": " << r.output;
    EXPECT_EQ(r.output.rfind("bounce: error:", 0), 0u) << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << arguments << ": " << r.output;
  }
  std::ifstream kept(settings);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), std::istreambuf_iterator<char>()), "{}\n");
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

// Expects `arguments` refused in one line naming `what` and the limit, and
// no image written; exit status 1 for a file's value, 2 for an option's.
void expectRefused(const std::string& arguments, const std::string& what, const fs::path& out, int exitCode) {
  Result r = run(arguments + " --width 32 --height 24 --frames 1 --out " + out.string());
  EXPECT_EQ(r.exitCode, exitCode) << arguments << ": " << r.output;
  EXPECT_EQ(lineCount(r.output), 1u) << arguments << ": " << r.output;
  EXPECT_EQ(r.output.rfind("bounce: error:", 0), 0u) << r.output;
  EXPECT_NE(r.output.find(what), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("above 1e+20"), std::string::npos) << "names the limit: " << r.output;
  EXPECT_FALSE(fs::exists(out / "render.exr")) << arguments;
}

TEST(Cli, AGltfSunBeyondFloatRangeIsRefusedAndOneAtTheLimitRendersFinite) {
  const fs::path dir = freshDirectory("bright_sun");
  expectRefused("render " + writeSunlitFloor(dir, "3e38").string(), "light 0 'Sun': intensity 3e+38", dir / "refused", 1);
  // At the limit the sunlit floor is far brighter than a half float holds:
  // it saturates at the largest finite one.
  EXPECT_EQ(renderFiniteFrame("render " + writeSunlitFloor(dir, "1e20").string(), dir / "limit"), 65504.0f);
  fs::remove_all(dir);
}

TEST(Cli, AnEnvironmentIntensityBeyondFloatRangeIsRefusedAndOneWithinItRendersFinite) {
  const fs::path dir = freshDirectory("bright_environment");
  expectRefused("render cornell --env-intensity 1e38", "--env-intensity 1e+38", dir / "cornell", 2);
  expectRefused("render sun-room --env-intensity 1e38", "--env-intensity 1e+38", dir / "sun-room", 2);
  // The sky is the intensity times the sun's illuminance (10 in sun-room).
  expectRefused("render sun-room --env-intensity 1e20", "times the sun's illuminance 10", dir / "product", 2);
  EXPECT_EQ(renderFiniteFrame("render sun-room --env-intensity 5e18", dir / "within"), 65504.0f);
  fs::remove_all(dir);
}

}  // namespace

// ---------------------------------------------------------------- hardening
// Each test below failed on the code before it: a crash, a shell injection,
// a late failure or a silent acceptance that a hostile but fair user found.

namespace {

// Runs bounce with exactly these arguments (spaces, quotes and all).
bounce::testing::ProcessResult runArgs(std::vector<std::string> arguments, bool separateStderr = false,
                                       const std::vector<std::string>& environment = {}) {
  arguments.insert(arguments.begin(), BOUNCE_BINARY);
  return bounce::testing::runProcess(arguments, environment, 120.0, separateStderr);
}

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(CliHardening, ReferenceFrameOptionIsBoundedAndSamplesOnlyItsFrame) {
  // 4294967295 wrapped frame + 1 to 0 and read past the camera frames;
  // 2147483647 overflowed an int; 30000000 allocated 1.45 GB of poses.
  for (const char* frame : {"4294967295", "2147483647", "30000000", "-1"}) {
    const auto r = runArgs({"reference", "cornell", "--frame", frame});
    EXPECT_EQ(r.exitCode, 2) << frame << ": " << r.output;
    EXPECT_EQ(lineCount(r.output), 1u) << r.output;
    EXPECT_NE(r.output.find("--frame"), std::string::npos) << r.output;
  }
  // The last frame allowed renders at once: only it and the one before are sampled.
  const fs::path dir = freshDirectory("reference_far_frame");
  const auto r = runArgs({"reference", "cornell", "--camera", "orbit", "--frame", "999999", "--width", "8", "--height",
                          "8", "--spp", "1", "--out", (dir / "ref.exr").string()});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "ref.exr"));
  fs::remove_all(dir);
}

TEST(CliHardening, FfmpegGetsTheOutputPathAsOneArgumentNeverThroughAShell) {
  // A stand-in ffmpeg first on PATH records the arguments it was given.
  const fs::path dir = freshDirectory("ffmpeg_injection");
  const fs::path bin = dir / "bin";
  fs::create_directories(bin);
  const fs::path log = dir / "arguments.txt";
  std::ofstream(bin / "ffmpeg") << "#!/bin/sh\nfor a in \"$@\"; do printf '%s\\n' \"$a\"; done > \"" << log.string()
                                << "\"\n";
  fs::permissions(bin / "ffmpeg", fs::perms::owner_all);
  const std::string hostile = "x'; touch INJECTED; echo '";
  const fs::path out = dir / hostile;
  const auto r = runArgs({"render", "cornell", "--width", "16", "--height", "12", "--frames", "2", "--gi-warmup", "0",
                          "--out", out.string()},
                         false, {"PATH=" + bin.string() + ":/usr/bin:/bin"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_FALSE(fs::exists("INJECTED")) << "the output name ran as a command";
  EXPECT_FALSE(fs::exists(dir / "INJECTED"));
  const std::string arguments = readText(log);
  // ffmpeg writes a new file beside render.mp4 (render.mp4.tmp-<random>),
  // which is then renamed into place: a link at the name is never followed.
  EXPECT_NE(arguments.find("\n" + (out / "render.mp4").string() + ".tmp-"), std::string::npos)
      << "the video path is one argument, apostrophes and all:\n"
      << arguments;
  EXPECT_TRUE(fs::is_regular_file(out / "render.mp4")) << "the video was not moved into place";
  EXPECT_NE(arguments.find("\n" + (out / "frames" / "frame%04d.png").string() + "\n"), std::string::npos) << arguments;
  fs::remove_all(dir);
}

TEST(CliHardening, UnwritableOutputIsFoundBeforeAnyRendering) {
  // /proc refuses new files even to root, who ignores permission bits.
  for (const char* out : {"/proc/self/fdinfo", "/proc/bounce-cannot-exist"}) {
    const auto r = runArgs({"render", "cornell", "--frames", "200", "--out", out});
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find(std::string("--out ") + out), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("device:"), std::string::npos) << "checked before the GPU was opened: " << r.output;
  }
  const fs::path file = freshDirectory("out_is_file");
  std::ofstream(file) << "not a folder";
  const auto r = runArgs({"render", "cornell", "--out", file.string()});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("exists and is not a folder"), std::string::npos) << r.output;
  EXPECT_EQ(readText(file), "not a folder") << "nothing the user gave is overwritten";
  fs::remove(file);

  const auto reference = runArgs({"reference", "cornell", "--out", "/proc/self/fdinfo/ref.exr"});
  EXPECT_EQ(reference.exitCode, 1) << reference.output;
  EXPECT_EQ(reference.output.find("device:"), std::string::npos) << reference.output;
}

TEST(CliHardening, NonFiniteNumbersAreRefusedWithAShortRange) {
  for (const std::vector<std::string>& arguments :
       std::vector<std::vector<std::string>>{{"render", "--exposure", "nan"},
                                             {"render", "--fps", "nan"},
                                             {"render", "--env-intensity", "inf"},
                                             {"render", "--sun-elevation", "nan"},
                                             {"render", "--sun-azimuth", "-inf"},
                                             {"render", "--env-rotation", "nan"},
                                             {"render", "--exposure", "-1"},
                                             {"reference", "--target-relmse", "nan"},
                                             {"compare", "a.exr", "b.exr", "--max-flip", "nan"},
                                             {"compare", "a.exr", "b.exr", "--min-psnr", "nan"},
                                             {"brdf-viz", "--roughness", "nan"}}) {
    const auto r = runArgs(arguments);
    EXPECT_EQ(r.exitCode, 2) << arguments[1] << " " << arguments[2] << ": " << r.output;
    EXPECT_EQ(lineCount(r.output), 1u) << r.output;
    EXPECT_LT(r.output.size(), 200u) << "no 309-digit bound: " << r.output;
  }
}

TEST(CliHardening, MistypedCommandsNameTheClosestAndVersionIsTheProjects) {
  const auto r = runArgs({"rendr", "cornell"});
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.output.find("unknown command 'rendr'; did you mean 'render'?"), std::string::npos) << r.output;
  const auto version = runArgs({"--version"});
  EXPECT_EQ(version.exitCode, 0);
  EXPECT_EQ(version.output, std::string("bounce ") + BOUNCE_VERSION_STRING + "\n");
}

TEST(CliHardening, CompareExitsOneForADifferenceAndTwoForTrouble) {
  const fs::path dir = freshDirectory("compare_exit");
  fs::create_directories(dir);
  bounce::io::ImageF a(4, 4, {"R", "G", "B"}), b(4, 4, {"R", "G", "B"});
  for (float& v : a.pixels) v = 0.5f;
  for (float& v : b.pixels) v = 0.9f;
  bounce::io::writeExr(dir / "a.exr", a);
  bounce::io::writeExr(dir / "b.exr", b);
  EXPECT_EQ(runArgs({"compare", (dir / "a.exr").string(), (dir / "a.exr").string(), "--max-relmse", "0"}).exitCode, 0);
  EXPECT_EQ(runArgs({"compare", (dir / "a.exr").string(), (dir / "b.exr").string(), "--max-relmse", "0.01"}).exitCode,
            1)
      << "differs beyond the threshold";
  const auto missing = runArgs({"compare", (dir / "a.exr").string(), (dir / "missing.exr").string()});
  EXPECT_EQ(missing.exitCode, 2) << "a missing file is trouble, not a difference: " << missing.output;
  EXPECT_NE(missing.output.find("missing.exr"), std::string::npos) << missing.output;
  fs::remove_all(dir);
}

// --regions splits the numbers by a label image: a region where the test
// is right has relMSE 0 and ratio 1, one where it is off says by how much;
// a label image of another size is refused naming it.
TEST(CliHardening, CompareReportsEachRegionOfALabelImage) {
  const fs::path dir = freshDirectory("compare_regions");
  fs::create_directories(dir);
  bounce::io::ImageF reference(4, 2, {"R", "G", "B"}), test(4, 2, {"R", "G", "B"}), labels(4, 2, {"Y"});
  for (float& v : reference.pixels) v = 0.5f;
  test = reference;
  for (int x = 0; x < 4; ++x) {
    labels.at(x, 0, 0) = 7.0f;
    labels.at(x, 1, 0) = 65537.0f;
    for (int c = 0; c < 3; ++c) test.at(x, 1, c) = 1.0f;  // the second row twice too bright
  }
  bounce::io::writeExr(dir / "ref.exr", reference);
  bounce::io::writeExr(dir / "test.exr", test);
  bounce::io::writeExr(dir / "ids.exr", labels);
  const auto r = runArgs({"compare", (dir / "ref.exr").string(), (dir / "test.exr").string(), "--regions",
                          (dir / "ids.exr").string(), "--json", (dir / "c.json").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("region     7 4 1 0\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("region     65537 4 2 "), std::string::npos) << r.output;
  const nlohmann::json parsed = nlohmann::json::parse(readText(dir / "c.json"));
  ASSERT_EQ(parsed.at("regions").size(), 2u);
  EXPECT_EQ(parsed.at("regions")[1].at("label"), 65537);
  EXPECT_NEAR(parsed.at("regions")[1].at("relmse").get<double>(), 0.25 / 0.26, 1e-4);

  bounce::io::writeExr(dir / "small.exr", bounce::io::ImageF(2, 2, {"Y"}));
  const auto wrongSize = runArgs({"compare", (dir / "ref.exr").string(), (dir / "test.exr").string(), "--regions",
                                  (dir / "small.exr").string()});
  EXPECT_EQ(wrongSize.exitCode, 2) << wrongSize.output;
  EXPECT_NE(wrongSize.output.find("small.exr: is 2x2"), std::string::npos) << wrongSize.output;
  fs::remove_all(dir);
}

// bounce sheet lays images out in rows of --columns under the first row's
// labels, each shrunk by --shrink, PNG shown as stored and EXR tonemapped;
// images of another size, too many labels and an output over an input are
// refused naming the file.
TEST(CliHardening, SheetLaysImagesOutInLabelledRows) {
  const fs::path dir = freshDirectory("sheet");
  fs::create_directories(dir);
  const std::vector<glm::vec3> colours = {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  std::vector<std::string> arguments = {"sheet"};
  for (std::size_t i = 0; i < colours.size(); ++i) {
    bounce::io::ImageF image(8, 4, {"R", "G", "B"});
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 8; ++x)
        for (int c = 0; c < 3; ++c) image.at(x, y, c) = colours[i][c];
    const fs::path path = dir / ("cell" + std::to_string(i) + ".png");
    bounce::io::writePng(path, image, bounce::io::PngEncoding::Srgb);
    arguments.push_back(path.string());
  }
  bounce::io::ImageF radiance(8, 4, {"R", "G", "B"});
  for (float& v : radiance.pixels) v = 1000.0f;  // tonemapped: near white, not clipped garbage
  bounce::io::writeExr(dir / "bright.exr", radiance);
  arguments.push_back((dir / "bright.exr").string());
  const fs::path out = dir / "sheet.png";
  std::vector<std::string> layout = arguments;
  for (const char* word : {"--columns", "2", "--shrink", "2", "--label", "a", "--label", "b", "--out"})
    layout.push_back(word);
  layout.push_back(out.string());
  const auto r = runArgs(layout);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const bounce::io::ImageF sheet = bounce::io::readImage(out);
  // Two columns of 4x2 cells; each row has a label strip above its cells.
  ASSERT_EQ(sheet.width, 8);
  ASSERT_GT(sheet.height, 4);
  const int rowHeight = sheet.height / 2, strip = rowHeight - 2;
  const auto cellColour = [&](int column, int row) {
    return glm::vec3(sheet.at(column * 4 + 1, row * rowHeight + strip + 1, 0),
                     sheet.at(column * 4 + 1, row * rowHeight + strip + 1, 1),
                     sheet.at(column * 4 + 1, row * rowHeight + strip + 1, 2));
  };
  for (std::size_t i = 0; i < colours.size(); ++i) {
    const glm::vec3 shown = cellColour(int(i) % 2, int(i) / 2);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(shown[c], colours[i][c], 0.01f) << "cell " << i;
  }
  const glm::vec3 bright = cellColour(1, 1);
  EXPECT_GT(bright.y, 0.9f);
  EXPECT_LE(bright.y, 1.0f);

  bounce::io::writePng(dir / "small.png", bounce::io::ImageF(4, 4, {"R", "G", "B"}), bounce::io::PngEncoding::Srgb);
  const auto wrongSize = runArgs({"sheet", arguments[1], (dir / "small.png").string(), "--out", out.string()});
  EXPECT_EQ(wrongSize.exitCode, 1);
  EXPECT_NE(wrongSize.output.find("small.png: 4x4 differs from the size of the first image"), std::string::npos)
      << wrongSize.output;
  const auto overInput = runArgs({"sheet", arguments[1], arguments[2], "--out", arguments[2]});
  EXPECT_EQ(overInput.exitCode, 2);
  EXPECT_NE(overInput.output.find("refusing to write --out over the input"), std::string::npos) << overInput.output;
  EXPECT_NEAR(bounce::io::readImage(arguments[2]).at(0, 0, 1), 1.0f, 1e-3f);  // the input is untouched
  const auto tooManyLabels = runArgs({"sheet", arguments[1], "--label", "a", "--label", "b", "--out", out.string()});
  EXPECT_EQ(tooManyLabels.exitCode, 2);
  EXPECT_NE(tooManyLabels.output.find("2 labels for 1 columns"), std::string::npos) << tooManyLabels.output;
  // A label takes one value: the images after it stay images.
  const auto labelsFirst =
      runArgs({"sheet", "--label", "a", "--label", "b", arguments[1], arguments[2], "--out", out.string()});
  EXPECT_EQ(labelsFirst.exitCode, 0) << labelsFirst.output;
  EXPECT_EQ(bounce::io::readImage(out).width, 16);
  fs::remove_all(dir);
}

// The sheet's font draws letters, digits, space and . , : = ( ) - / + %;
// any other character came out as a box. A label with one is refused as a
// command-line value (exit 2, one line), naming the character and where it
// is, before any image is read.
TEST(CliHardening, SheetRefusesLabelsItsFontCannotDraw) {
  const fs::path dir = freshDirectory("sheet_label");
  for (const char* label : {"caf\xc3\xa9", "a_b", "tab\there", "50\x1b[2J"}) {
    const auto r =
        runArgs({"sheet", (dir / "missing.png").string(), "--label", label, "--out", (dir / "sheet.png").string()});
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_EQ(lineCount(r.output), 1u) << r.output;
    EXPECT_EQ(r.output.rfind("bounce: error: --label: ", 0), 0u) << r.output;
    EXPECT_NE(r.output.find("cannot draw"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find('\x1b'), std::string::npos) << "control bytes are escaped";
  }
  const auto position = runArgs({"sheet", "x.png", "--label", "ok:a_b", "--out", "y.png"});
  EXPECT_NE(position.output.find("('_' at position 5)"), std::string::npos) << position.output;
  // A UTF-8 character is named whole, and counts as one.
  const auto accent = runArgs({"sheet", "x.png", "--label", "caf\xc3\xa9s", "--out", "y.png"});
  EXPECT_NE(accent.output.find("('\xc3\xa9' at position 4)"), std::string::npos) << accent.output;
  // Every character the font draws passes (the missing image is what fails).
  const auto drawable = runArgs({"sheet", (dir / "missing.png").string(), "--label", "Ref. 1,2: a=(b-c)/d+5% z",
                                 "--out", (dir / "sheet.png").string()});
  EXPECT_EQ(drawable.exitCode, 1) << drawable.output;
  EXPECT_NE(drawable.output.find("missing.png"), std::string::npos) << drawable.output;
}

// A sheet is worked out from its images' headers first: a PNG of a few
// hundred bytes declaring 16384 x 16384 pixels (its data ends after a row)
// is refused with the memory it would need, before anything is decoded; it
// used to be decoded and laid out in floats, 6 to 12 GB for a real one.
TEST(CliHardening, SheetsTooLargeToMakeAreRefusedFromTheHeaders) {
  const fs::path dir = freshDirectory("sheet_memory");
  fs::create_directories(dir);
  const std::vector<std::uint8_t> bytes = bounce::testing::zeroPng(16384, 16384, 1);
  std::ofstream(dir / "huge.png", std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  const auto r = runArgs({"sheet", (dir / "huge.png").string(), "--out", (dir / "sheet.png").string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_EQ(lineCount(r.output), 1u) << r.output;
  EXPECT_NE(
      r.output.find("bounce: error: " + (dir / "huge.png").string() + ": a sheet of one 16384x16384 image needs about"),
      std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("more than the limit of 2.0 GiB"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "sheet.png"));
  fs::remove_all(dir);
}

// Every option that names a file of a given format wants that format's
// extension: `sheet --out x.exr` used to write PNG bytes into x.exr. A
// wrong name is a command-line error (exit 2), found before any work.
TEST(CliHardening, OutputFilesMustBeNamedForTheFormatWritten) {
  const fs::path dir = freshDirectory("output_names");
  fs::create_directories(dir);
  const std::string image = (fs::path(BOUNCE_SOURCE_DIR) / "tests" / "data" / "flip" / "b_checker_ref.png").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"sheet", image, "--out", (dir / "x.exr").string()}, "must name a .png file"},
      {{"compare", image, image, "--error-map", (dir / "map.exr").string()}, "must name a .png file"},
      {{"compare", image, image, "--json", (dir / "values.png").string()}, "must name a .json file"},
      {{"compare", "--sequence", image, image, "--json", (dir / "values").string()}, "must name a .json file"},
      {{"reference", "cornell", "--out", (dir / "ref.png").string()}, "must name an .exr file"},
      {{"bench", "cornell", "--json", (dir / "bench.txt").string()}, "must name a .json file"},
  };
  for (const auto& [arguments, message] : cases) {
    const auto r = runArgs(arguments);
    EXPECT_EQ(r.exitCode, 2) << arguments[0] << ": " << r.output;
    EXPECT_EQ(lineCount(r.output), 1u) << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(dir.string()), std::string::npos) << "names the file: " << r.output;
  }
  EXPECT_TRUE(fs::is_empty(dir)) << "nothing written";
  // Any case of the extension will do.
  const auto upper = runArgs({"sheet", image, "--out", (dir / "x.PNG").string()});
  EXPECT_EQ(upper.exitCode, 0) << upper.output;
  EXPECT_EQ(bounce::io::readImage(dir / "x.PNG").width, 128);
  fs::remove_all(dir);
}

// --material changes a material's factor; a misspelt material, key or value
// is refused naming it (and, for a material, listing the scene's), before
// anything renders.
TEST(CliHardening, MaterialChangesAreAppliedOrRefusedByName) {
  const fs::path out = freshDirectory("material_change");
  const std::vector<std::string> common = {"render", "cornell", "--width", "8", "--height", "8", "--gi", "off",
                                           "--out", out.string(), "--aov", "metallic", "--material"};
  auto run = [&](const std::string& change) {
    std::vector<std::string> arguments = common;
    arguments.push_back(change);
    return runArgs(arguments);
  };
  const auto unknown = run("marble:roughness=0.2");
  EXPECT_NE(unknown.exitCode, 0);
  EXPECT_NE(unknown.output.find("no material 'marble' (it has '"), std::string::npos) << unknown.output;
  const auto badKey = run("cornell white:shininess=3");
  EXPECT_NE(badKey.exitCode, 0);
  EXPECT_NE(badKey.output.find("unknown key 'shininess'"), std::string::npos) << badKey.output;
  const auto badValue = run("cornell white:base_color=1,0.5");
  EXPECT_NE(badValue.exitCode, 0);
  EXPECT_NE(badValue.output.find("wants 3 numbers, got 2"), std::string::npos) << badValue.output;
  const auto outside = run("cornell white:metallic=1.5");
  EXPECT_NE(outside.exitCode, 0);
  EXPECT_NE(outside.output.find("1.5 is outside [0, 1]"), std::string::npos) << outside.output;
  EXPECT_FALSE(fs::exists(out / "frames")) << "refused before rendering";

  // cornell's walls are white dielectrics: made metal, the metallic AOV shows it.
  const auto metal = run("cornell white:metallic=1");
  ASSERT_EQ(metal.exitCode, 0) << metal.output;
  const bounce::io::ImageF metallic = bounce::io::readImage(out / "aov" / "metallic.exr");
  EXPECT_EQ(*std::max_element(metallic.pixels.begin(), metallic.pixels.end()), 1.0f);
  fs::remove_all(out);
}

TEST(CliHardening, BenchJsonIsValidJsonInAFileOrOnStdoutAndBenchValidatesClean) {
  const fs::path dir = freshDirectory("bench_json");
  fs::create_directories(dir);
  // A default bench copies 256 MiB buffers, twice what lavapipe binds at once.
  const auto toFile = runArgs({"bench", "cornell", "--validate", "--width", "16", "--height", "16", "--frames", "2",
                               "--warmup", "0", "--rays", "64", "--json", (dir / "bench.json").string()});
  ASSERT_EQ(toFile.exitCode, 0) << toFile.output;
  EXPECT_EQ(toFile.output.find("validation message"), std::string::npos) << toFile.output;
  const nlohmann::json parsed = nlohmann::json::parse(readText(dir / "bench.json"));
  EXPECT_EQ(parsed.at("scene"), "cornell");
  EXPECT_GT(parsed.at("passes").size(), 2u);
  // The composite reads and writes images of the render size: its traffic
  // floor is at least its output's bytes (rgba16f, 16x16).
  bool composite = false;
  for (const nlohmann::json& pass : parsed.at("passes"))
    if (pass.at("name") == "gi.composite") {
      composite = true;
      EXPECT_GE(pass.at("image_bytes").get<std::uint64_t>(), 16u * 16u * 8u) << pass;
    }
  EXPECT_TRUE(composite) << "no gi.composite in the JSON";

  const auto toStdout = runArgs({"bench", "cornell", "--width", "16", "--height", "16", "--frames", "2", "--warmup",
                                 "0", "--rays", "0", "--copy-mb", "1", "--json", "-"},
                                /*separateStderr=*/true);
  ASSERT_EQ(toStdout.exitCode, 0) << toStdout.errors;
  EXPECT_FALSE(fs::exists("-")) << "'-' means stdout, not a file named '-'";
  EXPECT_EQ(nlohmann::json::parse(toStdout.output).at("width"), 16) << "stdout is the JSON alone: " << toStdout.output;
  EXPECT_NE(toStdout.errors.find("GPU time per pass"), std::string::npos) << "the table goes to stderr";
  fs::remove_all(dir);
}

TEST(CliHardening, ARenderRemovesTheFramesOfAnEarlierLongerRender) {
  const fs::path out = freshDirectory("frames_mix");
  const std::vector<std::string> common = {"render", "cornell",     "--width", "8",     "--height",
                                           "8",      "--gi-warmup", "0",       "--out", out.string()};
  auto longer = common;
  longer.insert(longer.end(), {"--frames", "4"});
  ASSERT_EQ(runArgs(longer).exitCode, 0);
  std::ofstream(out / "frames" / "notes.txt") << "mine";
  auto shorter = common;
  shorter.insert(shorter.end(), {"--frames", "2"});
  const auto r = runArgs(shorter);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("removed"), std::string::npos) << "says what it removed: " << r.output;
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(out / "frames")) left.push_back(entry.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"frame0000.png", "frame0001.png", "notes.txt"}))
      << "only this render's frames, and what the user put there";
  fs::remove_all(out);
}

std::string fileText(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A one-triangle glTF in `dir` whose buffer file is `dir/bufferName`.
void writeTriangleGltf(const fs::path& dir, const std::string& bufferName) {
  fs::create_directories(dir);
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::ofstream(dir / bufferName, std::ios::binary).write(reinterpret_cast<const char*>(positions), sizeof positions);
  std::ofstream(dir / "scene.gltf") << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "buffers": [{"uri": ")" << bufferName << R"(", "byteLength": 36}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 0]}]})";
}

TEST(CliHardening, NoOutputReplacesAnInputOrAFileAnInputRefersTo) {
  const fs::path dir = freshDirectory("outputs_over_inputs");
  const std::vector<std::string> tiny = {"--width", "16", "--height", "8", "--gi", "off"};
  const auto refused = [&](std::vector<std::string> arguments, const fs::path& input) {
    const std::string before = fileText(input);
    arguments.insert(arguments.end(), tiny.begin(), tiny.end());
    const auto r = runArgs(arguments);
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("bounce: error:"), std::string::npos) << r.output;
    EXPECT_EQ(fileText(input), before) << input << " was changed";
  };
  // The scene's own buffer is named as the render's output would be.
  writeTriangleGltf(dir / "scene", "render.png");
  refused({"render", (dir / "scene" / "scene.gltf").string(), "--out", (dir / "scene").string()},
          dir / "scene" / "render.png");
  refused({"bench", (dir / "scene" / "scene.gltf").string(), "--frames", "1", "--warmup", "0", "--json",
           (dir / "scene" / "scene.gltf").string()},
          dir / "scene" / "scene.gltf");
  // A derived output: OUT.json beside OUT.exr is the camera file.
  fs::create_directories(dir / "cam");
  std::ofstream(dir / "cam" / "shot.json") << R"({"keyframes": [{"time": 0, "position": [0, 1, 3], "target": [0, 1, 0]}]})";
  refused({"reference", "cornell", "--spp", "1", "--camera", (dir / "cam" / "shot.json").string(), "--out",
           (dir / "cam" / "shot.exr").string()},
          dir / "cam" / "shot.json");
  // An environment map that is a render's output, its derived part, or a
  // link to it.
  ASSERT_EQ(runArgs({"render", "cornell", "--width", "16", "--height", "8", "--gi", "off", "--hdr", "--frames", "3",
                     "--out", (dir / "earlier").string()})
                .exitCode,
            0);
  const fs::path map = dir / "earlier" / "render.exr";
  refused({"render", "cornell", "--env", map.string(), "--out", (dir / "earlier").string()}, map);
  fs::copy_file(map, dir / "r.direct.exr");
  refused({"reference", "cornell", "--spp", "1", "--env", (dir / "r.direct.exr").string(), "--out",
           (dir / "r.exr").string()},
          dir / "r.direct.exr");
  fs::create_symlink(map, dir / "link.exr");
  refused({"reference", "cornell", "--spp", "1", "--env", map.string(), "--out", (dir / "link.exr").string()}, map);
  // An input the next render would remove (an earlier render's frame it
  // does not write again), or in a folder it fills.
  const fs::path frame = dir / "earlier" / "frames" / "frame0002.exr";
  refused({"render", "cornell", "--env", frame.string(), "--out", (dir / "earlier").string()}, frame);
  fs::create_directories(dir / "out" / "stages");
  fs::copy_file(map, dir / "out" / "stages" / "sky.exr");
  refused({"render", "cornell", "--dump-stages", "--env", (dir / "out" / "stages" / "sky.exr").string(), "--out",
           (dir / "out").string()},
          dir / "out" / "stages" / "sky.exr");
  fs::remove_all(dir);
}

TEST(CliHardening, ARunReplacesOrRemovesOnlyWhatAnEarlierBounceRunWrote) {
  const fs::path dir = freshDirectory("foreign_outputs");
  const fs::path out = dir / "out";
  fs::create_directories(out / "stages");
  std::ofstream(out / "render.png") << "the user's picture";
  std::ofstream(out / "render.mp4") << "the user's film";
  std::ofstream(dir / "victim.txt") << "outside the folder";
  std::ofstream(out / ".bounce-written") << "../victim.txt\n/etc/hostname\n";
  const std::vector<std::string> render = {"render", "cornell", "--width", "16", "--height", "8", "--gi", "off",
                                           "--out",  out.string()};
  const auto with = [&](std::initializer_list<std::string> extra) {
    std::vector<std::string> arguments = render;
    arguments.insert(arguments.end(), extra);
    return runArgs(arguments);
  };
  // render.png is the user's: refused before any work, nothing touched.
  const auto refused = with({});
  EXPECT_EQ(refused.exitCode, 2) << refused.output;
  EXPECT_NE(refused.output.find("render.png exists and no Bounce run wrote it"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("--overwrite"), std::string::npos) << refused.output;
  EXPECT_EQ(fileText(out / "render.png"), "the user's picture");
  // --overwrite replaces it; a one-frame render leaves the user's film, which it does not write, alone.
  ASSERT_EQ(with({"--overwrite"}).exitCode, 0);
  EXPECT_NE(fileText(out / "render.png"), "the user's picture");
  EXPECT_EQ(fileText(out / "render.mp4"), "the user's film");
  EXPECT_EQ(fileText(dir / "victim.txt"), "outside the folder") << "a record naming files elsewhere is ignored";
  // A second render replaces the first's files without --overwrite, but a
  // two-frame one would write the user's film.
  EXPECT_EQ(with({}).exitCode, 0);
  const auto film = with({"--frames", "2"});
  EXPECT_EQ(film.exitCode, 2) << film.output;
  EXPECT_NE(film.output.find("render.mp4 exists"), std::string::npos) << film.output;
  EXPECT_EQ(fileText(out / "render.mp4"), "the user's film");
  // A folder the render fills with files named by the work must hold only Bounce's.
  std::ofstream(out / "stages" / "notes.txt") << "the user's notes";
  const auto stages = with({"--dump-stages"});
  EXPECT_EQ(stages.exitCode, 2) << stages.output;
  EXPECT_NE(stages.output.find("notes.txt exists"), std::string::npos) << stages.output;
  fs::remove(out / "stages" / "notes.txt");
  ASSERT_EQ(with({"--dump-stages"}).exitCode, 0);
  EXPECT_FALSE(fs::is_empty(out / "stages"));
  // The next render without stages removes the earlier one's, and says so.
  const auto plain = with({});
  EXPECT_EQ(plain.exitCode, 0) << plain.output;
  EXPECT_NE(plain.output.find("an earlier render wrote"), std::string::npos) << plain.output;
  EXPECT_FALSE(fs::exists(out / "stages"));
  fs::remove_all(dir);
}

TEST(CliHardening, GiSettingsIgnoredByGiOffAreWarnedAbout) {
  const fs::path out = freshDirectory("gi_off_warn");
  const auto r = runArgs({"render", "cornell", "--width", "8", "--height", "8", "--gi", "off", "--gi.seed", "3",
                          "--gi.diffuse.spatial_radius", "4", "--out", out.string()});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  const std::size_t warning = r.output.find("warning: --gi off: ignoring ");
  ASSERT_NE(warning, std::string::npos) << r.output;
  const std::string line = r.output.substr(warning, r.output.find('\n', warning) - warning);
  EXPECT_NE(line.find("--gi.seed"), std::string::npos) << line;
  EXPECT_NE(line.find("--gi.diffuse.spatial_radius"), std::string::npos) << line;
  fs::remove_all(out);
}

// --gi names the branches that run: one left out writes black, an unknown
// name is refused before anything renders.
TEST(CliHardening, GiNamesTheBranchesThatRun) {
  const fs::path out = freshDirectory("gi_branches");
  const auto bad = runArgs({"render", "cornell", "--width", "8", "--height", "8", "--gi", "diffuse,mirror", "--out",
                            out.string()});
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(bad.output.find("'mirror' is not a GI branch"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(out / "render.png"));
  const auto specular = runArgs({"render", "cornell", "--width", "16", "--height", "12", "--gi", "specular", "--gi-warmup",
                                 "2", "--aov", "indirect-diffuse,indirect-specular", "--out", out.string()});
  ASSERT_EQ(specular.exitCode, 0) << specular.output;
  const bounce::io::ImageF diffuse = bounce::io::readImage(out / "aov" / "indirect-diffuse.exr");
  float largest = 0.0f;
  for (float v : diffuse.pixels) largest = std::max(largest, std::abs(v));
  EXPECT_EQ(largest, 0.0f) << "--gi specular leaves the diffuse branch off";
  fs::remove_all(out);
}

TEST(CliHardening, SettingsFilesTooDeepOrWithARepeatedKeyAreRefusedBeforeRendering) {
  const fs::path dir = freshDirectory("settings_depth");
  fs::create_directories(dir);
  std::string deep;
  for (int i = 0; i < 30000; ++i) deep += "{\"a\":";
  deep += "1" + std::string(30000, '}');
  std::ofstream(dir / "deep.json") << deep;
  std::ofstream(dir / "twice.json") << R"({"diffuse": {"spatial_radius": 4, "spatial_radius": 5}})";
  for (const auto& [file, says] : {std::pair{"deep.json", "JSON nested deeper than 64 levels"},
                                   std::pair{"twice.json", "gi.diffuse.spatial_radius is given more than once"}}) {
    const auto r = runArgs({"render", "cornell", "--gi-settings", (dir / file).string(), "--out", dir.string()});
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_EQ(r.signal, 0) << "crashed: " << r.output;
    EXPECT_NE(r.output.find(says), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("device:"), std::string::npos) << "refused before the GPU was opened: " << r.output;
  }
  fs::remove_all(dir);
}

TEST(CliHardening, AFrameLargerThanTheDeviceHeapIsRefusedUpFront) {
  // Every command that makes a frame estimates its images (the renderer's,
  // the GI library's, the path tracer's) before making any: lavapipe's heap
  // is 2 GiB, so nothing of these may be allocated (they were, up to 15 GB).
  const fs::path dir = freshDirectory("huge");
  fs::create_directories(dir);
  std::ofstream(dir / "s.txt") << "wait 1\n";
  const std::vector<std::pair<std::vector<std::string>, std::string>> commands = {
      {{"render", "cornell", "--out", (dir / "render").string()}, "frame with GI needs at least"},
      {{"render", "cornell", "--gi", "off", "--out", (dir / "render").string()}, "frame needs at least 12.0 GiB"},
      {{"reference", "cornell", "--out", (dir / "r.exr").string()}, "frame and path tracing needs at least"},
      {{"view", "cornell", "--headless", "--script", (dir / "s.txt").string(), "--out", (dir / "view").string()},
       "frame with GI needs at least"},
      {{"bench", "cornell", "--frames", "1", "--warmup", "0"}, "frame with GI needs at least"},
      {{"denoise", "cornell", "--out", (dir / "denoise").string()}, "with GI and path tracing needs at least"},
  };
  for (auto [arguments, mentions] : commands) {
    arguments.insert(arguments.end(), {"--width", "16384", "--height", "16384"});
    const auto r = runArgs(arguments);
    EXPECT_EQ(r.exitCode, 1) << arguments[0] << ": " << r.output;
    EXPECT_NE(r.output.find(mentions), std::string::npos) << arguments[0] << ": " << r.output;
    EXPECT_NE(r.output.find("has 2.0 GiB"), std::string::npos) << r.output;
  }
  fs::remove_all(dir);
}

}  // namespace

// ---------------------------------------------------------------------------
// Scene input a hostile-but-fair user hands over (issue 10): where glTF files
// may read from, scenes with nothing in them, cameras chosen by name.
namespace {

void writeFile(const fs::path& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

// A glTF of one triangle (in z = 0, facing +Z) whose buffer is at
// `bufferUri`, held by the node `node` (JSON).
std::string triangleGltf(const std::string& bufferUri, const std::string& node = R"({"mesh": 0})") {
  return R"({"asset": {"version": "2.0"},
    "buffers": [{"uri": ")" +
         bufferUri + R"(", "byteLength": 36}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
    "nodes": [)" +
         node + "]}";
}

// The triangle's 36 bytes of positions, `scale` metres wide.
std::string trianglePositions(float scale = 1.0f) {
  const float positions[9] = {-scale, 0, 0, scale, 0, 0, 0, scale, 0};
  return std::string(reinterpret_cast<const char*>(positions), sizeof positions);
}

TEST(CliSceneInput, BuffersOutsideTheGltfFolderNeedAllowOutsideAssets) {
  const fs::path dir = freshDirectory("outside_assets");
  fs::create_directories(dir / "scene");
  writeFile(dir / "triangle.bin", trianglePositions());
  const fs::path gltf = dir / "scene" / "triangle.gltf";
  writeFile(gltf, triangleGltf("../triangle.bin"));
  const std::vector<std::string> commands = {
      "render " + gltf.string() + " --width 16 --height 12 --gi off --out " + (dir / "out").string(),
      "reference " + gltf.string() + " --width 8 --height 6 --spp 1 --out " + (dir / "ref.exr").string(),
      "bench " + gltf.string() + " --width 16 --height 12 --frames 1 --warmup 0 --copy-mb 0 --rays 0 --gi off"};
  for (const std::string& command : commands) {
    const Result refused = run(command);
    EXPECT_EQ(refused.exitCode, 1) << command << ": " << refused.output;
    EXPECT_EQ(lineCount(refused.output), 1u) << command << ": " << refused.output;
    EXPECT_NE(refused.output.find(gltf.string() + ": the buffer or image file '../triangle.bin' lies outside the "
                                                  "glTF file's folder"),
              std::string::npos)
        << command << ": " << refused.output;
    const Result allowed = run(command + " --allow-outside-assets");
    EXPECT_EQ(allowed.exitCode, 0) << command << ": " << allowed.output;
  }
  fs::remove_all(dir);
}

// Scenes too large for 32-bit floats get a one-line error naming what failed
// and its values, not the same message for every cause.
TEST(CliSceneInput, ScenesTooLargeForFloatsSayWhatFailed) {
  const fs::path dir = freshDirectory("huge_scenes");
  fs::create_directories(dir);
  writeFile(dir / "unit.bin", trianglePositions());
  writeFile(dir / "huge.bin", trianglePositions(1e30f));
  writeFile(dir / "huge_positions.gltf", triangleGltf("huge.bin"));
  writeFile(dir / "huge_scale.gltf", triangleGltf("unit.bin", R"({"mesh": 0, "scale": [1e19, 1e19, 1e19]})"));
  writeFile(dir / "half_turn_lens.gltf",
            R"({"asset": {"version": "2.0"}, "nodes": [{"camera": 0}],
                "cameras": [{"type": "perspective", "perspective": {"yfov": 3.14159265, "znear": 0.1}}]})");
  const std::pair<const char*, const char*> cases[] = {
      // The camera framing the scene is checked with every frame's before rendering.
      {"huge_positions.gltf",
       "huge_positions.gltf's camera: frame 0 (at 0 s): camera: position (0, 1.56165e+30, 3.0333e+30) is more than "
       "1e+18 from the origin along an axis"},
      {"huge_scale.gltf",
       "huge_scale.gltf's camera: frame 0 (at 0 s): camera: position (0, 1.56165e+19, 3.0333e+19) is more than 1e+18"},
      {"half_turn_lens.gltf", "camera 0: yfov 3.14159265 must be between 0 and pi (exclusive, as a 32-bit float)"}};
  for (const auto& [file, message] : cases) {
    const Result r =
        run("render " + (dir / file).string() + " --width 16 --height 12 --gi off --out " + (dir / "out").string());
    EXPECT_EQ(r.exitCode, 1) << file << ": " << r.output;
    const std::size_t error = r.output.find("bounce: error:");
    ASSERT_NE(error, std::string::npos) << file << ": " << r.output;
    EXPECT_EQ(lineCount(r.output.substr(error)), 1u) << file << ": " << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << file << ": " << r.output;
  }
  fs::remove_all(dir);
}

// --camera gltf:N and gltf:NAME choose among a file's cameras; one that does
// not exist is a one-line error listing those that do.
TEST(CliSceneInput, GltfCamerasAreChosenByNumberOrName) {
  const fs::path dir = freshDirectory("gltf_cameras");
  fs::create_directories(dir);
  const fs::path gltf = dir / "cameras.gltf";
  writeFile(gltf, R"({"asset": {"version": "2.0"},
      "cameras": [{"type": "perspective", "name": "wide", "perspective": {"yfov": 1.2, "znear": 0.1}},
                  {"type": "perspective", "name": "tele", "perspective": {"yfov": 0.3, "znear": 0.1}}],
      "nodes": [{"camera": 0, "name": "left"}, {"camera": 1, "translation": [0, 1, 0]}]})");
  const std::string render = "render " + gltf.string() + " --width 16 --height 12 --gi off --out ";
  for (const char* camera : {"gltf:1", "gltf:tele", "gltf:left"}) {
    const Result r = run(render + (dir / "out").string() + " --camera " + camera);
    EXPECT_EQ(r.exitCode, 0) << camera << ": " << r.output;
  }
  const Result missing = run(render + (dir / "out").string() + " --camera gltf:2");
  EXPECT_EQ(missing.exitCode, 1) << missing.output;
  EXPECT_EQ(missing.output,
            "bounce: error: scene 'cameras.gltf' has no glTF camera number 2 (camera path 'gltf:2'); "
            "its cameras, by number and name: 0 'wide' (node 'left'), 1 'tele'\n");
  fs::remove_all(dir);
}

// A valid glTF with nothing to draw renders the sky, in every command.
TEST(CliSceneInput, AGltfWithNothingInItRendersTheSky) {
  const fs::path dir = freshDirectory("empty_gltf");
  fs::create_directories(dir);
  const fs::path gltf = dir / "empty.gltf";
  writeFile(gltf, R"({"asset": {"version": "2.0"}})");
  const Result render = run("render " + gltf.string() + " --width 32 --height 24 --out " + (dir / "out").string());
  ASSERT_EQ(render.exitCode, 0) << render.output;
  // readImage refuses NaN and infinity.
  const bounce::io::ImageF image = bounce::io::readImage(dir / "out" / "render.exr");
  EXPECT_EQ(image.width, 32);
  double sum = 0.0;
  for (float value : image.pixels) sum += value;
  EXPECT_GT(sum, 0.0) << "the sky is lit";

  for (const std::string& command :
       {"reference " + gltf.string() + " --width 8 --height 6 --spp 2 --out " + (dir / "ref.exr").string(),
        "bench " + gltf.string() + " --validate --width 16 --height 12 --frames 1 --warmup 0 --copy-mb 0 --rays 64"}) {
    const Result r = run(command);
    EXPECT_EQ(r.exitCode, 0) << command << ": " << r.output;
  }
  fs::remove_all(dir);
}

}  // namespace
