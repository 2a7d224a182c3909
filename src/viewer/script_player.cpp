#include "viewer/script_player.h"

namespace bounce::viewer {

bool ScriptPlayer::readsFrame(const ScriptCommand& command) {
  using Kind = ScriptCommand::Kind;
  return command.kind == Kind::Click || command.kind == Kind::Inspect || command.kind == Kind::Screenshot ||
         command.kind == Kind::Measure;
}

ScriptPlayer::Step ScriptPlayer::step(FlyInput& input, const Execute& execute) {
  // The session renders a frame after every step that keeps the script running.
  const bool framed = framed_;
  framed_ = true;
  Step result;
  if (waitFrames_ > 0) {
    --waitFrames_;
    return result;
  }
  if (playing_) {
    result.stopPlaying = true;
    playing_ = false;
  }
  if (heldFrames_ > 0) {
    --heldFrames_;
    input.forward = heldKey_ == "w";
    input.left = heldKey_ == "a";
    input.back = heldKey_ == "s";
    input.right = heldKey_ == "d";
    input.down = heldKey_ == "q";
    input.up = heldKey_ == "e";
    input.fast = heldKey_ == "shift";
    return result;
  }
  using Kind = ScriptCommand::Kind;
  while (next_ < script_.size()) {
    // A click on the first line would otherwise pick from ids no frame has
    // written (material 0 everywhere) and a screenshot would find no frame:
    // the command waits for the first frame, which the commands before it
    // (a camera, a setting) have already shaped.
    if (!framed && readsFrame(script_[next_])) return result;
    const ScriptCommand& c = script_[next_++];
    switch (c.kind) {
      case Kind::Wait:
        waitFrames_ = std::uint32_t(c.numbers[0]) - 1;
        return result;
      case Kind::Key: {
        heldKey_ = c.words[0];
        heldFrames_ = std::uint32_t(c.numbers[0]);
        const Step held = step(input, execute);
        return {held.running, result.stopPlaying || held.stopPlaying};
      }
      case Kind::Look:
        input.turnPixels += glm::vec2(float(c.numbers[0]), float(c.numbers[1]));
        break;
      case Kind::Play:
        execute(c);
        playing_ = true;
        waitFrames_ = std::uint32_t(c.numbers[0]) - 1;
        return result;
      case Kind::Quit:
        result.running = false;
        return result;
      default:
        if (execute(c)) return result;
        break;
    }
  }
  result.running = false;
  return result;
}

}  // namespace bounce::viewer
