// bounce view in a window, as a user runs it, under Xvfb (an X server
// without a screen) with lavapipe: a script changes a setting, picks and
// edits a material and takes screenshots; the screenshots must match what
// bounce render makes offline from the same camera, settings and material,
// with zero validation messages.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "io/image_io.h"
#include "process.h"
#include "viewer/brdf_plot.h"

namespace {

namespace fs = std::filesystem;

constexpr const char* kXvfbRun = "/usr/bin/xvfb-run";

// An empty folder of this test's own under the temporary directory.
fs::path freshDirectory(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("bounce_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

bounce::testing::ProcessResult bounce(std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), BOUNCE_BINARY);
  return bounce::testing::runProcess(arguments);
}

// The window needs an X server: a private Xvfb for this run (-a picks a
// free display number, so tests running side by side do not meet).
bounce::testing::ProcessResult bounceInWindow(std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), {kXvfbRun, "-a", "-s", "-screen 0 320x240x24", BOUNCE_BINARY});
  return bounce::testing::runProcess(arguments);
}

double flip(const fs::path& a, const fs::path& b) {
  const bounce::testing::ProcessResult r = bounce({"compare", a.string(), b.string()});
  const std::size_t at = r.output.find("FLIP");
  EXPECT_NE(at, std::string::npos) << r.output;
  if (at == std::string::npos) return 1.0;
  // "FLIP  mean <value> ..." as bounce compare prints it.
  std::istringstream line(r.output.substr(at));
  std::string key, kind;
  double value = 1.0;
  line >> key >> kind >> value;
  return value;
}

double meanRedShare(const fs::path& exr) {
  const bounce::io::ImageF image = bounce::io::readImage(exr);
  double red = 0.0, all = 0.0;
  const std::size_t channels = image.channelCount();
  for (std::size_t i = 0; i < image.pixels.size(); i += channels) {
    red += image.pixels[i];
    all += image.pixels[i] + image.pixels[i + 1] + image.pixels[i + 2];
  }
  return red / all;
}

TEST(Viewer, AScriptedSessionMatchesOfflineRendersOfTheSameSettingsAndMaterial) {
  ASSERT_TRUE(fs::exists(kXvfbRun)) << "xvfb-run is missing: scripts/install-deps.sh installs xvfb";
  const fs::path dir = freshDirectory("viewer");
  const fs::path script = dir / "session.txt";
  std::ofstream(script) << "# cornell: six frames, then a red back wall and a smaller spatial radius\n"
                           "wait 6\n"
                           "screenshot before\n"
                           "click 32 12      # the back wall\n"
                           "material base_color 0.9 0.2 0.2\n"
                           "set diffuse.spatial_radius 12   # restarts the GI: the next frames are a fresh run\n"
                           "wait 24\n"
                           "screenshot after\n"
                           "window panels   # the README's picture of the viewer\n";
  const std::vector<std::string> size = {"--width", "64", "--height", "48"};
  std::vector<std::string> view = {
      "view", "cornell", "--script", script.string(), "--out", (dir / "view").string(), "--validate"};
  view.insert(view.end(), size.begin(), size.end());
  const bounce::testing::ProcessResult session = bounceInWindow(view);
  ASSERT_EQ(session.exitCode, 0) << session.output;
  EXPECT_EQ(session.output.find("vulkan validation"), std::string::npos) << session.output;
  EXPECT_NE(session.output.find("picked material 0 (cornell white)"), std::string::npos) << session.output;

  // The same frames offline, from a cut at the scene's camera.
  const auto offline = [&](const std::string& name, const std::string& frames, std::vector<std::string> flags) {
    std::vector<std::string> render = {"render",      "cornell", "--frames", frames,
                                       "--gi-warmup", "0",       "--out",    (dir / name).string()};
    render.insert(render.end(), size.begin(), size.end());
    render.insert(render.end(), flags.begin(), flags.end());
    const bounce::testing::ProcessResult r = bounce(render);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return dir / name / "render.exr";
  };
  const std::vector<std::string> edited = {"--material", "cornell white:base_color=0.9,0.2,0.2",
                                           "--gi.diffuse.spatial_radius", "12"};
  const fs::path before = offline("before", "6", {});
  const fs::path after = offline("after", "16", edited);
  std::vector<std::string> otherSeed = edited;
  otherSeed.insert(otherSeed.end(), {"--gi.seed", "1"});
  const fs::path afterOtherSeed = offline("after-seed-1", "16", otherSeed);
  const fs::path unedited = offline("unedited", "16", {"--gi.diffuse.spatial_radius", "12"});

  // Before the edit the viewer's frames are the offline run's, frame index
  // for frame index, and a run gives the same bits every time: the two
  // frames agree (the frame without GI is above 0.3 from it).
  const double viewerBefore = flip(dir / "view" / "before.exr", before);
  std::printf("viewer against the offline run before the edit: FLIP %.5f\n", viewerBefore);
  EXPECT_LT(viewerBefore, 0.005);
  // After the restart the viewer's frame indices run on from 7, so its
  // noise is another; it must differ from the offline frame no more than
  // another seed's run does, and much less than the unedited material's.
  const double viewerToOffline = flip(dir / "view" / "after.exr", after);
  EXPECT_LT(viewerToOffline, 1.25 * flip(afterOtherSeed, after));
  EXPECT_LT(viewerToOffline, 0.6 * flip(unedited, after));
  // The edit shows: the frame turns red.
  EXPECT_GT(meanRedShare(dir / "view" / "after.exr"), meanRedShare(dir / "view" / "before.exr") + 0.1);
  EXPECT_TRUE(fs::exists(dir / "view" / "after.png"));
  // The window as shown: the frame stretched over it and the panels on top.
  const bounce::io::ImageF window = bounce::io::readImage(dir / "view" / "panels.png");
  EXPECT_EQ(window.width, 64);
  EXPECT_EQ(window.height, 48);
  fs::remove_all(dir);
}

