// bounce ghosting on lavapipe, in miniature (docs/metrics.md): both events
// at 96x64 with a few frames and 1-spp references (tracing them was most of
// each test's time: at 4 spp the moving object took 31 s of its 120 s on a
// busy 2-core machine, issue 46). The references are far too noisy here
// for the errors to mean much at any of those sample counts, so beyond
// their being finite the tests check what the regions are: the pixels a fast turn uncovers are
// those outside the view before the turn (worked out here from the two
// cameras alone), and on the uncovered pixels of either event the GI
// library's own history length (which its reprojection, not the tool's,
// decides) starts at one frame and grows by one a frame, while the rest
// keeps its long history.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "io/image_io.h"
#include "process.h"

namespace {

namespace fs = std::filesystem;

struct Result {
  int exitCode;
  std::string output;  // stdout and stderr together
};

// `arguments` split at spaces; `whole`: arguments passed as they are
// (material names with spaces).
Result run(const std::string& arguments, const std::vector<std::string>& whole = {}) {
  std::vector<std::string> argv = {BOUNCE_BINARY};
  for (std::string& word : bounce::testing::splitWords(arguments)) argv.push_back(std::move(word));
  argv.insert(argv.end(), whole.begin(), whole.end());
  const bounce::testing::ProcessResult r = bounce::testing::runProcess(argv);
  return {r.exitCode, r.output};
}

fs::path freshDirectory(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("bounce_ghosting_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

constexpr int kWidth = 96, kHeight = 64;
const std::string kSmall = " --validate --width 96 --height 64 --gi-warmup 2 --reference-spp 1 --seed 3";

// Labels of regions.exr.
enum Label { kBackground = 0, kRest = 1, kUncovered = 2, kNeither = 3, kNearby = 4 };

nlohmann::json readJson(const fs::path& file) {
  std::ifstream stream(file);
  return nlohmann::json::parse(stream);
}

// What every run writes, and the parts of its JSON every run must have.

nlohmann::json checkOutputs(const fs::path& dir, const Result& r, std::size_t ages) {
  for (const char* name : {"ghosting.json", "ghosting.png", "regions.exr", "regions.png"})
    EXPECT_TRUE(fs::exists(dir / name)) << name << "\n" << r.output;
  for (const char* table : {"\nframe relMSE", "\nindirect diffuse relMSE", "\nindirect specular relMSE"})
    EXPECT_NE(r.output.find(table), std::string::npos) << table << "\n" << r.output;
  EXPECT_NE(r.output.find("the uncovered pixels within 1.5 x the rest"), std::string::npos) << r.output;
  const bounce::io::ImageF plot = bounce::io::readImage(dir / "ghosting.png");
  EXPECT_GT(plot.width, 500);
  EXPECT_GT(plot.height, 3 * 200) << "a panel for the frame and one per indirect signal";
  const nlohmann::json json = readJson(dir / "ghosting.json");
  EXPECT_EQ(json["ages"].size(), ages);
  for (const nlohmann::json& age : json["ages"])
    for (const char* region : {"uncovered", "nearby", "rest"}) {
      EXPECT_GT(age[region]["pixels"].get<int>(), 0) << region << " at +" << age["after_event"];
      for (const char* part : {"frame", "indirect_diffuse", "indirect_specular"}) {
        const nlohmann::json& value = age[region]["relmse"][part];
        EXPECT_TRUE(value.is_number()) << region << " " << part << ": " << value;
        const double relMse = value.is_number() ? value.get<double>() : std::nan("");
        EXPECT_TRUE(std::isfinite(relMse) && relMse > 0.0) << region << " " << part << ": " << relMse;
      }
    }
  return json;
}

// The library's history on the uncovered pixels: one frame at the event
// (it restarted where the tool says the surface is new), one more each
// frame after; the rest's long, throughout.
void checkHistories(const nlohmann::json& json) {
  for (const nlohmann::json& age : json["ages"]) {
    const int k = age["after_event"];
    const double uncovered = age["uncovered"]["history"], rest = age["rest"]["history"];
    std::printf("+%d: history %.3f on the uncovered pixels, %.3f on the rest; frame relMSE %.4f and %.4f\n", k,
                uncovered, rest, age["uncovered"]["relmse"]["frame"].get<double>(),
                age["rest"]["relmse"]["frame"].get<double>());
    EXPECT_NEAR(uncovered, k + 1.0, 0.5) << "+" << k;
    EXPECT_GT(rest, uncovered + 2.0) << "+" << k;
  }
}

glm::vec3 vec3(const nlohmann::json& v) { return {v[0].get<float>(), v[1].get<float>(), v[2].get<float>()}; }

// A camera of the JSON: its basis and the tangents of its half angles.
struct View {
  glm::vec3 right, up, forward, position;
  float tanX, tanY;
  explicit View(const nlohmann::json& pose) {
    position = vec3(pose["position"]);
    forward = glm::normalize(vec3(pose["target"]) - position);
    right = glm::normalize(glm::cross(forward, vec3(pose["up"])));
    up = glm::cross(right, forward);
    tanY = std::tan(glm::radians(pose["fovY"].get<float>()) / 2.0f);
    tanX = tanY * float(kWidth) / float(kHeight);
  }
};

// A fast turn: the uncovered pixels are exactly those the view before did
// not show, the library restarts its history on them (and keeps it on the
// rest), and every region's error is measured (finite; what 1-spp
// references can say of it).
TEST(Ghosting, AFastTurnUncoversWhatTheViewBeforeDidNotShow) {
  const fs::path dir = freshDirectory("turn");
  const Result r = run("ghosting sun-room --event-frame 5 --after 3 --settle 2" + kSmall + " --out " + dir.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json json = checkOutputs(dir, r, 4);
  checkHistories(json);
  EXPECT_TRUE(json["settled"].is_object()) << "--settle 2 measures once more";

  // A turn about the camera's own position moves nothing in front of
  // anything: a surface is new exactly when its direction lay outside the
  // view before. Every pixel the tool put in a region is checked.
  const View before(json["camera_before_event"]), after(json["camera_at_event"]);
  ASSERT_EQ(before.position, after.position);
  const bounce::io::ImageF labels = bounce::io::readImage(dir / "regions.exr");
  ASSERT_EQ(labels.width, kWidth);
  int agree = 0, disagree = 0, neither = 0, uncovered = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const int label = int(labels.at(x, y, 0));
      if (label == kBackground) continue;
      if (label == kNeither) {
        ++neither;
        continue;
      }
      const float ndcX = 2.0f * (float(x) + 0.5f) / kWidth - 1.0f, ndcY = 1.0f - 2.0f * (float(y) + 0.5f) / kHeight;
      const glm::vec3 ray = after.forward + ndcX * after.tanX * after.right + ndcY * after.tanY * after.up;
      const float depth = glm::dot(ray, before.forward);
      const bool outside = !(depth > 0.0f && std::abs(glm::dot(ray, before.right)) <= before.tanX * depth &&
                             std::abs(glm::dot(ray, before.up)) <= before.tanY * depth);
      uncovered += label == kUncovered;
      ((label == kUncovered) == outside ? agree : disagree) += 1;
    }
  std::printf("fast turn: %d pixels uncovered; %d agree with the cameras, %d do not, %d in no region\n", uncovered,
              agree, disagree, neither);
  EXPECT_GT(uncovered, kWidth * kHeight / 10) << "20 degrees of a 77-degree-wide view";
  EXPECT_LE(disagree + neither, kHeight) << "at most a column along the old view's edge";
  EXPECT_EQ(json["events"][0]["uncovered_pixels"].get<int>(), uncovered);
  fs::remove_all(dir);
}

// A moving object: three event frames' strips are found and pooled by their
// age, the library's history restarts on each strip and grows a frame a
// frame while the rest keeps its own, and every region's error is finite.
// The 1-spp references change none of that (the checks on the regions and
// histories never read them); they only cost less to trace than 4 spp.
TEST(Ghosting, AMovingObjectUncoversStripsTheLibraryStartsOverOn) {
  const fs::path dir = freshDirectory("object");
  const Result r = run("ghosting --event object --event-frame 5 --events 3 --after 3 --settle 0" + kSmall + " --out " +
                       dir.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json json = checkOutputs(dir, r, 4);
  EXPECT_EQ(json["scene"], "sun-room-animated");
  EXPECT_TRUE(json["settled"].is_null());
  EXPECT_EQ(json["ages"][3]["frames"], nlohmann::json({8, 9, 10})) << "age +3 pools the three events";
  checkHistories(json);
  // The strips lie beside the box: some of the nearby rest shows it.
  const bounce::io::ImageF labels = bounce::io::readImage(dir / "regions.exr");
  int uncovered = 0;
  for (float label : labels.pixels) uncovered += int(label) == kUncovered;
  EXPECT_GT(uncovered, 0);
  fs::remove_all(dir);
}

// In a black scene every region's relMSE is 0 (defined: its epsilon), and
// the uncovered pixels' ratio to the others is 0 / 0: "undefined" in the
// table, null in the JSON. It showed "-", the mark of a number not measured.
TEST(Ghosting, RatiosOverABlackReferenceAreUndefinedNotMissing) {
  const fs::path dir = freshDirectory("black");
  const Result r =
      run("ghosting sun-room --no-sun --env-intensity 0 --width 32 --height 18 --after 1 --settle 1 "
          "--reference-spp 1 --gi-warmup 1 --event-frame 2 --out " +
          dir.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find(" nan"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("-nan"), std::string::npos) << r.output;
  const std::string table = r.output.substr(r.output.find("\nframe relMSE"));
  const std::string firstRow = table.substr(table.find("\n  +0"), 80);
  EXPECT_NE(firstRow.find("  0          0          0  undefined  undefined"), std::string::npos) << table;
  const nlohmann::json json = readJson(dir / "ghosting.json");
  const nlohmann::json& age = json["ages"][0];
  EXPECT_EQ(age["uncovered"]["relmse"]["frame"], 0.0);
  EXPECT_TRUE(age["ratio_to_rest"]["frame"].is_null());
  fs::remove_all(dir);
}

// The means of a convergence event's JSON, frame by frame: [after_event] -> mean.
std::vector<double> means(const nlohmann::json& json, const char* signal) {
  std::vector<double> values;
  for (const nlohmann::json& frame : json["frames"]) values.push_back(frame[signal]["mean"].get<double>());
  return values;
}

// bounce ghosting --event light on cornell: its lamp off until the event
// frame, switched on there; `options` the sizes and frames, `dir` the output.
Result switchCornellsLampOn(const std::string& options, const fs::path& dir) {
  return run("ghosting cornell --event light --seed 3 " + options + " --out " + dir.string(),
             {"--material", "cornell light:emission=0,0,0", "--light-change", "cornell light:emission=10,10,10"});
}

// --event light: cornell's lamp, off until the event frame, switched on
// there (the viewer's material edit). The reference is of the lamp on, so
// the frame before the event is far below it; from the event on the
// indirect light climbs towards the settled frame. A lamp switched before
// the event, or a reference of the old lighting, fails the first check; an
// edit never made fails the second (the light stays at its level before).
TEST(Ghosting, ALampSwitchedOnIsFollowedFrameByFrameToItsSettledLight) {
  const fs::path dir = freshDirectory("light");
  const Result r = switchCornellsLampOn(
      "--width 48 --height 32 --gi-warmup 2 --event-frame 3 --after 4 --settle 8 --reference-spp 16 --validate", dir);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* name : {"ghosting.json", "ghosting.png"}) EXPECT_TRUE(fs::exists(dir / name)) << name;
  EXPECT_NE(r.output.find("indirect diffuse: the mean within 10 % of its settled value"), std::string::npos)
      << r.output;
  const nlohmann::json json = readJson(dir / "ghosting.json");
  ASSERT_EQ(json["frames"].size(), 6u) << "the frame before the event, then +0 .. +4";
  EXPECT_EQ(json["frames"][0]["after_event"], -1);
  EXPECT_EQ(json["settled"]["frame"], 3 + 4 + 8);
  const std::vector<double> diffuse = means(json, "indirect_diffuse");
  const double reference = json["reference_mean"]["indirect_diffuse"],
               settled = json["settled"]["indirect_diffuse"]["mean"];
  std::printf("indirect diffuse mean: before %.4f, +0 %.4f, +4 %.4f, settled %.4f, reference %.4f\n", diffuse[0],
              diffuse[1], diffuse[5], settled, reference);
  EXPECT_LT(diffuse[0], 0.2 * reference) << "the lamp is off before the event; the reference has it on";
  EXPECT_GT(diffuse[5], 5.0 * diffuse[0]) << "the lamp's light arrives after the event";
  EXPECT_GE(diffuse[5], diffuse[1]) << "and climbs";
  EXPECT_GT(settled, diffuse[5]);
  for (const char* signal : {"indirect_diffuse", "indirect_specular"})
    for (const char* tolerance : {"10_percent", "5_percent"})
      for (const char* of : {"of_reference", "of_settled"}) {
        const nlohmann::json& value = json["within"][signal][tolerance][of];
        EXPECT_TRUE(value.is_null() || value.is_number_integer()) << signal << " " << tolerance << " " << of;
      }
  const bounce::io::ImageF plot = bounce::io::readImage(dir / "ghosting.png");
  EXPECT_GT(plot.height, 2 * 200) << "a panel per indirect signal";
  fs::remove_all(dir);
}

// The bar on lavapipe: cornell's lamp, off through the warm-up,
// switched on; 10 frames later the indirect diffuse is within 10 % of the
// reference of the lamp on. The library sees the change in the direct light
// it is given (gi.light_change: the lamp's share of the frame's light) and
// every temporal history restarts at the event and the frame after (when
// the screen's samples first see the lamp), then regrows. Without that the
// histories (reservoirs, the denoiser's, the radiance cache's) held the
// dark room: 0.38 of the reference 10 frames after the lamp.
// The reference is traced at 16 spp (64 took most of the test's 36.6 s of
// its 120 s on a busy 2-core machine, issue 46): its indirect diffuse mean
// over the 96x64 frame is 1.1553 at 16 spp and 1.1518 at 64, 0.3 % apart
// against the 10 % bar, so the test still proves the same: the GI frame is
// within 10 % of the new light 10 frames on (1.054 of it), after a dark
// room of 36 frames. Its frames are kept: the value at +10 depends on how
// long the room was dark (1.23 with the event at frame 12).
TEST(Ghosting, ALampSwitchedOnIsWithinTenPercentOfTheNewLightTenFramesLater) {
  const fs::path dir = freshDirectory("lamp_ten_frames");
  const Result r = switchCornellsLampOn(
      "--width 96 --height 64 --gi-warmup 16 --event-frame 20 --after 10 --settle 1 --reference-spp 16", dir);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json json = readJson(dir / "ghosting.json");
  ASSERT_EQ(json["frames"].size(), 12u) << "the frame before the event, then +0 .. +10";
  const double reference = json["reference_mean"]["indirect_diffuse"];
  const nlohmann::json& last = json["frames"][11];
  ASSERT_EQ(last["after_event"], 10);
  const double atTen = last["indirect_diffuse"]["mean"];
  std::printf("indirect diffuse 10 frames after the lamp: %.4f, reference %.4f (%.3f of it)\n", atTen, reference,
              atTen / reference);
  EXPECT_NEAR(atTen / reference, 1.0, 0.10);
  for (const nlohmann::json& frame : json["frames"]) {
    const int after = frame["after_event"];
    const double changed = frame["light_changed"], kept = frame["history_kept"];
    if (after == 0) {
      EXPECT_GT(changed, 0.5) << "the lamp is most of the frame's light";
    } else {
      EXPECT_EQ(changed, 0.0) << "+" << after << ": nothing changed";
    }
    const double restarted = after == 0 || after == 1 ? 0.0 : 1.0;
    EXPECT_EQ(kept, restarted) << "+" << after << (restarted == 0.0 ? ": every history restarts" : "");
  }
  fs::remove_all(dir);
}

// Issue 46 (S1): at 16x16 and 8x8 no pixel centre falls on cornell's lamp
// (1.3 x 1.05 m, seen nearly edge on), so the direct light and emission the
// library compares showed no change when it was switched on, every history
// held the dark room, and two frames later the indirect light was 2-3 % of
// the reference. The renderer now declares its emission edit
// (FrameInputs::lightChange): the verdict is the whole light changed at
// the event, every history restarts at it and the frame after, and the
// indirect light follows (0.8 of the reference at +2, 16x16).
TEST(Ghosting, ALampNoPixelShowsIsStillSeenSwitchingOn) {
  for (const char* size : {"16", "8"}) {
    const fs::path dir = freshDirectory(std::string("tiny_lamp_") + size);
    const Result r = switchCornellsLampOn(std::string("--width ") + size + " --height " + size +
                                              " --gi-warmup 4 --event-frame 3 --after 2 --settle 1 "
                                              "--reference-spp 4 --validate",
                                          dir);
    ASSERT_EQ(r.exitCode, 0) << size << "\n" << r.output;
    const nlohmann::json json = readJson(dir / "ghosting.json");
    ASSERT_EQ(json["frames"].size(), 4u) << "the frame before the event, then +0 .. +2";
    for (const nlohmann::json& frame : json["frames"]) {
      const int after = frame["after_event"];
      EXPECT_EQ(frame["light_changed"].get<double>(), after == 0 ? 1.0 : 0.0) << size << " at +" << after;
      EXPECT_EQ(frame["history_kept"].get<double>(), after == 0 || after == 1 ? 0.0 : 1.0) << size << " at +" << after;
    }
    const std::vector<double> diffuse = means(json, "indirect_diffuse");
    const double reference = json["reference_mean"]["indirect_diffuse"];
    std::printf("%sx%s: indirect diffuse before %.4f, +2 %.4f, reference %.4f\n", size, size, diffuse[0], diffuse[3],
                reference);
    EXPECT_GT(diffuse[3], 10.0 * diffuse[0]) << size << ": the lamp's light arrived";
    EXPECT_GT(diffuse[3], 0.25 * reference) << size << ": not held at the dark room's level";
    fs::remove_all(dir);
  }
}

// --event cut: a still camera cuts in place. Every history restarts, so
// the denoised diffuse at the cut is noisier than the frame before (a cut
// not made would leave the two alike), and the JSON says when the mean is
// back within 10 % and 5 % of its value before the cut.
TEST(Ghosting, ACutInPlaceRestartsTheHistoriesAndIsFollowedBackToItsLevel) {
  const fs::path dir = freshDirectory("cut");
  const Result r =
      run("ghosting cornell --event cut --width 48 --height 32 --gi-warmup 16 --event-frame 2 --after 3 "
          "--settle 4 --reference-spp 16 --seed 3 --validate --out " +
          dir.string());
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json json = readJson(dir / "ghosting.json");
  ASSERT_EQ(json["frames"].size(), 5u);
  const double before = json["frames"][0]["indirect_diffuse"]["relmse"],
               atCut = json["frames"][1]["indirect_diffuse"]["relmse"];
  std::printf("indirect diffuse relMSE: before the cut %.4f, at it %.4f\n", before, atCut);
  EXPECT_GT(atCut, 1.5 * before) << "the histories restarted at the cut";
  EXPECT_TRUE(json["within"]["indirect_diffuse"]["10_percent"].contains("of_before_cut"));
  EXPECT_NE(r.output.find("of the value before the cut"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

// --event sun: sun-room's sun turned half round at the event frame, so it
// no longer shines in through the window. The reference (of the lighting
// after the event) holds much less indirect light than that of a cut in
// place (the lighting before); a sun never moved, for the path tracer or
// the renderer, leaves the two alike.
TEST(Ghosting, ASunTurnedAwayFromTheWindowIsTracedAfterItsTurn) {
  const std::string common =
      " --width 48 --height 32 --gi-warmup 8 --event-frame 3 --after 2 --settle 2 "
      "--reference-spp 16 --seed 3 --validate --out ";
  const fs::path sunDir = freshDirectory("sun"), cutDir = freshDirectory("sun_cut");
  const Result turned = run("ghosting sun-room --event sun --sun-jump 180" + common + sunDir.string());
  ASSERT_EQ(turned.exitCode, 0) << turned.output;
  const Result still = run("ghosting sun-room --event cut" + common + cutDir.string());
  ASSERT_EQ(still.exitCode, 0) << still.output;
  const nlohmann::json after = readJson(sunDir / "ghosting.json"), before = readJson(cutDir / "ghosting.json");
  EXPECT_EQ(after["sun_jump_degrees"], 180.0);
  const double moved = after["reference_mean"]["indirect_diffuse"], kept = before["reference_mean"]["indirect_diffuse"];
  std::printf("sun-room's indirect diffuse, reference mean: %.4f with the sun turned, %.4f without\n", moved, kept);
  EXPECT_LT(moved, 0.8 * kept);
  EXPECT_NE(turned.output.find("sun turned by 180 degrees"), std::string::npos) << turned.output;
  fs::remove_all(sunDir);
  fs::remove_all(cutDir);
}

TEST(Ghosting, BadArgumentsAreOneClearLine) {
  const fs::path dir = freshDirectory("bad");
  fs::create_directories(dir);
  // A settings file where an output will go: outputs never replace inputs.
  const fs::path settings = dir / "ghosting.json";
  std::ofstream(settings) << "{}\n";
  const std::string out = " --out " + dir.string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"ghosting --event spin", "--event"},
      {"ghosting cornell --event object" + out, "has no animation"},
      {"ghosting --event-frame 4 --after 8" + out, "too early for --after 8"},
      {"ghosting --event object --turn-degrees 10" + out, "--turn-degrees is for --event turn"},
      {"ghosting --camera static --turn-degrees 10" + out, "leave one of them out"},
      {"ghosting --turn-degrees 0" + out, "does not turn"},
      {"ghosting --gi off" + out, "--gi off"},
      {"ghosting --within nan" + out, "--within"},
      {"ghosting --turn-degrees inf" + out, "--turn-degrees"},
      {"ghosting --gi-settings " + settings.string() + out, "refusing to write --out over the input"},
      {"ghosting cornell --event light" + out, "--event light needs what changes"},
      {"ghosting cornell --event cut --light-change lamp:emission=0,0,0" + out, "--light-change is for --event light"},
      {"ghosting --light-change lamp:emission=0,0,0" + out, "--light-change is for --event light"},
      {"ghosting cornell --event light --light-change lamp:emission=0,0,0" + out, "has no material 'lamp'"},
      {"ghosting cornell --event light --light-change lamp:emission" + out, "--light-change lamp:emission"},
      {"ghosting cornell --event cut --settle 0" + out, "--settle 0"},
      {"ghosting cornell --event cut --events 2" + out, "--events is for --event object"},
      {"ghosting cornell --event cut --sun-jump 10" + out, "--sun-jump is for --event sun"},
      {"ghosting --sun-jump 10" + out, "--sun-jump is for --event sun"},
      {"ghosting sun-room --event sun --sun-jump 0" + out, "--sun-jump 0"},
      {"ghosting sun-room --event sun --no-sun" + out, "--event sun needs a sun"}};
  for (const auto& [arguments, words] : cases) {
    const Result r = run(arguments);
    EXPECT_NE(r.exitCode, 0) << arguments;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << arguments << ": " << r.output;
    EXPECT_EQ(r.output.rfind("bounce: error:", 0), 0u) << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << arguments << ": " << r.output;
  }
  // Issue 46 (S3, U1): events that change nothing or measure nothing, and
  // cornell's lamp named as it is not: command-line mistakes (exit 2), each
  // saying why and what to give instead. They ran (exit 0) or suggested
  // 'light:emission=0,0,0' for a lamp named 'cornell light'.
  const std::vector<std::pair<std::string, std::string>> mistakes = {
      {"ghosting sun-room --event sun --sun-elevation -90" + out,
       "is below the horizon: there is no daylight whose change to follow; give --sun-elevation between 0 and 90"},
      {"ghosting sun-room --event sun --sun-elevation 90 --sun-jump 90" + out,
       "stands at the zenith, where turning its azimuth moves nothing"},
      {"ghosting sun-room --event sun --sun-jump 1e-30" + out,
       "(azimuth 105 -> 105): nothing changes; the sun must move by at least 0.01 degrees"},
      {"ghosting cornell --event cut --gi off" + out, "--event cut measures the GI, and there is none to measure"},
      {"ghosting cornell --event light --gi off --light-change lamp:emission=0,0,0" + out,
       "--event light measures the GI"},
      {"ghosting cornell --event light" + out, "'cornell light:emission=0,0,0' switches cornell's lamp off"},
      {"ghosting cornell --event light --light-change light:emission=0,0,0" + out,
       "has no material 'light'; its lamps (materials that emit light) are 'cornell light', e.g. --light-change "
       "'cornell light:emission=0,0,0' switches it off"}};
  for (const auto& [arguments, words] : mistakes) {
    const Result r = run(arguments);
    EXPECT_EQ(r.exitCode, 2) << arguments << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << arguments << ": " << r.output;
    EXPECT_EQ(r.output.rfind("bounce: error:", 0), 0u) << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << arguments << ": " << r.output;
  }
  // A camera that never moves uncovers nothing: said (last, after the
  // device and scene lines) once the event frame is rendered.
  // (In a folder of its own: the settings file the user put in `dir` is
  // not Bounce's, so no run may write ghosting.json there.)
  const Result still = run("ghosting cornell --camera static --width 24 --height 16 --gi-warmup 0 --event-frame 2 "
                           "--after 1 --out " + (dir / "still").string());
  EXPECT_NE(still.exitCode, 0);
  EXPECT_NE(still.output.find("\nbounce: error: nothing is newly uncovered at frame 2"), std::string::npos)
      << still.output;
  std::ifstream kept(settings);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}), "{}\n") << "the input was left as it was";
  const Result help = run("ghosting --help");
  EXPECT_EQ(help.exitCode, 0) << help.output;
  EXPECT_NE(help.output.find("--event"), std::string::npos);
  EXPECT_NE(help.output.find("'cornell light:emission=0,0,0' switches cornell's lamp off"), std::string::npos)
      << help.output;
  fs::remove_all(dir);
}

}  // namespace
