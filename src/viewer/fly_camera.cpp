#include "viewer/fly_camera.h"

#include <algorithm>
#include <cmath>

namespace bounce::viewer {

bool samePose(const scene::CameraPose& a, const scene::CameraPose& b) {
  return a.position == b.position && a.target == b.target && a.up == b.up && a.fovYDegrees == b.fovYDegrees;
}
namespace {

// Pitch stops this short of the up vector, where yaw would lose its axis.
constexpr float kMaxPitch = 1.55f;  // radians, about 89 degrees

}  // namespace

FlyCamera::FlyCamera(const scene::CameraPose& pose, float sceneSize)
    : speed_(std::isfinite(sceneSize) && sceneSize > 0.0f ? 0.1f * sceneSize : 1.0f) {
  setPose(pose);
}

void FlyCamera::setPose(const scene::CameraPose& pose) {
  pose_ = pose;
  pose_.up = glm::normalize(pose.up);
  pose_.target = pose.position + glm::normalize(pose.target - pose.position);
}

bool FlyCamera::update(const FlyInput& input, float seconds) {
  if (input.wheel != 0.0f) speed_ *= std::pow(kWheelStep, input.wheel);
  const glm::vec3 up = pose_.up;
  glm::vec3 forward = glm::normalize(pose_.target - pose_.position);
  bool changed = false;
  if (input.turnPixels != glm::vec2(0.0f)) {
    // Yaw about up, then pitch within (-kMaxPitch, kMaxPitch) of the horizon.
    float pitch = std::asin(std::clamp(glm::dot(forward, up), -1.0f, 1.0f));
    glm::vec3 horizontal = glm::normalize(forward - up * glm::dot(forward, up));
    const glm::vec3 side = glm::normalize(glm::cross(horizontal, up));
    const float yaw = input.turnPixels.x * kTurnPerPixel;  // a drag to the right turns right
    horizontal = glm::normalize(horizontal * std::cos(yaw) + side * std::sin(yaw));
    pitch = std::clamp(pitch - input.turnPixels.y * kTurnPerPixel, -kMaxPitch, kMaxPitch);
    forward = horizontal * std::cos(pitch) + up * std::sin(pitch);
    changed = true;
  }
  const glm::vec3 side = glm::normalize(glm::cross(forward, up));
  glm::vec3 move(0.0f);
  if (input.forward) move += forward;
  if (input.back) move -= forward;
  if (input.right) move += side;
  if (input.left) move -= side;
  if (input.up) move += up;
  if (input.down) move -= up;
  if (move != glm::vec3(0.0f) && seconds > 0.0f) {
    pose_.position += glm::normalize(move) * speed_ * (input.fast ? kFastFactor : 1.0f) * seconds;
    changed = true;
  }
  pose_.target = pose_.position + forward;
  return changed;
}

}  // namespace bounce::viewer
