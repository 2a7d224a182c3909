// The analytic scene end to end on the GPU: G-buffer and direct sunlight
// against closed-form answers.
#include <gtest/gtest.h>

#include <cmath>

#include "gpu/frame_loop.h"
#include "gpu/transfer.h"
#include "gpu_test.h"
#include "render/analytic_scene.h"

namespace bounce::testing {
namespace {

// Odd sizes put a pixel centre exactly on the optical axis.
constexpr std::uint32_t kWidth = 81, kHeight = 61;

// One sphere of radius 0.5 at (0,1,0) under an overhead sun (elevation 90),
// so its shadow is the disk of radius 0.5 around the origin; the camera
// looks at the origin from (0,4,4), past the sphere.
render::AnalyticScene overheadSunScene(float elevation) {
  render::AnalyticScene scene;
  scene.groundColor = glm::vec3(0.8f, 0.4f, 0.2f);  // 204, 102, 51 of 255: exact in rgba8
  scene.spheres = {{{0.0f, 1.0f, 0.0f}, 0.5f, {0.5f, 0.5f, 0.5f}, 0.0f, 0.5f}};
  scene.sun.elevationDegrees = elevation;
  scene.sun.azimuthDegrees = 90.0f;  // from +X: a low sun throws the shadow sideways, in view
  scene.sun.illuminance = 2.5f;
  scene.sun.color = glm::vec3(1.0f);
  return scene;
}

render::Camera obliqueCamera() {
  render::Camera camera;
  camera.position = glm::vec3(0.0f, 4.0f, 4.0f);
  camera.target = glm::vec3(0.0f);
  camera.fovYDegrees = 40.0f;
  return camera;
}

struct Frame {
  io::ImageF viewZ, normal, baseColor, direct;
};

Frame renderOnce(gpu::Context& context, const render::AnalyticScene& scene) {
  render::AnalyticRenderer renderer(context, kWidth, kHeight, scene);
  context.submitAndWait([&](gpu::Recorder& r) { renderer.record(r, obliqueCamera()); });
  return {gpu::readbackImage(context, renderer.viewZ()), gpu::readbackImage(context, renderer.normalRoughness()),
          gpu::readbackImage(context, renderer.baseColorMetallic()),
          gpu::readbackImage(context, renderer.directLight())};
}

using AnalyticScene = GpuTest;

TEST_F(AnalyticScene, SunLitGroundIsIlluminanceTimesAlbedoOverPi) {
  for (float elevation : {90.0f, 35.0f}) {
    const render::AnalyticScene scene = overheadSunScene(elevation);
    Frame frame = renderOnce(context(), scene);
    const float cosine = std::sin(glm::radians(elevation));
    int lit = 0, ground = 0;
    for (int y = 0; y < int(kHeight); ++y)
      for (int x = 0; x < int(kWidth); ++x) {
        if (frame.viewZ.at(x, y, 0) <= 0.0f || frame.normal.at(x, y, 1) < 0.9999f) continue;  // not ground
        ++ground;
        if (frame.direct.at(x, y, 0) == 0.0f) continue;  // in the sphere's shadow
        ++lit;
        for (int c = 0; c < 3; ++c) {
          const float expected = scene.sun.illuminance * scene.groundColor[c] / float(M_PI) * cosine;
          ASSERT_NEAR(frame.direct.at(x, y, c), expected, 1e-3f * expected)
              << "pixel " << x << "," << y << " channel " << c << " elevation " << elevation;
        }
      }
    EXPECT_GT(ground, int(kWidth * kHeight) / 2);
    EXPECT_GT(lit, ground * 9 / 10) << "most of the ground is in the sun";
    EXPECT_LT(lit, ground) << "and some of it is in the sphere's shadow";
  }
}

TEST_F(AnalyticScene, ShadowAndGBufferMatchGeometry) {
  Frame frame = renderOnce(context(), overheadSunScene(90.0f));
  const int cx = kWidth / 2, cy = kHeight / 2;
  // The optical axis hits the origin: the centre of the overhead shadow.
  EXPECT_NEAR(frame.viewZ.at(cx, cy, 0), std::sqrt(32.0f), 1e-4f);
  EXPECT_NEAR(frame.normal.at(cx, cy, 1), 1.0f, 1e-3f);
  EXPECT_EQ(frame.direct.at(cx, cy, 0), 0.0f) << "the origin lies in the sphere's shadow";
  EXPECT_NEAR(frame.baseColor.at(cx, cy, 0), 0.8f, 1e-6f);
  // Sphere pixels have unit normals.
  int sphere = 0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x)
      if (frame.viewZ.at(x, y, 0) > 0.0f && frame.normal.at(x, y, 1) < 0.999f) {
        ++sphere;
        glm::vec3 n(frame.normal.at(x, y, 0), frame.normal.at(x, y, 1), frame.normal.at(x, y, 2));
        ASSERT_NEAR(glm::length(n), 1.0f, 2e-3f);
      }
  EXPECT_GT(sphere, 20);
}

TEST_F(AnalyticScene, SkyPixelsHaveZeroViewZAndSkyRadiance) {
  // The default camera looks slightly down; its top row is above the horizon.
  render::AnalyticScene scene = render::AnalyticScene::standard();
  render::AnalyticRenderer renderer(context(), kWidth, kHeight, scene);
  context().submitAndWait([&](gpu::Recorder& r) { renderer.record(r, render::Camera{}); });
  io::ImageF viewZ = gpu::readbackImage(context(), renderer.viewZ());
  io::ImageF direct = gpu::readbackImage(context(), renderer.directLight());
  for (int x = 0; x < int(kWidth); ++x) {
    ASSERT_EQ(viewZ.at(x, 0, 0), 0.0f) << "column " << x;
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(direct.at(x, 0, c), scene.skyRadiance[c], 1e-3f);
  }
  EXPECT_GT(viewZ.at(int(kWidth) / 2, int(kHeight) - 1, 0), 0.0f) << "the bottom row sees the ground";
}

TEST_F(AnalyticScene, RendersEveryFrameOfAFrameLoopSilently) {
  render::AnalyticRenderer renderer(context(), kWidth, kHeight, render::AnalyticScene::standard());
  gpu::FrameLoop loop(context());
  for (int frame = 0; frame < 4; ++frame) {
    renderer.record(loop.beginFrame(), obliqueCamera());
    loop.endFrame();
  }
  loop.finish();
  auto rows = loop.timings().summary();
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].pass, "render.analytic_gbuffer");
  EXPECT_EQ(rows[1].pass, "render.direct_sun");
  EXPECT_EQ(rows[1].samples, 4u);
}

}  // namespace
}  // namespace bounce::testing
