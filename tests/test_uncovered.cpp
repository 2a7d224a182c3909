// metrics/uncovered.h, on frames ray-cast here on the CPU: a floor and a
// box, the box moved or the camera turned between two frames, and the
// pixels newly uncovered compared with what the geometry says.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "metrics/uncovered.h"

namespace {

using bounce::metrics::FrameSurfaces;
using bounce::metrics::PixelHistory;

constexpr int kWidth = 96, kHeight = 64;
const glm::vec3 kBoxMin(-0.5f, 0.0f, -0.5f), kBoxMax(0.5f, 1.0f, 0.5f);  // in the box's object space

struct Camera {
  glm::vec3 position{0.0f, 2.0f, 5.0f}, target{0.0f, 0.3f, 0.0f};
};

struct Hit {
  float t = std::numeric_limits<float>::infinity();
  glm::vec3 normal{0.0f};
  std::uint32_t instance = bounce::metrics::kNoInstance;
};

// A ray against the box (instance 1, placed by `boxToWorld`, a translation) and the floor y = 0 (instance 0).
Hit cast(glm::vec3 origin, glm::vec3 direction, const glm::mat4& boxToWorld) {
  Hit hit;
  if (direction.y < 0.0f) {
    hit.t = -origin.y / direction.y;
    hit.normal = glm::vec3(0.0f, 1.0f, 0.0f);
    hit.instance = 0;
  }
  const glm::vec3 lo = glm::vec3(boxToWorld * glm::vec4(kBoxMin, 1.0f));
  const glm::vec3 hi = glm::vec3(boxToWorld * glm::vec4(kBoxMax, 1.0f));
  float near = 0.0f, far = std::numeric_limits<float>::infinity();
  int axis = -1;
  for (int a = 0; a < 3; ++a) {
    float t0 = (lo[a] - origin[a]) / direction[a], t1 = (hi[a] - origin[a]) / direction[a];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > near) near = t0, axis = a;
    far = std::min(far, t1);
  }
  if (axis >= 0 && near <= far && near < hit.t) {
    hit.t = near;
    hit.normal = glm::vec3(0.0f);
    hit.normal[axis] = direction[axis] > 0.0f ? -1.0f : 1.0f;
    hit.instance = 1;
  }
  return hit;
}

FrameSurfaces render(const Camera& camera, const glm::mat4& boxToWorld) {
  FrameSurfaces frame;
  frame.width = kWidth;
  frame.height = kHeight;
  frame.view = bounce::metrics::screenViewOf(camera.position, camera.target, glm::vec3(0.0f, 1.0f, 0.0f), 50.0f, kWidth,
                                             kHeight);
  const glm::vec3 forward = glm::normalize(camera.target - camera.position);
  const glm::vec2 size(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const glm::vec3 direction = bounce::shared::pixelRayDirection(frame.view, glm::vec2(x, y), size);
      const Hit hit = cast(camera.position, direction, boxToWorld);
      const bool surface = std::isfinite(hit.t);
      frame.viewZ.push_back(surface ? hit.t * glm::dot(direction, forward) : 0.0f);
      frame.normal.push_back(hit.normal);
      frame.instance.push_back(hit.instance);
    }
  frame.objectToWorld = {glm::mat4(1.0f), boxToWorld};
  return frame;
}

glm::mat4 boxAt(float x) { return glm::translate(glm::mat4(1.0f), glm::vec3(x, 0.0f, 0.0f)); }

// Whether the previous frame saw the world point: in its view and not hidden behind the box.
bool visibleIn(const FrameSurfaces& frame, const Camera& camera, const glm::mat4& boxToWorld, glm::vec3 point) {
  const glm::vec3 q = bounce::shared::projectToScreen(frame.view, point, glm::vec2(kWidth, kHeight));
  if (!(q.z > 0.0f) || q.x < 0.0f || q.y < 0.0f || q.x >= kWidth || q.y >= kHeight) return false;
  const glm::vec3 toPoint = point - camera.position;
  const float distance = glm::length(toPoint);
  return cast(camera.position, toPoint / distance, boxToWorld).t > distance * (1.0f - 1e-4f);
}

// How many surface pixels the reprojection gets right against the geometry,
// and how many it calls unclear; those it gets wrong must be silhouettes.
struct Agreement {
  int right = 0, wrong = 0, unclear = 0, uncovered = 0;
};

