#include "gi/frame_constants.h"

#include <cmath>
#include <string>

#include <glm/gtc/type_ptr.hpp>

namespace bounce::gi {
namespace {

bool finite(const float (&m)[16]) {
  for (float v : m)
    if (!std::isfinite(v)) return false;
  return true;
}

}  // namespace

shared::ScreenView screenView(const Camera& camera, const char* which) {
  const auto fail = [&](const std::string& why) { return Error(std::string("gi: ") + which + ": " + why); };
  if (!finite(camera.worldToView) || !finite(camera.viewToClip) || !std::isfinite(camera.jitter[0]) ||
      !std::isfinite(camera.jitter[1]))
    throw fail("camera matrices and jitter must be finite");
  const glm::mat4 worldToView = glm::make_mat4(camera.worldToView);
  const glm::mat4 p = glm::make_mat4(camera.viewToClip);
  if (!(p[0][0] > 0.0f) || p[1][1] == 0.0f || std::abs(p[2][3] + 1.0f) > 1e-5f || std::abs(p[3][3]) > 1e-6f)
    throw fail("viewToClip must be a perspective projection looking down -Z (as glm::perspective makes)");
  if (std::abs(p[2][0]) > 1e-6f || std::abs(p[2][1]) > 1e-6f)
    throw fail("viewToClip must be symmetric; give sub-pixel jitter in Camera::jitter instead");
  const glm::mat4 viewToWorld = glm::inverse(worldToView);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(viewToWorld[c][r])) throw fail("worldToView is not invertible");
  return {worldToView, viewToWorld,
          glm::vec4(1.0f / p[0][0], 1.0f / std::abs(p[1][1]), camera.jitter[0], camera.jitter[1])};
}

std::vector<gpu::ResourceDecl> frameGroupDecls(GroupPart part) {
  std::vector<gpu::ResourceDecl> group = {
      {"gIn_Frame", gpu::Access::Read, VK_FORMAT_UNDEFINED, "cameras, render size, the engine's encodings",
       gpu::ResourceKind::UniformBuffer},
      {"gIn_ViewZ", gpu::Access::Read, VK_FORMAT_UNDEFINED, "the engine's viewZ: 0 = background",
       gpu::ResourceKind::SampledImage},
      {"gIn_NormalRoughness", gpu::Access::Read, VK_FORMAT_UNDEFINED,
       "the engine's world normal and roughness (either encoding)", gpu::ResourceKind::SampledImage}};
  group.resize(std::size_t(part));
  return group;
}

gpu::ConstantsDecl frameConstantsLayout() {
  using shared::GiFrameConstants;
  return BOUNCE_CONSTANTS_LAYOUT("gIn_Frame", GiFrameConstants, view, previousView, renderSize, halfSize, motionScale,
                                 frameIndex, noHistory, seed, normalEncoding, hasEmissive,
                                 hasMaterialId, declaredLightChange);
}

FrameGroup::FrameGroup(gpu::Buffer& frameConstants, gpu::Image& viewZ, gpu::Image& normalRoughness,
                       VkSampler nearest)
    : binds_{gpu::Bind("gIn_Frame", frameConstants), gpu::Bind("gIn_ViewZ", viewZ, nearest),
             gpu::Bind("gIn_NormalRoughness", normalRoughness, nearest)} {}

}  // namespace bounce::gi
