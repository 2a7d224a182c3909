// bounce view's parts that need no window: the script parser, the fly
// camera, the settings file the panel saves.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <sys/stat.h>
#include <unistd.h>

#include <glm/glm.hpp>

#include "bounce/gi_settings.h"
#include "viewer/fly_camera.h"
#include "viewer/panels.h"
#include "viewer/script.h"
#include "viewer/script_player.h"

namespace {

using bounce::viewer::parseScript;
using Kind = bounce::viewer::ScriptCommand::Kind;

std::string errorOf(const std::string& text) {
  try {
    parseScript(text, "s.txt");
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST(ViewerScript, ParsesEveryCommandWithItsLineAndArguments) {
  const auto commands = parseScript(
      "# a session\n"
      "wait 8\n"
      "\n"
      "key w 3   # forward\n"
      "look -10 2.5\n"
      "camera 0 1 5 0 1 0\n"
      "click 20 27\n"
      "set diffuse.spatial_radius 12\n"
      "gi screen-only\n"
      "material base_color 0.9 0.2 0.2\n"
      "material roughness 0.3\n"
      "screenshot after\n"
      "stages all\n"
      "window shot\n"
      "quit\n",
      "s.txt");
  ASSERT_EQ(commands.size(), 13u);
  EXPECT_EQ(commands[0].kind, Kind::Wait);
  EXPECT_EQ(commands[0].numbers, std::vector<double>{8.0});
  EXPECT_EQ(commands[1].kind, Kind::Key);
  EXPECT_EQ(commands[1].line, 4);
  EXPECT_EQ(commands[1].words, std::vector<std::string>{"w"});
  EXPECT_EQ(commands[2].numbers, (std::vector<double>{-10.0, 2.5}));
  EXPECT_EQ(commands[3].numbers.size(), 6u);
  EXPECT_EQ(commands[4].numbers, (std::vector<double>{20.0, 27.0}));
  EXPECT_EQ(commands[5].words, (std::vector<std::string>{"diffuse.spatial_radius", "12"}));
  EXPECT_EQ(commands[6].words, std::vector<std::string>{"screen-only"});
  EXPECT_EQ(commands[7].words, std::vector<std::string>{"base_color"});
  EXPECT_EQ(commands[7].numbers, (std::vector<double>{0.9, 0.2, 0.2}));
  EXPECT_EQ(commands[8].numbers, std::vector<double>{0.3});
  EXPECT_EQ(commands[9].kind, Kind::Screenshot);
  EXPECT_EQ(commands[10].kind, Kind::Stages);
  EXPECT_EQ(commands[11].kind, Kind::Window);
  EXPECT_EQ(commands[12].kind, Kind::Quit);
  EXPECT_EQ(commands[12].line, 15);
}

TEST(ViewerScript, ParsesTheViewCommands) {
  const auto commands = parseScript(
      "split reference\nmeasure\nstage render.normal\ninspect 3 4\nsave-gltf edited.glb\npanels off\ntimings ui\n",
      "s.txt");
  ASSERT_EQ(commands.size(), 7u);
  EXPECT_EQ(commands[6].kind, Kind::Timings);
  const auto camera = parseScript("pose 1 2 3 4 5 6\nplay 12\nmaterial emission_strength 40\nsplit other\n", "s");
  ASSERT_EQ(camera.size(), 4u);
  EXPECT_EQ(camera[0].kind, Kind::Pose);
  EXPECT_EQ(camera[1].kind, Kind::Play);
  EXPECT_EQ(camera[1].numbers, std::vector<double>{12.0});
  EXPECT_EQ(camera[2].numbers, std::vector<double>{40.0});
  EXPECT_EQ(camera[3].words, std::vector<std::string>{"other"});
  const auto other = parseScript("other-settings b.json\n", "s");
  ASSERT_EQ(other.size(), 1u);
  EXPECT_EQ(other[0].kind, Kind::OtherSettings);
  EXPECT_NE(errorOf("play 0\n").find("out of range"), std::string::npos);
  EXPECT_NE(errorOf("pose 1 2 3 1 2 3\n").find("same point"), std::string::npos);
  EXPECT_EQ(commands[6].words, std::vector<std::string>{"ui"});
  EXPECT_EQ(commands[0].kind, Kind::Split);
  EXPECT_EQ(commands[0].words, std::vector<std::string>{"reference"});
  EXPECT_EQ(commands[1].kind, Kind::Measure);
  EXPECT_EQ(commands[2].words, std::vector<std::string>{"render.normal"});
  EXPECT_EQ(commands[3].kind, Kind::Inspect);
  EXPECT_EQ(commands[3].numbers, (std::vector<double>{3.0, 4.0}));
  EXPECT_EQ(commands[4].words, std::vector<std::string>{"edited.glb"});
  EXPECT_EQ(commands[5].words, std::vector<std::string>{"off"});
  EXPECT_NE(errorOf("split left\n").find("none, gi-off, other or reference"), std::string::npos);
  EXPECT_NE(errorOf("save-gltf edited.obj\n").find("ending in .gltf or .glb"), std::string::npos);
  EXPECT_NE(errorOf("save-gltf ../x.gltf\n").find("plain file name"), std::string::npos);
  EXPECT_NE(errorOf("panels maybe\n").find("on or off"), std::string::npos);
  EXPECT_NE(errorOf("measure now\n").find("takes 0 arguments"), std::string::npos);
}

TEST(ViewerScript, MistakesNameTheFileLineAndProblem) {
  EXPECT_EQ(errorOf("wait 2\njump 3\n").rfind("s.txt:2: unknown command 'jump'", 0), 0u) << errorOf("jump 3");
  EXPECT_NE(errorOf("wait\n").find("s.txt:1: 'wait' takes 1 argument"), std::string::npos);
  EXPECT_NE(errorOf("wait 0\n").find("out of range"), std::string::npos);
  EXPECT_NE(errorOf("wait 2.5\n").find("not a whole number"), std::string::npos);
  EXPECT_NE(errorOf("wait nan\n").find("not a number"), std::string::npos);
  EXPECT_NE(errorOf("key x 3\n").find("unknown key 'x'"), std::string::npos);
  EXPECT_NE(errorOf("click -1 4\n").find("out of range"), std::string::npos);
  EXPECT_NE(errorOf("material shininess 3\n").find("unknown material field"), std::string::npos);
  EXPECT_NE(errorOf("material roughness 1.5\n").find("out of range"), std::string::npos);
  EXPECT_NE(errorOf("material base_color 1 0\n").find("takes 4 arguments"), std::string::npos);
  EXPECT_NE(errorOf("gi sideways\n").find("off, screen-only or hybrid"), std::string::npos);
  EXPECT_NE(errorOf("screenshot ../x\n").find("not a plain file name"), std::string::npos);
  EXPECT_NE(errorOf("screenshot a/b\n").find("not a plain file name"), std::string::npos);
  EXPECT_NE(errorOf("camera 1 2 3 1 2 3\n").find("same point"), std::string::npos);
  EXPECT_EQ(errorOf("# only a comment\n\n   \n"), "");
}

TEST(ViewerScript, ANulByteIsShownInTheMessageNotCutAt) {
  // Before, the message ended at the NUL: "unknown command 'screen".
  const std::string error = errorOf(std::string("wait 1\nscreen\0shot x\n", 21));
  EXPECT_EQ(error.find('\0'), std::string::npos);
  EXPECT_EQ(error.rfind("s.txt:2: ", 0), 0u) << error;
  EXPECT_NE(error.find("'screen\\x00shot x'"), std::string::npos) << error;
  EXPECT_NE(error.find("NUL byte at column 7"), std::string::npos) << error;
  // Other control bytes of a quoted word are made visible too.
  EXPECT_NE(errorOf("gi \x1b[2Joff\n").find("'\\x1b[2Joff'"), std::string::npos) << errorOf("gi \x1b[2Joff\n");
}

TEST(ViewerScript, ACameraTooFarFromTheOriginForTheViewersFloatsIsRefusedWithItsLine) {
  // One unit ahead of 1e9 is 1e9 in 32-bit floats: the view direction was
  // NaN, refused by the renderer without the script's line.
  for (const char* line : {"camera 0 0 1e9 0 0 0\n", "pose 0 0 1e9 0 0 0\n", "camera 1e8 0 0 0 0 0\n"}) {
    const std::string error = errorOf(std::string("wait 1\n") + line);
    EXPECT_EQ(error.rfind("s.txt:2: the camera at (", 0), 0u) << line << error;
    EXPECT_NE(error.find("too far from the origin"), std::string::npos) << line << error;
    EXPECT_NE(error.find("lost to rounding"), std::string::npos) << line << error;
    EXPECT_EQ(error.find("nan"), std::string::npos) << line << error;
  }
  // Far enough to turn the view visibly: the turn is named.
  const std::string turned = errorOf("camera 1000000 0 0 0 1000000 0\n");
  EXPECT_NE(turned.find("would turn the view by"), std::string::npos) << turned;
  // A scene's own scale, and a room's, parse.
  EXPECT_EQ(errorOf("camera 0 1 5 0 1 0\ncamera 500 300 -800 0 0 0\npose 2000 10 0 0 0 0\n"), "");
}

TEST(ViewerScriptPlayer, ACommandThatReadsTheFrameWaitsForTheFirstFrame) {
  using bounce::viewer::ScriptCommand;
  using bounce::viewer::ScriptPlayer;
  for (const char* reader : {"click 1 2", "inspect 1 2", "screenshot x", "measure"}) {
    const auto script = parseScript(std::string("camera 0 1 5 0 1 0\n") + reader + "\nwait 2\n", "s.txt");
    ScriptPlayer player(script);
    std::vector<Kind> ran;
    const ScriptPlayer::Execute execute = [&](const ScriptCommand& c) {
      ran.push_back(c.kind);
      return false;
    };
    bounce::viewer::FlyInput input;
    // Before the first frame: the camera is placed, the reader waits.
    EXPECT_TRUE(player.step(input, execute).running) << reader;
    EXPECT_EQ(ran, std::vector<Kind>{Kind::Camera}) << reader;
    // After it, the reader runs, then the wait's first frame.
    EXPECT_TRUE(player.step(input, execute).running) << reader;
    ASSERT_EQ(ran.size(), 2u) << reader;
    EXPECT_EQ(ran[1], script[1].kind) << reader;
    EXPECT_TRUE(player.step(input, execute).running) << reader;
    EXPECT_FALSE(player.step(input, execute).running) << reader;
    EXPECT_EQ(ran.size(), 2u) << reader;
  }
  // Commands that do not read the frame run before it, and after the first
  // frame a reader runs at once.
  const auto script = parseScript("set diffuse.spatial_radius 4\nwait 1\nclick 0 0\n", "s.txt");
  ScriptPlayer player(script);
  std::vector<Kind> ran;
  const ScriptPlayer::Execute execute = [&](const ScriptCommand& c) {
    ran.push_back(c.kind);
    return false;
  };
  bounce::viewer::FlyInput input;
  EXPECT_TRUE(player.step(input, execute).running);
  EXPECT_EQ(ran, std::vector<Kind>{Kind::Set});
  EXPECT_FALSE(player.step(input, execute).running);
  EXPECT_EQ(ran, (std::vector<Kind>{Kind::Set, Kind::Click}));
}

TEST(ViewerScript, SaveGltfTakesEveryNameWithAStemAndAGltfOrGlbExtension) {
  for (const char* name : {"x.glb", "x.gltf", "scene.edited.glb"}) {
    const auto script = parseScript(std::string("save-gltf ") + name + "\n", "s.txt");
    ASSERT_EQ(script.size(), 1u) << name;
    EXPECT_EQ(script[0].words.at(0), name);
  }
  for (const char* name : {".glb", ".gltf", "x.png", "xglb"})
    EXPECT_NE(errorOf(std::string("save-gltf ") + name + "\n").find("not a plain file name"), std::string::npos)
        << name;
}

TEST(ViewerScript, OnlyARegularFileOfBoundedSizeIsRead) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("bounce_script_files_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto errorLoading = [](const std::filesystem::path& file) -> std::string {
    try {
      bounce::viewer::loadScript(file);
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  };
  // A FIFO nobody writes would block the read forever; /dev/zero never ends.
  const std::filesystem::path fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(errorLoading(fifo), fifo.string() + ": not a regular file");
  EXPECT_EQ(errorLoading("/dev/zero"), "/dev/zero: not a regular file");
  EXPECT_EQ(errorLoading(dir), dir.string() + ": not a regular file");
  const std::filesystem::path big = dir / "big.txt";
  {
    std::ofstream out(big);
    const std::string line = "wait 1\n";
    for (std::uintmax_t written = 0; written <= bounce::viewer::kMaxScriptBytes; written += line.size()) out << line;
  }
  EXPECT_NE(errorLoading(big).find("at most 16777216 are read"), std::string::npos) << errorLoading(big);
  const std::filesystem::path small = dir / "small.txt";
  std::ofstream(small) << "wait 3\nquit\n";
  EXPECT_EQ(errorLoading(small), "");
  EXPECT_EQ(bounce::viewer::loadScript(small).size(), 2u);
  std::filesystem::remove_all(dir);
}

TEST(ViewerScript, AMissingFileIsAnErrorNamingIt) {
  try {
    bounce::viewer::loadScript("/nonexistent/bounce-script.txt");
    FAIL() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/bounce-script.txt"), std::string::npos);
  }
}

TEST(ViewerFlyCamera, KeysMoveAlongTheViewAndTheMouseTurnsWithoutRolling) {
  bounce::scene::CameraPose pose;
  pose.position = {0.0f, 1.0f, 5.0f};
  pose.target = {0.0f, 1.0f, 0.0f};
  bounce::viewer::FlyCamera camera(pose, 20.0f);
  EXPECT_FLOAT_EQ(camera.speed(), 2.0f);  // a tenth of the scene a second
  bounce::viewer::FlyInput forward;
  forward.forward = true;
  EXPECT_TRUE(camera.update(forward, 0.5f));
  EXPECT_NEAR(camera.pose().position.z, 4.0f, 1e-5f);
  EXPECT_NEAR(camera.pose().position.y, 1.0f, 1e-5f);
  forward.fast = true;
  camera.update(forward, 0.5f);
  EXPECT_NEAR(camera.pose().position.z, 0.0f, 1e-5f);  // shift: 4x

  bounce::viewer::FlyInput turn;
  turn.turnPixels = {-100.0f, 0.0f};  // a drag to the left turns left (towards -x)
  camera.update(turn, 0.0f);
  const glm::vec3 look = camera.pose().target - camera.pose().position;
  EXPECT_NEAR(glm::length(look), 1.0f, 1e-5f);
  EXPECT_NEAR(look.y, 0.0f, 1e-5f);
  EXPECT_LT(look.x, -0.2f);
  // Pitch stops short of straight up, whatever the drag.
  turn.turnPixels = {0.0f, -1.0e6f};
  camera.update(turn, 0.0f);
  const glm::vec3 up = glm::normalize(camera.pose().target - camera.pose().position);
  EXPECT_GT(up.y, 0.99f);
  EXPECT_LT(up.y, 1.0f);
  bounce::viewer::FlyInput wheel;
  wheel.wheel = 2.0f;
  camera.update(wheel, 0.0f);
  EXPECT_NEAR(camera.speed(), 2.0f * 1.44f, 1e-4f);
}

TEST(ViewerPanels, SavedSettingsLoadBackToTheSameSettings) {
  bounce::gi::Settings edited;
  bounce::gi::applySetting(edited, "diffuse.spatial_radius", "12");
  bounce::gi::applySetting(edited, "denoise.enabled", "off");
  bounce::gi::applySetting(edited, "restir", "off");
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("bounce_viewer_settings_" + std::to_string(::getpid()) + ".json");
  std::ofstream(file) << bounce::viewer::settingsJson(edited);
  bounce::gi::Settings loaded;
  bounce::gi::applySettingsFile(loaded, file);
  std::filesystem::remove(file);
  for (const bounce::gi::SettingInfo& info : bounce::gi::settingKeys())
    EXPECT_EQ(bounce::gi::settingValue(loaded, info.key), bounce::gi::settingValue(edited, info.key)) << info.key;
}

}  // namespace
