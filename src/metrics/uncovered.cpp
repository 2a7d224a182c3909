#include "metrics/uncovered.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace bounce::metrics {
namespace {

void checkFrame(const FrameSurfaces& frame, const char* which) {
  const std::size_t pixels = std::size_t(std::max(frame.width, 0)) * std::size_t(std::max(frame.height, 0));
  if (frame.width <= 0 || frame.height <= 0) throw std::invalid_argument(std::string(which) + " frame has no pixels");
  if (frame.viewZ.size() != pixels || frame.normal.size() != pixels || frame.instance.size() != pixels)
    throw std::invalid_argument(std::string(which) + " frame's per-pixel values are not " +
                                std::to_string(frame.width) + "x" + std::to_string(frame.height));
}

}  // namespace

shared::ScreenView screenViewOf(glm::vec3 position, glm::vec3 target, glm::vec3 up, float fovYDegrees, int width,
                                int height) {
  // The basis of render::gpuCamera and render::giCamera.
  const glm::vec3 forward = glm::normalize(target - position);
  const glm::vec3 right = glm::normalize(glm::cross(forward, up));
  const glm::vec3 trueUp = glm::cross(right, forward);
  glm::mat4 viewToWorld(1.0f);
  viewToWorld[0] = glm::vec4(right, 0.0f);
  viewToWorld[1] = glm::vec4(trueUp, 0.0f);
  viewToWorld[2] = glm::vec4(-forward, 0.0f);
  viewToWorld[3] = glm::vec4(position, 1.0f);
  const float tanY = std::tan(glm::radians(fovYDegrees) * 0.5f);
  return {glm::inverse(viewToWorld), viewToWorld, glm::vec4(tanY * float(width) / float(height), tanY, 0.0f, 0.0f)};
}

std::size_t Reprojection::count(PixelHistory what) const {
  return std::size_t(std::count(history.begin(), history.end(), what));
}

Reprojection reproject(const FrameSurfaces& previous, const FrameSurfaces& current) {
  checkFrame(previous, "the previous");
  checkFrame(current, "the current");
  if (previous.width != current.width || previous.height != current.height)
    throw std::invalid_argument("the two frames differ in size");
  const int width = current.width, height = current.height;
  const glm::vec2 size{float(width), float(height)};

  // Per instance: current world -> previous world, for points and normals.
  // An instance either frame lacks is taken as still.
  const std::size_t instances = std::min(previous.objectToWorld.size(), current.objectToWorld.size());
  std::vector<glm::mat4> pointToPrevious(instances);
  std::vector<glm::mat3> normalToPrevious(instances);
  for (std::size_t i = 0; i < instances; ++i) {
    pointToPrevious[i] = previous.objectToWorld[i] * glm::inverse(current.objectToWorld[i]);
    normalToPrevious[i] = glm::transpose(glm::inverse(glm::mat3(pointToPrevious[i])));
  }

  Reprojection result;
  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  result.history.assign(pixels, PixelHistory::Background);
  result.source.assign(pixels, -1);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t p = std::size_t(y) * std::size_t(width) + std::size_t(x);
      const float viewZ = current.viewZ[p];
      const std::uint32_t instance = current.instance[p];
      if (!(viewZ > 0.0f) || instance == kNoInstance) continue;
      glm::vec3 point = shared::reconstructPosition(current.view, glm::vec2(float(x), float(y)), viewZ, size);
      glm::vec3 normal = current.normal[p];
      if (instance < instances) {
        point = glm::vec3(pointToPrevious[instance] * glm::vec4(point, 1.0f));
        normal = normalToPrevious[instance] * normal;
      }
      const float normalLength = glm::length(normal);
      normal = normalLength > 0.0f ? normal / normalLength : glm::vec3(0.0f);
      const glm::vec3 q = shared::projectToScreen(previous.view, point, size);
      if (!(q.z > 0.0f) || !(q.x >= 0.0f && q.x < size.x && q.y >= 0.0f && q.y < size.y)) {
        result.history[p] = PixelHistory::Uncovered;
        continue;
      }
      // The 2x2 previous pixels whose centres surround the point, those
      // with a bilinear weight above kMinTapWeight (a point at a pixel's
      // centre was seen by that pixel alone, not by its neighbours).
      const int x0 = int(std::floor(q.x - 0.5f)), y0 = int(std::floor(q.y - 0.5f));
      const float fx = q.x - 0.5f - float(x0), fy = q.y - 0.5f - float(y0);
      // The closest plane distance decides; the source is the passing tap
      // nearest the point (on a still surface the pixel itself).
      float closest = std::numeric_limits<float>::infinity(), nearest = std::numeric_limits<float>::infinity();
      std::int32_t source = -1;
      for (int ty = y0; ty <= y0 + 1; ++ty)
        for (int tx = x0; tx <= x0 + 1; ++tx) {
          const float weight = (tx == x0 ? 1.0f - fx : fx) * (ty == y0 ? 1.0f - fy : fy);
          if (tx < 0 || ty < 0 || tx >= width || ty >= height || weight <= kMinTapWeight) continue;
          const std::size_t t = std::size_t(ty) * std::size_t(width) + std::size_t(tx);
          if (previous.instance[t] != instance || !(previous.viewZ[t] > 0.0f)) continue;
          const glm::vec3 tap =
              shared::reconstructPosition(previous.view, glm::vec2(float(tx), float(ty)), previous.viewZ[t], size);
          const float distance = std::abs(glm::dot(normal, tap - point)) / q.z;
          closest = std::min(closest, distance);
          const glm::vec2 offset = glm::vec2(float(tx) + 0.5f, float(ty) + 0.5f) - glm::vec2(q.x, q.y);
          const float screenDistance = glm::dot(offset, offset);
          if (distance < kSeenPlaneDistance && screenDistance < nearest) {
            nearest = screenDistance;
            source = std::int32_t(t);
          }
        }
      if (closest < kSeenPlaneDistance) {
        result.history[p] = PixelHistory::Seen;
        result.source[p] = source;
      } else {
        result.history[p] = closest > kUncoveredPlaneDistance ? PixelHistory::Uncovered : PixelHistory::Unclear;
      }
    }
  return result;
}

std::vector<std::uint8_t> followRegion(const std::vector<std::uint8_t>& region, const Reprojection& step) {
  std::vector<std::uint8_t> followed(step.history.size(), 0);
  for (std::size_t p = 0; p < step.history.size(); ++p) {
    const std::int32_t source = step.source[p];
    if (step.history[p] == PixelHistory::Seen && source >= 0 && std::size_t(source) < region.size())
      followed[p] = region[std::size_t(source)];
  }
  return followed;
}

}  // namespace bounce::metrics
