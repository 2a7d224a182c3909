// bounce view --record: the session written as a script as it goes
// (viewer/script.h reads it back): what the panels changed, the camera's
// poses, the waits between them; replaying it makes the same frames.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <string>

#include "bounce/gi_settings.h"
#include "scene/camera_path.h"
#include "viewer/panels.h"

namespace bounce::viewer {

// Numbers as a recorded script writes them: each after a space, in as many
// digits as give the same float back.
std::string scriptNumbers(std::initializer_list<float> values);

class SessionRecorder {
 public:
  // `file` empty: nothing is recorded (every call does nothing). The
  // session starts with `settings` in `mode`.
  SessionRecorder(const std::filesystem::path& file, const std::string& sceneName, const gi::Settings& settings,
                  GiMode mode);
  bool active() const { return out_.is_open(); }
  // A command, after the waits for the frames since the last one.
  void line(const std::string& command);
  // What the panels changed since the last frame, as the commands that make it.
  void state(const PanelState& panels);
  // A rendered frame: its pose when the camera moved (camera on a cut,
  // pose otherwise), and one more frame to wait.
  void frame(const scene::CameraPose& pose, bool cut);
  // Writes the last waits and closes the script.
  void finish();

 private:
  std::filesystem::path file_;
  std::ofstream out_;
  std::uint32_t waits_ = 0;
  std::optional<scene::CameraPose> pose_;
  gi::Settings settings_;
  GiMode mode_;
  SplitMode split_ = SplitMode::None;
  std::string stage_ = "final";
  bool hidden_ = false;
};

}  // namespace bounce::viewer
