#include "render/gi_inputs.h"

namespace bounce::render {

gi::Camera giCamera(const scene::CameraPose& pose, std::uint32_t width, std::uint32_t height, glm::vec2 jitter) {
  // The same basis as gpuCamera(), unscaled: the renderer's rays and the
  // library's reconstruction must agree to the last bit that matters.
  const glm::vec3 forward = glm::normalize(pose.target - pose.position);
  const glm::vec3 right = glm::normalize(glm::cross(forward, pose.up));
  const glm::vec3 up = glm::cross(right, forward);
  return gi::cameraFromBasis(pose.position, right, up, forward, glm::radians(pose.fovYDegrees),
                             float(width) / float(height), jitter);
}

gi::FrameInputs giFrameInputs(FrameRenderer& renderer, std::uint64_t frameIndex, const FrameView& view,
                              const FrameView& previous, bool jitter) {
  const std::uint32_t w = renderer.width(), h = renderer.height();
  gi::FrameInputs inputs;
  inputs.viewZ = &renderer.viewZ();
  inputs.normalRoughness = &renderer.normalRoughness();
  inputs.baseColorMetallic = &renderer.baseColorMetallic();
  inputs.motion = &renderer.motion();
  inputs.direct = &renderer.direct();  // holds the emission too
  inputs.environment = &renderer.environment().radiance();
  inputs.environmentSampler = renderer.environment().sampler();
  inputs.camera = giCamera(view.camera, w, h, jitter ? jitterOffset(frameIndex) : glm::vec2(0.0f));
  inputs.previousCamera =
      giCamera(previous.camera, w, h, jitter && frameIndex > 0 ? jitterOffset(frameIndex - 1) : glm::vec2(0.0f));
  inputs.frameIndex = frameIndex;
  inputs.cameraCut = view.cut;
  return inputs;
}

}  // namespace bounce::render
