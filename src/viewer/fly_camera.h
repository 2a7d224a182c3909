// The viewer's fly camera: WASD moves along the view and sideways, Q and E
// down and up, shift moves faster, a mouse drag turns (yaw about the pose's
// up, pitch short of straight up or down), the wheel scales the speed. It
// keeps the pose's field of view and up vector; the target stays one unit
// ahead (the distance to it does not matter for the picture).
#pragma once

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace bounce::viewer {

// What the user held and did during one frame.
struct FlyInput {
  bool forward = false, back = false, left = false, right = false, down = false, up = false;
  bool fast = false;
  glm::vec2 turnPixels{0.0f};  // mouse drag this frame
  float wheel = 0.0f;          // scroll steps this frame
};

// Whether two poses are the same view (the reference restarts on any change).
bool samePose(const scene::CameraPose& a, const scene::CameraPose& b);

class FlyCamera {
 public:
  // `sceneSize`: the scene's bounding-box diagonal; the speed starts at a
  // tenth of it a second, so a room and a city both take seconds to cross.
  FlyCamera(const scene::CameraPose& pose, float sceneSize);

  // Moves by one frame of `seconds` under `input`; returns whether the pose changed.
  bool update(const FlyInput& input, float seconds);
  void setPose(const scene::CameraPose& pose);
  const scene::CameraPose& pose() const { return pose_; }
  float speed() const { return speed_; }  // world units a second

  // Radians a pixel of mouse drag turns.
  static constexpr float kTurnPerPixel = 0.0025f;
  // How much one wheel step scales the speed, and shift's factor.
  static constexpr float kWheelStep = 1.2f;
  static constexpr float kFastFactor = 4.0f;

 private:
  scene::CameraPose pose_;
  float speed_;
};

}  // namespace bounce::viewer
