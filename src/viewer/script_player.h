// bounce view --script: the script's clock. It runs the commands until one
// takes frames (wait, key, play, stages, window), holds keys and waits over
// the frames they span, and hands every command that changes the session
// to the session (Session::execute in viewer.cpp). A command that reads the
// frame (click, inspect, screenshot, measure) waits for the first frame to
// be rendered: before it there is none to read.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>

#include "viewer/fly_camera.h"
#include "viewer/script.h"

namespace bounce::viewer {

class ScriptPlayer {
 public:
  explicit ScriptPlayer(std::span<const ScriptCommand> script) : script_(script) {}

  // Runs a command the player does not keep time for (all but wait, key,
  // look and quit; play too, after which the player waits its frames);
  // returns true when the command takes the next frame (stages, window).
  using Execute = std::function<bool(const ScriptCommand&)>;
  struct Step {
    bool running = true;       // false: the script has ended (or quit)
    bool stopPlaying = false;  // a play command has had its frames: the camera path stops
  };
  // Before a frame: `input` gets the held key and the looks of this frame.
  // Every call but the last (running false) is followed by a frame.
  Step step(FlyInput& input, const Execute& execute);

  // Whether a command reads the last rendered frame, so that it cannot run
  // before the first one.
  static bool readsFrame(const ScriptCommand& command);

 private:
  std::span<const ScriptCommand> script_;
  std::size_t next_ = 0;
  std::uint32_t waitFrames_ = 0;
  std::string heldKey_;
  std::uint32_t heldFrames_ = 0;
  bool playing_ = false;
  bool framed_ = false;  // a frame has been rendered: an earlier step returned running
};

}  // namespace bounce::viewer
