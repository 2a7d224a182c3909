// The corpus's viewer-script, compare and settings cases (issue 46).
#include <algorithm>
#include <string>
#include <vector>

#include "bad_input_corpus_builder.h"
#include "io/image_io.h"

namespace bounce::testing {

namespace {

namespace fs = std::filesystem;
using corpus_files::writeText;

// bounce view, headless, on the script {dir}/s.txt.
std::vector<std::string> view(bool gi) {
  std::vector<std::string> arguments = {"view",     "cornell",          "--headless", "--width", "16", "--height",
                                        "12",       "--script",         "{dir}/s.txt", "--out",   "{out}"};
  if (!gi) arguments.insert(arguments.end(), {"--gi", "off"});
  return arguments;
}

// An 8x8 RGB EXR of one value everywhere.
void writeFlatExr(const fs::path& path, float value) {
  io::ImageF image(8, 8, {"R", "G", "B"});
  std::fill(image.pixels.begin(), image.pixels.end(), value);
  io::writeExr(path, image);
}

// "" when `path` is an image of finite values, some of them lit; else what is wrong.
std::string litImage(const fs::path& path) {
  try {
    const io::ImageF image = io::readImage(path);
    for (const float value : image.pixels)
      if (value > 0.0f) return "";
    return path.string() + " is all black";
  } catch (const std::exception& error) {
    return error.what();
  }
}

}  // namespace

void scriptAndCompareCases(CorpusBuilder& corpus) {
  // S4, U3: a command that reads the frame as the script's first line used
  // to read a frame that did not exist yet (a screenshot: "gi: composite():
  // no frame has been recorded yet"); it now waits for the first frame.
  for (const bool gi : {false, true}) {
    corpus
        .add(
            std::string("script_screenshot_first_line") + (gi ? "_gi_on" : ""), "s.txt",
            [](const fs::path& dir) { writeText(dir / "s.txt", "screenshot x\n"); }, view(gi), "",
            Outcome::Completes)
        .check = [](const fs::path& dir) {
      const std::string exr = litImage(dir / "out" / "x.exr");
      return exr.empty() ? litImage(dir / "out" / "x.png") : exr;
    };
  }
  corpus
      .add(
          "script_click_then_edit_first_lines", "s.txt",
          [](const fs::path& dir) {
            writeText(dir / "s.txt", "click 8 6\nmaterial roughness 0.5\nscreenshot x\ninspect 8 6\n");
          },
          view(false), "", Outcome::Completes)
      .check = [](const fs::path& dir) { return litImage(dir / "out" / "x.exr"); };

  // U2: a camera far enough from the origin that the viewer's 32-bit floats
  // lose its direction gave "target (-nan, -nan, -nan) is not finite"
  // without the script's line.
  corpus.textFile("script_camera_1e9_from_the_origin", "s.txt", "wait 1\ncamera 0 0 1e9 0 0 0\n", view(false),
                  "s.txt:2: the camera at (0, 0, 1e+09) is too far from the origin");
  corpus.textFile("script_pose_1e8_from_the_origin_gi_on", "s.txt", "pose 1e8 0 0 0 0 0\nwait 1\n", view(true),
                  "s.txt:1: the camera at (1e+08, 0, 0) is too far from the origin");
  corpus.textFile("script_camera_1e6_turns_the_view", "s.txt", "camera 1e6 0 0 0 1e6 0\n", view(false),
                  "would turn the view by");

  // U4: a NUL in a line cut the message at it ("unknown command 'screen").
  corpus.textFile("script_nul_in_a_command", "s.txt", std::string("wait 1\nscreen\0shot x\n", 21), view(false),
                  "s.txt:2: a NUL byte at column 7 of 'screen\\x00shot x'");
  corpus.textFile("script_nul_in_a_file_name", "s.txt", std::string("other-settings a\0b.json\n", 24), view(false),
                  "'other-settings a\\x00b.json'");

  // S7: a test image of negative values was compared without a word
  // (HDR-FLIP 0.29); radiance is never negative.
  corpus.add(
      "compare_test_image_negative", "test.exr",
      [](const fs::path& dir) {
        writeFlatExr(dir / "ref.exr", 0.5f);
        writeFlatExr(dir / "test.exr", -1.0f);
      },
      {"compare", "{dir}/ref.exr", "{dir}/test.exr"}, "holds a negative R value (-1) at pixel (0, 0)");
  corpus.add(
      "compare_reference_one_negative_texel", "ref.exr",
      [](const fs::path& dir) {
        io::ImageF image(8, 8, {"R", "G", "B", "A"});
        std::fill(image.pixels.begin(), image.pixels.end(), 0.25f);
        image.at(5, 3, 2) = -0.125f;
        io::writeExr(dir / "ref.exr", image);
        writeFlatExr(dir / "test.exr", 0.25f);
      },
      {"compare", "{dir}/ref.exr", "{dir}/test.exr", "--flip", "ldr"}, "negative B value (-0.125) at pixel (5, 3)");

  // U10: black against black failed with HDR-FLIP's "no positive luminance"
  // and no word of --flip ldr, which compares them (FLIP 0).
  corpus.add(
      "compare_black_against_black", "black.exr", [](const fs::path& dir) { writeFlatExr(dir / "black.exr", 0.0f); },
      {"compare", "{dir}/black.exr", "{dir}/black.exr"}, "compare with --flip ldr");
  corpus.add(
      "compare_black_against_black_ldr", "black.exr",
      [](const fs::path& dir) { writeFlatExr(dir / "black.exr", 0.0f); },
      {"compare", "{dir}/black.exr", "{dir}/black.exr", "--flip", "ldr", "--max-flip", "0"}, "", Outcome::Completes);

  // U5: every initial candidate 0 with the (default) tracing bridge was
  // refused by the library after the scene had loaded. Checked first now:
  // the scene named here does not exist, and the settings are what is said.
  const std::vector<std::string> noCandidates = {
      "--gi.diffuse.screen_candidates", "0", "--gi.diffuse.bright_candidates", "0", "--gi.diffuse.ray_candidates", "0"};
  std::vector<std::string> flags = {"render", "{dir}/missing.gltf", "--out", "{out}"};
  flags.insert(flags.end(), noCandidates.begin(), noCandidates.end());
  corpus.add(
      "gi_no_candidate_with_the_bridge_flags", "", [](const fs::path&) {}, flags,
      "gi.diffuse.ray_candidates is 0 while gi.diffuse.enabled is on with a scene bridge that traces");
  corpus.textFile(
      "gi_no_candidate_with_the_bridge_settings_file", "settings.json",
      R"({"diffuse": {"screen_candidates": 0, "bright_candidates": 0, "ray_candidates": 0}})",
      {"render", "{dir}/missing.gltf", "--gi-settings", "{dir}/settings.json", "--out", "{out}"},
      "settings.json: gi.diffuse.screen_candidates and gi.diffuse.bright_candidates are 0");
  corpus.add(
      "gi_no_candidate_with_the_bridge_budget_view", "settings.json",
      [](const fs::path& dir) {
        writeText(dir / "settings.json",
                  R"({"diffuse": {"screen_candidates": 0, "bright_candidates": 0}, "world_ray_budget": 0.5})");
        writeText(dir / "s.txt", "wait 1\n");
      },
      {"view", "{dir}/missing.gltf", "--gi-settings", "{dir}/settings.json", "--headless", "--script", "{dir}/s.txt",
       "--out", "{out}"},
      "gi.world_ray_budget 0.5 leaves no ray for gi.diffuse.ray_candidates");
}

}  // namespace bounce::testing
