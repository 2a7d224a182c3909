// Which pixels of a frame show surfaces that the frame before did not: the
// disocclusions (and the screen edges of a turning camera) where a temporal
// method has no history and must start over. Worked out on the CPU from two
// frames' G-buffers, cameras and instance transforms, independently of the
// GI library's own reprojection, so that `bounce ghosting` can measure how
// fast the library's error on such pixels returns to the level of the rest
// (docs/metrics.md, "bounce ghosting").
//
// A current pixel's surface point is moved to where it was in the previous
// frame (its instance's previous object-to-world times the inverse of its
// current one) and projected into the previous camera. It was seen when one
// of the 2x2 previous pixels around that point (those of a bilinear weight
// above kMinTapWeight) shows the same instance within a plane distance of
// kSeenPlaneDistance x viewZ of it (the distance
// of the previous pixel's surface point from the current surface's plane,
// moved alike: robust on surfaces seen at grazing angles, where viewZ
// changes fast from pixel to pixel). It is uncovered when the point was off
// screen or behind the previous camera, or when no such pixel comes within
// kUncoveredPlaneDistance x viewZ; anything between is unclear and counts
// for neither.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "shared/screen_view.glsl"

namespace bounce::metrics {

inline constexpr std::uint32_t kNoInstance = 0xffffffffu;
// Plane distances, as fractions of the point's viewZ in the previous frame.
inline constexpr float kSeenPlaneDistance = 0.01f;
inline constexpr float kUncoveredPlaneDistance = 0.05f;
// Previous pixels of a smaller bilinear weight at the point do not count
// (the GI library's history taps have the same cut-off).
inline constexpr float kMinTapWeight = 0.05f;

// One frame's surfaces, as the G-buffer and the scene describe them.
struct FrameSurfaces {
  int width = 0, height = 0;
  shared::ScreenView view{};             // the camera, without jitter
  std::vector<float> viewZ;              // per pixel; 0 = background
  std::vector<glm::vec3> normal;         // per pixel: the geometric normal, world space
  std::vector<std::uint32_t> instance;   // per pixel: the scene instance it shows, kNoInstance for background
  std::vector<glm::mat4> objectToWorld;  // per instance, at the frame's time
};

// The camera of a pose (position, target, up, vertical field of view in
// degrees) rendered at width x height, as the renderer builds its rays.
shared::ScreenView screenViewOf(glm::vec3 position, glm::vec3 target, glm::vec3 up, float fovYDegrees, int width,
                                int height);

enum class PixelHistory : std::uint8_t {
  Background,  // no surface (viewZ 0)
  Seen,        // the previous frame showed this surface point
  Uncovered,   // it did not: off screen or hidden behind something else
  Unclear,     // neither clearly (near a silhouette, or a plane distance between the two thresholds)
};

struct Reprojection {
  std::vector<PixelHistory> history;  // per current pixel
  std::vector<std::int32_t> source;   // Seen: the previous pixel that showed the point (of those within
                                      // kSeenPlaneDistance, the nearest on screen); else -1
  std::size_t count(PixelHistory what) const;
};

// Throws std::invalid_argument when the frames differ in size or their
// per-pixel vectors are not width x height long.
Reprojection reproject(const FrameSurfaces& previous, const FrameSurfaces& current);

// A set of pixels (1 = in) followed one frame on: the current pixels whose
// surface was seen in the previous frame on a pixel of `region`.
std::vector<std::uint8_t> followRegion(const std::vector<std::uint8_t>& region, const Reprojection& step);

}  // namespace bounce::metrics