// A line of the viewer's output that starts with `prefix`, or "".
std::string lineStartingWith(const std::string& output, const std::string& prefix) {
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind(prefix, 0) == 0) return line;
  return "";
}

TEST(Viewer, TheSplitReferenceStageViewInspectorAndGltfSaveWork) {
  ASSERT_TRUE(fs::exists(kXvfbRun)) << "xvfb-run is missing: scripts/install-deps.sh installs xvfb";
  const fs::path dir = freshDirectory("viewer_view");
  const fs::path script = dir / "session.txt";
  std::ofstream(script) << "wait 2\n"
                           "split reference   # the error readout comes at 4 and 8 samples per pixel\n"
                           "wait 8\n"
                           "inspect 32 30\n"
                           "panels off\n"
                           "stage render.normal\n"
                           "wait 1\n"
                           "window normals\n"
                           "stage gi.denoise.validation\n"
                           "wait 1\n"
                           "window validation\n"
                           "stage final\n"
                           "click 32 12\n"
                           "material roughness 0.2\n"
                           "save-gltf edited.gltf\n";
  const bounce::testing::ProcessResult r =
      bounceInWindow({"view", "cornell", "--script", script.string(), "--out", (dir / "view").string(), "--validate",
                      "--width", "64", "--height", "48"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("vulkan validation"), std::string::npos) << r.output;

  // The GI frame against the reference: closer as the reference's noise falls.
  const auto relMseAt = [&](const std::string& spp) {
    const std::string line = lineStartingWith(r.output, "against the reference (" + spp + " spp): relMSE ");
    EXPECT_FALSE(line.empty()) << r.output;
    return line.empty() ? 0.0 : std::stod(line.substr(line.find("relMSE ") + 7));
  };
  EXPECT_LT(relMseAt("8"), relMseAt("4"));
  EXPECT_GT(relMseAt("8"), 0.0);

  // The inspector reads the renderer's images at the pixel: the back wall,
  // white (cornell white's 0.73), facing the camera, a few units away.
  const std::string depth = lineStartingWith(r.output, "inspect (32, 30) render.viewZ: ");
  ASSERT_FALSE(depth.empty()) << r.output;
  const double viewZ = std::stod(depth.substr(depth.find(": ") + 2));
  EXPECT_GT(viewZ, 1.0);
  EXPECT_LT(viewZ, 100.0);
  EXPECT_NE(lineStartingWith(r.output, "inspect (32, 30) render.albedo: 0.729412 0.729412 0.729412"), "") << r.output;
  EXPECT_NE(lineStartingWith(r.output, "inspect (32, 30) gi.composite"), "") << r.output;

  // The stage view shows the normals in the dumps' false colour (x 0.5 + 0.5):
  // the back wall faces +z, so the window is blue there.
  const bounce::io::ImageF window = bounce::io::readImage(dir / "view" / "normals.png");
  const float* centre = &window.pixels[(std::size_t(24) * std::size_t(window.width) + 32) * window.channelCount()];
  EXPECT_GT(centre[2], centre[0] + 0.2f);
  EXPECT_GT(centre[2], centre[1] + 0.2f);

  // The denoiser's validation view (drawn on captured frames only, so
  // shown frames are captured): another picture than the normals, not flat.
  const bounce::io::ImageF validation = bounce::io::readImage(dir / "view" / "validation.png");
  ASSERT_EQ(validation.pixels.size(), window.pixels.size());
  std::size_t differing = 0;
  float low = 1.0f, high = 0.0f;
  for (std::size_t i = 0; i < validation.pixels.size(); ++i) {
    differing += std::abs(validation.pixels[i] - window.pixels[i]) > 0.05f ? 1 : 0;
    low = std::min(low, validation.pixels[i]);
    high = std::max(high, validation.pixels[i]);
  }
  EXPECT_GT(differing, validation.pixels.size() / 4);
  EXPECT_GT(high - low, 0.3f);

  // The saved glTF holds the edit.
  std::ifstream gltf(dir / "view" / "edited.gltf");
  ASSERT_TRUE(gltf) << r.output;
  const nlohmann::json document = nlohmann::json::parse(gltf);
  EXPECT_FLOAT_EQ(document["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"].get<float>(), 0.2f);
  fs::remove_all(dir);
}

TEST(Viewer, HeadlessItDrawsThePanelsIntoAnImageAndReportsItsOwnCost) {
  const fs::path dir = freshDirectory("viewer_headless");
  const fs::path script = dir / "costs.txt";
  std::ofstream(script) << "panels off\nwait 4\ntimings hidden\nwindow bare\npanels on\nwait 4\ntimings shown\n"
                           "window panels\nset restir off\nsplit other\nwait 2\npanels off\nwindow defaults\n"
                           "other-settings missing.json\n";
  // No X server: the environment has no DISPLAY, and none is needed.
  const bounce::testing::ProcessResult r =
      bounce::testing::runProcess({BOUNCE_BINARY, "view", "cornell", "--headless", "--script", script.string(), "--out",
                                   (dir / "view").string(), "--validate", "--width", "64", "--height", "48"},
                                  {"DISPLAY=", "WAYLAND_DISPLAY="});
  // The script ran to its last line, which names the missing file.
  ASSERT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("missing.json"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("vulkan validation"), std::string::npos) << r.output;
  for (const char* label : {"timings hidden: ", "timings shown: "}) {
    const std::string line = lineStartingWith(r.output, label);
    ASSERT_FALSE(line.empty()) << r.output;
    EXPECT_NE(line.find("GI library "), std::string::npos) << line;
    EXPECT_NE(line.find("viewer's own "), std::string::npos) << line;
  }
  // With the panels the image differs from the frame alone.
  const bounce::io::ImageF bare = bounce::io::readImage(dir / "view" / "bare.png");
  const bounce::io::ImageF panels = bounce::io::readImage(dir / "view" / "panels.png");
  ASSERT_EQ(bare.pixels.size(), panels.pixels.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < bare.pixels.size(); ++i) differing += bare.pixels[i] != panels.pixels[i] ? 1 : 0;
  EXPECT_GT(differing, bare.pixels.size() / 4);
  // The split against the default settings: the right half is another
  // library's frame (with ReSTIR, where the left has none), a grey line between.
  const bounce::io::ImageF split = bounce::io::readImage(dir / "view" / "defaults.png");
  const float* line = &split.pixels[(std::size_t(10) * std::size_t(split.width) + 32) * split.channelCount()];
  EXPECT_NEAR(line[0], line[1], 1e-6f);
  EXPECT_GT(line[0], 0.1f);
  // Frames captured only for the library's validation views write nothing:
  // every GI session used to leave an empty folder named "-stages".
  EXPECT_FALSE(fs::exists(dir / "view" / "-stages"));
  fs::remove_all(dir);

  const bounce::testing::ProcessResult noScript = bounce({"view", "cornell", "--headless"});
  EXPECT_EQ(noScript.exitCode, 2);  // a mistake on the command line
  EXPECT_NE(noScript.output.find("--headless needs --script"), std::string::npos) << noScript.output;
}

// The bytes of a PNG as stored (readImage would decode sRGB to linear).
bounce::io::Rgba8Image pngBytes(const fs::path& png) {
  std::ifstream in(png, std::ios::binary);
  const std::vector<unsigned char> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return bounce::io::decodeRgba8(file, png.string(), 16384);
}

// Whether `window` shows `plot`'s image byte for byte somewhere in the
// BRDF window's corner of the window (right of the panels, near the top).
bool showsPlot(const bounce::io::Rgba8Image& window, const bounce::viewer::BrdfPlot& plot) {
  const std::vector<std::uint8_t>& bytes = plot.rgba();
  const auto matches = [&](int x0, int y0) {
    for (int y = 0; y < plot.height(); ++y)
      for (int x = 0; x < plot.width(); ++x)
        for (std::size_t c = 0; c < 3; ++c)
          if (window.rgba8[(std::size_t(y0 + y) * std::size_t(window.width) + std::size_t(x0 + x)) * 4 + c] !=
              bytes[(std::size_t(y) * std::size_t(plot.width()) + std::size_t(x)) * 4 + c])
            return false;
    return true;
  };
  for (int y0 = 0; y0 + plot.height() <= window.height && y0 < 80; ++y0)
    for (int x0 = 300; x0 + plot.width() <= window.width; ++x0)
      if (matches(x0, y0)) return true;
  return false;
}

TEST(Viewer, ThePickedMaterialsBrdfPlotsFollowItsEdits) {
  const fs::path dir = freshDirectory("viewer_brdf");
  const fs::path script = dir / "brdf.txt";
  std::ofstream(script) << "wait 1\nclick 360 200\nmaterial metallic 1\nmaterial roughness 0.15\nwait 8\n"
                           "window smooth\nmaterial roughness 0.9\nwait 8\nwindow rough\n";
  // GI off: the plots need none, and the frame is cheaper on the CPU.
  const bounce::testing::ProcessResult r = bounce::testing::runProcess(
      {BOUNCE_BINARY, "view", "cornell", "--gi", "off", "--headless", "--script", script.string(), "--out",
       (dir / "view").string(), "--validate", "--width", "720", "--height", "300"},
      {"DISPLAY="});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("vulkan validation"), std::string::npos) << r.output;
  const bounce::io::Rgba8Image smooth = pngBytes(dir / "view" / "smooth.png");
  const bounce::io::Rgba8Image rough = pngBytes(dir / "view" / "rough.png");
  // The window shows the plots of the edited values, refined by 4096
  // samples a frame (8 frames after each edit, the capture's frame the 9th),
  // texel for texel as BrdfPlot makes them; and not the other edit's.
  const glm::vec3 white(0.73f);  // cornell white
  bounce::viewer::BrdfPlot smoothPlot(90), roughPlot(90);
  smoothPlot.setMaterial(white, 0.15f, 1.0f);
  roughPlot.setMaterial(white, 0.9f, 1.0f);
  for (int frame = 0; frame < 9; ++frame) {
    smoothPlot.refine(4096);
    roughPlot.refine(4096);
  }
  EXPECT_TRUE(showsPlot(smooth, smoothPlot));
  EXPECT_TRUE(showsPlot(rough, roughPlot));
  EXPECT_FALSE(showsPlot(rough, smoothPlot));
  fs::remove_all(dir);
}