Agreement check(const FrameSurfaces& before, const Camera& cameraBefore, const glm::mat4& boxBefore,
                const FrameSurfaces& now, const glm::mat4& boxNow) {
  const bounce::metrics::Reprojection step = bounce::metrics::reproject(before, now);
  Agreement agreement;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t p = std::size_t(y) * kWidth + std::size_t(x);
      if (now.viewZ[p] <= 0.0f) {
        EXPECT_EQ(step.history[p], PixelHistory::Background);
        continue;
      }
      // The point in the frame before: the box's points moved with it.
      glm::vec3 point =
          bounce::shared::reconstructPosition(now.view, glm::vec2(x, y), now.viewZ[p], glm::vec2(kWidth, kHeight));
      if (now.instance[p] == 1) point = glm::vec3(boxBefore * glm::inverse(boxNow) * glm::vec4(point, 1.0f));
      const bool truth = !visibleIn(before, cameraBefore, boxBefore, point);
      if (step.history[p] == PixelHistory::Unclear) {
        ++agreement.unclear;
        continue;
      }
      const bool said = step.history[p] == PixelHistory::Uncovered;
      agreement.uncovered += said;
      (said == truth ? agreement.right : agreement.wrong) += 1;
      if (!said) {
        EXPECT_GE(step.source[p], 0) << "a seen pixel names where it was seen";
      }
    }
  return agreement;
}

TEST(Uncovered, AMovingBoxUncoversTheFloorBehindIt) {
  const Camera camera;
  const FrameSurfaces before = render(camera, boxAt(0.0f)), now = render(camera, boxAt(0.3f));
  const Agreement a = check(before, camera, boxAt(0.0f), now, boxAt(0.3f));
  std::printf("moving box: %d right, %d wrong, %d unclear, %d uncovered\n", a.right, a.wrong, a.unclear, a.uncovered);
  EXPECT_GT(a.uncovered, 50);
  EXPECT_LE(a.wrong + a.unclear, a.uncovered / 10) << "only silhouette pixels may be misjudged";
}

TEST(Uncovered, AFastTurnUncoversTheScreenEdge) {
  const Camera before;
  Camera turned = before;
  // 15 degrees to the left about the vertical through the camera.
  const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), glm::radians(15.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  turned.target = before.position + glm::vec3(turn * glm::vec4(before.target - before.position, 0.0f));
  const FrameSurfaces then = render(before, boxAt(0.0f)), now = render(turned, boxAt(0.0f));
  const Agreement a = check(then, before, boxAt(0.0f), now, boxAt(0.0f));
  std::printf("turn: %d right, %d wrong, %d unclear, %d uncovered\n", a.right, a.wrong, a.unclear, a.uncovered);
  EXPECT_GT(a.uncovered, kHeight * 5);
  EXPECT_LE(a.wrong + a.unclear, kHeight * 2) << "at most the pixels along the old view's edge";
}

TEST(Uncovered, AStillFrameUncoversNothingAndFollowsEveryPixelToItself) {
  const Camera camera;
  const FrameSurfaces frame = render(camera, boxAt(0.0f));
  const bounce::metrics::Reprojection step = bounce::metrics::reproject(frame, frame);
  EXPECT_EQ(step.count(PixelHistory::Uncovered) + step.count(PixelHistory::Unclear), 0u);
  for (std::size_t p = 0; p < step.history.size(); ++p)
    if (step.history[p] == PixelHistory::Seen) {
      EXPECT_EQ(step.source[p], std::int32_t(p));
    }
}

TEST(Uncovered, ARegionFollowsTheSurfaceItShows) {
  const Camera camera;
  const FrameSurfaces before = render(camera, boxAt(0.0f)), now = render(camera, boxAt(0.25f));
  std::vector<std::uint8_t> box(before.instance.size());
  for (std::size_t p = 0; p < box.size(); ++p) box[p] = before.instance[p] == 1 ? 1 : 0;
  const std::vector<std::uint8_t> followed =
      bounce::metrics::followRegion(box, bounce::metrics::reproject(before, now));
  // Every followed pixel shows the box now, and most of the box is followed
  // (all but the faces the move turned into view).
  int boxNow = 0, inRegion = 0;
  for (std::size_t p = 0; p < followed.size(); ++p) {
    boxNow += now.instance[p] == 1;
    inRegion += followed[p];
    if (followed[p]) {
      EXPECT_EQ(now.instance[p], 1u) << "pixel " << p;
    }
  }
  EXPECT_GT(inRegion, boxNow * 8 / 10);
}

TEST(Uncovered, FramesOfDifferentSizesAreRefused) {
  const Camera camera;
  FrameSurfaces a = render(camera, boxAt(0.0f)), b = a;
  b.width = kWidth / 2;
  EXPECT_THROW(bounce::metrics::reproject(a, b), std::invalid_argument);
  b = a;
  b.normal.pop_back();
  EXPECT_THROW(bounce::metrics::reproject(a, b), std::invalid_argument);
}

}  // namespace
