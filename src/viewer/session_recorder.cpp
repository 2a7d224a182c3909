#include "viewer/session_recorder.h"

#include <cstdio>
#include <stdexcept>

#include "viewer/fly_camera.h"

namespace bounce::viewer {

std::string scriptNumbers(std::initializer_list<float> values) {
  std::string text;
  char number[32];
  for (float v : values) {
    std::snprintf(number, sizeof number, " %.9g", double(v));
    text += number;
  }
  return text;
}

SessionRecorder::SessionRecorder(const std::filesystem::path& file, const std::string& sceneName,
                                 const gi::Settings& settings, GiMode mode)
    : file_(file), settings_(settings), mode_(mode) {
  if (file.empty()) return;
  out_.open(file, std::ios::binary);
  if (!out_) throw std::runtime_error(file.string() + ": cannot write the recording");
  out_ << "# bounce view " << sceneName << ", recorded (replay: bounce view ... --script " << file.filename().string()
       << ")\n";
}

void SessionRecorder::line(const std::string& command) {
  if (!active()) return;
  if (waits_ > 0) out_ << "wait " << waits_ << "\n";
  waits_ = 0;
  out_ << command << "\n";
}

void SessionRecorder::state(const PanelState& panels) {
  if (!active()) return;
  if (panels.mode != mode_) line(std::string("gi ") + giModeName(panels.mode));
  mode_ = panels.mode;
  for (const gi::SettingInfo& info : gi::settingKeys()) {
    const std::string value = gi::settingValue(panels.settings, info.key);
    if (value != gi::settingValue(settings_, info.key)) line("set " + info.key + " " + value);
  }
  settings_ = panels.settings;
  if (panels.split != split_) line(std::string("split ") + splitModeName(panels.split));
  split_ = panels.split;
  const std::string& stage = panels.stageNames[std::size_t(panels.stage)];
  if (stage != stage_) line("stage " + stage);
  stage_ = stage;
  if (panels.hidden != hidden_) line(panels.hidden ? "panels off" : "panels on");
  hidden_ = panels.hidden;
}

void SessionRecorder::frame(const scene::CameraPose& pose, bool cut) {
  if (!active()) return;
  if (cut || !pose_ || !samePose(pose, *pose_)) {
    line(std::string(cut ? "camera" : "pose") + scriptNumbers({pose.position.x, pose.position.y, pose.position.z,
                                                               pose.target.x, pose.target.y, pose.target.z}));
    pose_ = pose;
  }
  ++waits_;
}

void SessionRecorder::finish() {
  if (!active()) return;
  if (waits_ > 0) out_ << "wait " << waits_ << "\n";
  waits_ = 0;
  out_.close();
  std::printf("wrote %s (the session as a script)\n", file_.c_str());
}

}  // namespace bounce::viewer