TEST(Viewer, ARecordedSessionReplaysToTheSamePictures) {
  const fs::path dir = freshDirectory("viewer_record");
  const fs::path script = dir / "session.txt", recording = dir / "recorded.txt";
  std::ofstream(script) << "wait 2\nkey w 3\nlook 30 0\nclick 32 24\nmaterial roughness 0.4\n"
                           "set diffuse.spatial_radius 12\nwait 3\nscreenshot moved\nframes on\nplay 5\n"
                           "frames off\nscreenshot path\n";
  const auto view = [&](const fs::path& commands, const std::string& out, bool record) {
    // GI off: the renderer alone is deterministic, so a replay must give the same pictures.
    std::vector<std::string> arguments = {BOUNCE_BINARY, "view",
                                          "cornell",     "--gi",
                                          "off",         "--camera",
                                          "orbit",       "--headless",
                                          "--script",    commands.string(),
                                          "--out",       (dir / out).string(),
                                          "--width",     "64",
                                          "--height",    "48"};
    if (record) arguments.insert(arguments.end(), {"--record", recording.string()});
    const bounce::testing::ProcessResult r = bounce::testing::runProcess(arguments, {"DISPLAY="});
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return r;
  };
  view(script, "original", true);
  std::ifstream in(recording);
  const std::string recorded((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // What the session did, as commands: the clicks, edits, settings and
  // screenshots as they were, the camera as a pose a frame (a cut as camera).
  for (const char* line : {"\nclick 32 24\n", "\nmaterial roughness 0.4", "\nset diffuse.spatial_radius 12\n",
                           "\nscreenshot moved\n", "\nscreenshot path\n", "\ncamera ", "\npose "})
    EXPECT_NE(recorded.find(line), std::string::npos) << line << " in\n" << recorded;
  view(recording, "replay", false);
  // The same frames: the same camera each frame, the same edits.
  for (const char* shot : {"moved.exr", "path.exr"})
    EXPECT_LT(flip(dir / "original" / shot, dir / "replay" / shot), 0.01) << shot;
  // The camera path moved the camera: the two screenshots differ.
  EXPECT_GT(flip(dir / "original" / "moved.exr", dir / "original" / "path.exr"), 0.2);
  // R's frames: the five of the path, numbered, as the screenshots' PNGs are.
  for (int frame = 0; frame < 5; ++frame)
    EXPECT_TRUE(fs::exists(dir / "original" / "recording-0" / ("frame000" + std::to_string(frame) + ".png")));
  EXPECT_FALSE(fs::exists(dir / "original" / "recording-0" / "frame0005.png"));
  // A recording never replaces a file.
  const bounce::testing::ProcessResult again =
      bounce({"view", "cornell", "--headless", "--script", script.string(), "--record", recording.string()});
  EXPECT_EQ(again.exitCode, 2);
  EXPECT_NE(again.output.find("exists; not overwritten"), std::string::npos) << again.output;
  fs::remove_all(dir);
}

TEST(Viewer, ABadScriptIsOneLineNamingItsLineBeforeAnyWindowOpens) {
  const fs::path script = fs::temp_directory_path() / ("bounce_viewer_bad_" + std::to_string(::getpid()) + ".txt");
  std::ofstream(script) << "wait 2\nmaterial shininess 4\n";
  // No X server here: the script is refused before the window is needed.
  const bounce::testing::ProcessResult r =
      bounce({"view", "cornell", "--script", script.string(), "--width", "32", "--height", "24"});
  fs::remove(script);
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find(script.string() + ":2: unknown material field 'shininess'"), std::string::npos) << r.output;
}

TEST(Viewer, AScriptThatFailsMidSessionIsOneLineAndDestroysNothingTheGpuStillUses) {
  const fs::path dir = freshDirectory("viewer_failing");
  const fs::path script = dir / "s.txt";
  // Frames in flight with GI on, a stage capture pending, then a failing command.
  std::ofstream(script) << "wait 2\nstages a\nstage nope\n";
  const bounce::testing::ProcessResult r = bounce({"view", "cornell", "--headless", "--validate", "--width", "32",
                                                   "--height", "18", "--script", script.string(), "--out",
                                                   (dir / "out").string()});
  EXPECT_EQ(r.signal, 0) << r.output;
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_EQ(r.output.find("VUID"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("vulkan validation"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("validation messages"), std::string::npos) << r.output;
  const std::string expected = "bounce: error: " + script.string() + ":3: no image 'nope'";
  EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
  fs::remove_all(dir);
}

// The lines of `output` that start with one of `prefixes`.
std::vector<std::string> linesStartingWith(const std::string& output, std::initializer_list<const char*> prefixes) {
  std::vector<std::string> found;
  std::istringstream stream(output);
  for (std::string line; std::getline(stream, line);)
    for (const char* prefix : prefixes)
      if (line.rfind(prefix, 0) == 0) found.push_back(line);
  return found;
}

TEST(Viewer, ClickAndInspectOnTheFirstLineSeeTheFirstFrame) {
  // Before any frame existed, a click picked "material 0" (the ids of no
  // frame) and inspect printed zeros: they now wait for the first frame and
  // see what a script that waits for it sees.
  const fs::path dir = freshDirectory("viewer_first_line");
  std::vector<std::vector<std::string>> seen;
  // (0, 0) is the sky: "no surface", not material 0; (8, 6) is the back wall.
  for (const char* script : {"click 0 0\ninspect 8 6\n", "wait 1\nclick 0 0\ninspect 8 6\n"}) {
    std::ofstream(dir / "s.txt") << script;
    const bounce::testing::ProcessResult r =
        bounce({"view", "cornell", "--headless", "--gi", "off", "--width", "16", "--height", "12", "--script",
                (dir / "s.txt").string(), "--out", (dir / "out").string()});
    ASSERT_EQ(r.exitCode, 0) << script << r.output;
    seen.push_back(linesStartingWith(r.output, {"picked material", "no surface", "inspect "}));
    ASSERT_GT(seen.back().size(), 2u) << script << r.output;
  }
  EXPECT_EQ(seen[0], seen[1]);
  EXPECT_EQ(seen[0][0], "no surface at pixel (0, 0)");
  bool lit = false;  // the wall's depth and albedo, not the zeros of no frame
  for (const std::string& line : seen[0])
    if (line.rfind("inspect (8, 6) render.albedo: ", 0) == 0 && line.find(": 0 0 0") == std::string::npos) lit = true;
  EXPECT_TRUE(lit) << seen[0][1];
  fs::remove_all(dir);
}

TEST(Viewer, AScreenshotOrStageDumpNeverReplacesAFile) {
  const fs::path dir = freshDirectory("viewer_names");
  const fs::path out = dir / "out";
  fs::create_directories(out / "a-stages");
  std::ofstream(out / "a.png") << "the user's own file";
  std::ofstream(out / "a-stages" / "notes.txt") << "the user's own notes";
  const fs::path script = dir / "s.txt";
  std::ofstream(script) << "wait 1\nscreenshot a\nscreenshot a\nstages a\nwait 1\n";
  const bounce::testing::ProcessResult r = bounce({"view", "cornell", "--headless", "--gi", "off", "--width", "32",
                                                   "--height", "18", "--script", script.string(), "--out",
                                                   out.string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::ifstream kept(out / "a.png");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}), "the user's own file");
  EXPECT_FALSE(fs::exists(out / "a.exr")) << "a.png was taken, so a.exr is not this screenshot's";
  for (const char* name : {"a-2.png", "a-2.exr", "a-3.png", "a-3.exr"})
    EXPECT_NO_THROW(bounce::io::readImage(out / name)) << name << "\n" << r.output;
  EXPECT_EQ(std::distance(fs::directory_iterator(out / "a-stages"), fs::directory_iterator{}), 1);
  EXPECT_GT(std::distance(fs::directory_iterator(out / "a-2-stages"), fs::directory_iterator{}), 4);
  EXPECT_NE(r.output.find("the screenshot is a-2"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

TEST(Viewer, NoDisplayIsAClearErrorNamingXvfb) {
  const bounce::testing::ProcessResult r = bounce::testing::runProcess(
      {BOUNCE_BINARY, "view", "cornell", "--width", "32", "--height", "24"}, {"DISPLAY=", "WAYLAND_DISPLAY="});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.output.find("xvfb-run"), std::string::npos) << r.output;
}

}  // namespace
