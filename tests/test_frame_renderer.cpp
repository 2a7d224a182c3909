// Tests of src/render/frame_renderer: the G-buffer and direct light of scenes
// with known answers (a plane and a sphere), motion vectors checked by
// reprojecting, and the direct-light laws (sun: E * BRDF * cos; point light:
// inverse square; shadowed points: black). All on lavapipe with validation.
#include "render/frame_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gpu/error.h"
#include "gpu/frame_loop.h"
#include "gpu/transfer.h"
#include "gpu_test.h"
#include "gpuio/gpu_images.h"
#include "render/frame_types.glsl"
#include "shared/brdf.glsl"
#include "shared/intersect.glsl"
#include "test_meshes.h"

namespace bounce::render {
namespace {

constexpr std::uint32_t kWidth = 96;
constexpr std::uint32_t kHeight = 64;
const glm::vec3 kSphereCenter(0.0f, 1.0f, 0.0f);
constexpr float kSphereRadius = 1.0f;

// Plane (material 0) and sphere (material 1, node 1) under a sun.
scene::Scene planeAndSphere() {
  scene::Scene s;
  s.name = "plane-and-sphere";
  scene::Material ground;
  ground.baseColorFactor = glm::vec4(0.6f, 0.5f, 0.4f, 1.0f);
  ground.metallicFactor = 0.0f;
  ground.roughnessFactor = 0.8f;
  scene::Material ball = ground;
  ball.baseColorFactor = glm::vec4(0.2f, 0.3f, 0.9f, 1.0f);
  s.materials = {ground, ball};
  s.meshes = {testing::planeMesh(50.0f), testing::sphereMesh(96, 48)};
  s.meshes[1].material = 1;
  scene::Node planeNode;
  planeNode.meshes = {0};
  scene::Node sphereNode;
  sphereNode.meshes = {1};
  sphereNode.local.translation = kSphereCenter;
  s.nodes = {planeNode, sphereNode};
  s.roots = {0, 1};
  s.sun.elevationDegrees = 40.0f;
  s.sun.azimuthDegrees = 20.0f;
  s.sun.illuminance = 3.0f;
  s.sun.color = glm::vec3(1.0f);
  return s;
}

// The CPU twin of a G-buffer ray through a pixel centre.
glm::vec3 rayThrough(const shared::GpuCamera& camera, int x, int y) {
  return shared::cameraRayDirection(camera, glm::vec2(float(x) + 0.5f, float(y) + 0.5f),
                                    glm::vec2(float(kWidth), float(kHeight)));
}

// Base colour as the G-buffer stores it (rgba8 unorm).
glm::vec3 storedBaseColor(const glm::vec4& factor) { return glm::round(glm::vec3(factor) * 255.0f) / 255.0f; }

// The plane mesh is 100 m wide; the analytic plane goes on for ever.
bool onPlaneMesh(const glm::vec3& p) { return std::abs(p.x) < 49.0f && std::abs(p.z) < 49.0f; }

struct Frame {
  io::ImageF viewZ, normal, geometric, motion, direct, ids;
};

class FrameRendererTest : public testing::GpuTest {
 protected:
  // Renders the given views in order (one FrameLoop frame each) and returns
  // the G-buffer and direct light of every frame.
  std::vector<Frame> render(const scene::Scene& s, const std::vector<FrameView>& views, bool jitter = false) {
    FrameRendererOptions options = testing::smallRendererOptions(s, kWidth, kHeight);
    options.jitter = jitter;
    FrameRenderer renderer(context(), s, options);
    gpu::FrameLoop loop(context(), FrameRenderer::kFramesInFlight);
    std::vector<Frame> frames;
    for (const FrameView& view : views) {
      gpu::Recorder& recorder = loop.beginFrame();
      renderer.record(recorder, loop.frameIndex(), view);
      loop.endFrame();
      loop.finish();
      frames.push_back(
          {gpuio::readbackImage(context(), renderer.viewZ()), gpuio::readbackImage(context(), renderer.normalRoughness()),
           gpuio::readbackImage(context(), renderer.geometricNormal()), gpuio::readbackImage(context(), renderer.motion()),
           gpuio::readbackImage(context(), renderer.direct()), gpuio::readbackImage(context(), renderer.ids())});
    }
    return frames;
  }
};

// Each pose that cannot make an image is refused with the condition that
// failed and its values (a glTF with 1e30 positions, or 1e19 node scales,
// used to get one message listing every condition at once).
TEST(CheckCamera, NamesTheConditionThatFailedAndItsValues) {
  const auto messageOf = [](const scene::CameraPose& pose) -> std::string {
    try {
      checkCamera(pose);
    } catch (const gpu::GpuError& error) {
      return error.what();
    }
    return "accepted";
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  scene::CameraPose pose = testing::cameraAt({3e19f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 45.0f);
  EXPECT_EQ(messageOf(pose),
            "camera: position (3e+19, 0, 0) is more than 1e+18 from the origin along an axis; the renderer's 32-bit "
            "floats cannot square distances that large");
  pose.position = {1e17f, 5.0f, 0.0f};
  EXPECT_EQ(messageOf(pose), "accepted");
  pose.target = {0.0f, nan, 0.0f};
  EXPECT_NE(messageOf(pose).find("camera: target (0, "), std::string::npos) << messageOf(pose);
  EXPECT_NE(messageOf(pose).find(", 0) is not finite"), std::string::npos) << messageOf(pose);
  pose = testing::cameraAt({1.0f, 2.0f, 3.0f}, {1.0f, 2.0f, 3.0f}, 45.0f);
  EXPECT_EQ(messageOf(pose), "camera: position (1, 2, 3) and target (1, 2, 3) are the same point");
  pose = testing::cameraAt({0.0f, 0.0f, 0.0f}, {0.0f, 5.0f, 0.0f}, 45.0f);
  pose.up = {0.0f, 2.0f, 0.0f};
  EXPECT_EQ(messageOf(pose), "camera: up vector (0, 2, 0) is parallel to the view direction (0, 1, 0)");
  pose.up = glm::vec3(0.0f);
  EXPECT_EQ(messageOf(pose), "camera: up vector (0, 0, 0) is zero");
  pose = testing::cameraAt({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, 180.0f);
  EXPECT_EQ(messageOf(pose), "camera: vertical field of view 180 degrees is outside (0, 180)");
  pose.fovYDegrees = 179.99998f;
  EXPECT_EQ(messageOf(pose), "accepted");
}

// A floor 20 m wide made of a mesh a picometre wide scaled up 1e13 times
// (a float determinant overflows there; it used to vanish from the BVH
// without a word) is drawn, normals and all; a flattened node that truly
// cannot be drawn is named in one warning, however many frames there are.
TEST_F(FrameRendererTest, NodesScaledFarFromOneAreDrawnAndUndrawableOnesWarnedAboutOnce) {
  scene::Scene s;
  s.name = "scales";
  s.materials.resize(1);
  s.meshes = {testing::planeMesh(1e-12f)};
  scene::Node floor;
  floor.name = "floor";
  floor.meshes = {0};
  floor.local.scale = glm::vec3(1e13f);
  scene::Node flat = floor;
  flat.name = "flat";
  flat.local.scale = {1.0f, 0.0f, 1.0f};
  s.nodes = {floor, flat};
  s.roots = {0, 1};
  std::vector<std::string> warnings;
  FrameRendererOptions options = testing::smallRendererOptions(s, kWidth, kHeight);
  options.warn = [&](const std::string& line) { warnings.push_back(line); };
  FrameRenderer renderer(context(), s, options);
  gpu::FrameLoop loop(context(), FrameRenderer::kFramesInFlight);
  const scene::CameraPose pose = testing::cameraAt({0.0f, 2.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, 50.0f);
  for (int frame = 0; frame < 2; ++frame) {
    renderer.record(loop.beginFrame(), loop.frameIndex(), {pose, 0.0f, frame == 0});
    loop.endFrame();
  }
  loop.finish();

  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("scene 'scales': 1 mesh instance(s) cannot be drawn", 0), 0u) << warnings[0];
  EXPECT_NE(warnings[0].find(": node 1 'flat'"), std::string::npos) << warnings[0];
  EXPECT_EQ(warnings[0].find("floor"), std::string::npos) << warnings[0];
  // The middle of the image sees the floor where the analytic plane y = 0 is.
  const io::ImageF viewZ = gpuio::readbackImage(context(), renderer.viewZ());
  const io::ImageF normal = gpuio::readbackImage(context(), renderer.normalRoughness());
  const shared::GpuCamera camera = gpuCamera(pose, kWidth, kHeight);
  const int x = int(kWidth) / 2, y = int(kHeight) / 2;
  const glm::vec3 d = rayThrough(camera, x, y);
  const glm::vec3 hit = pose.position + d * shared::intersectPlane(pose.position, d, glm::vec3(0, 1, 0), 0.0f, 0.0f);
  EXPECT_NEAR(viewZ.at(x, y, 0), glm::dot(hit - pose.position, glm::vec3(camera.forward)), 1e-3f);
  EXPECT_NEAR(normal.at(x, y, 1), 1.0f, 1e-3f) << "the floor faces up";
}

// A valid glTF may hold no mesh and no material ({"asset": {"version": "2.0"}}):
// every buffer the passes bind still exists, and the frame is the sky.
TEST_F(FrameRendererTest, ASceneWithNothingInItShowsTheSky) {
  scene::Scene empty;
  empty.name = "empty";
  const Frame frame =
      render(empty, {{testing::cameraAt({0.0f, 1.0f, 5.0f}, {0.0f, 1.5f, 0.0f}, 60.0f), 0.0f, true}})[0];
  double sum = 0.0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      ASSERT_EQ(frame.viewZ.at(x, y, 0), 0.0f) << x << "," << y << " is background";
      for (int c = 0; c < 3; ++c) {
        ASSERT_TRUE(std::isfinite(frame.direct.at(x, y, c)) && frame.direct.at(x, y, c) >= 0.0f) << x << "," << y;
        sum += frame.direct.at(x, y, c);
      }
    }
  EXPECT_GT(sum, 0.0) << "the sky is lit";
}

TEST_F(FrameRendererTest, PlaneAndSphereGiveExactViewZAndNormals) {
  const scene::Scene s = planeAndSphere();
  const scene::CameraPose pose = testing::cameraAt({0.5f, 2.0f, 6.0f}, {0.0f, 0.8f, 0.0f}, 50.0f);
  const Frame frame = render(s, {{pose, 0.0f, true}})[0];
  const shared::GpuCamera camera = gpuCamera(pose, kWidth, kHeight);
  int planePixels = 0, spherePixels = 0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      const glm::vec3 d = rayThrough(camera, x, y);
      const float tSphere = shared::intersectSphere(pose.position, d, kSphereCenter, kSphereRadius, 0.0f);
      const float tPlane = shared::intersectPlane(pose.position, d, glm::vec3(0, 1, 0), 0.0f, 0.0f);
      const float viewZ = frame.viewZ.at(x, y, 0);
      // Pixels near the sphere's silhouette differ between the tessellation
      // and the true sphere; they are left out.
      const glm::vec3 toCenter = kSphereCenter - pose.position;
      const float distanceToAxis = glm::length(toCenter - d * glm::dot(toCenter, d));
      if (std::abs(distanceToAxis - kSphereRadius) < 0.03f) continue;
      const bool sphere = tSphere < shared::kNoHit;
      const float t = sphere ? tSphere : tPlane;
      if (!sphere && tPlane < shared::kNoHit && !onPlaneMesh(pose.position + d * tPlane)) continue;
      if (t >= shared::kNoHit) {
        EXPECT_EQ(viewZ, 0.0f) << x << "," << y << " sees the sky";
        continue;
      }
      const glm::vec3 hit = pose.position + d * t;
      const float expectedViewZ = glm::dot(hit - pose.position, glm::vec3(camera.forward));
      const glm::vec3 normal(frame.normal.at(x, y, 0), frame.normal.at(x, y, 1), frame.normal.at(x, y, 2));
      const glm::vec3 geometric(frame.geometric.at(x, y, 0), frame.geometric.at(x, y, 1), frame.geometric.at(x, y, 2));
      if (sphere) {
        ++spherePixels;
        const glm::vec3 expected = glm::normalize(hit - kSphereCenter);
        // 96 x 48 facets: the chord sags 0.05 % of the radius; facet normals
        // tilt up to ~3.8 degrees, interpolated ones about half that.
        EXPECT_NEAR(viewZ, expectedViewZ, 2e-3f * expectedViewZ) << x << "," << y;
        EXPECT_GT(glm::dot(geometric, expected), std::cos(glm::radians(4.0f))) << x << "," << y;
        EXPECT_GT(glm::dot(normal, expected), std::cos(glm::radians(2.5f))) << x << "," << y;
      } else {
        ++planePixels;
        EXPECT_NEAR(viewZ, expectedViewZ, 1e-4f * expectedViewZ) << x << "," << y;
        EXPECT_NEAR(normal.y, 1.0f, 1e-3f) << x << "," << y;
        EXPECT_NEAR(geometric.y, 1.0f, 1e-3f) << x << "," << y;
        EXPECT_EQ(std::uint32_t(frame.ids.at(x, y, 0)) & 0xffffu, 0u) << "plane material";
      }
    }
  EXPECT_GT(planePixels, 1000);
  EXPECT_GT(spherePixels, 300);
}

TEST_F(FrameRendererTest, MotionVectorsReprojectToThePreviousPixel) {
  const scene::Scene s = planeAndSphere();
  // A small move and turn, as between two real frames (motion of a few pixels).
  const scene::CameraPose first = testing::cameraAt({0.5f, 2.0f, 6.0f}, {0.0f, 0.8f, 0.0f}, 50.0f);
  const scene::CameraPose second = testing::cameraAt({0.55f, 2.02f, 5.9f}, {0.03f, 0.8f, 0.0f}, 50.0f);
  const std::vector<Frame> frames = render(s, {{first, 0.0f, true}, {second, 0.0f, false}});
  const shared::GpuCamera previous = gpuCamera(first, kWidth, kHeight);
  const shared::GpuCamera current = gpuCamera(second, kWidth, kHeight);
  const glm::vec2 size{float(kWidth), float(kHeight)};
  int checked = 0, reprojected = 0;
  float largest = 0.0f;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      const float viewZ = frames[1].viewZ.at(x, y, 0);
      if (viewZ <= 0.0f) continue;
      const glm::vec3 d = rayThrough(current, x, y);
      const glm::vec3 world = second.position + d * (viewZ / glm::dot(d, glm::vec3(current.forward)));
      const glm::vec2 expected = glm::vec2(shared::projectToPixel(previous, world, size));
      const glm::vec2 motion(frames[1].motion.at(x, y, 0), frames[1].motion.at(x, y, 1));
      const glm::vec2 reprojection = glm::vec2(float(x) + 0.5f, float(y) + 0.5f) + motion;
      largest = std::max(largest, glm::length(motion));
      EXPECT_LT(glm::length(reprojection - expected), 0.01f) << x << "," << y;
      ++checked;
      // And the previous frame really saw this point there: its depth at the
      // reprojected pixel puts a surface at the same place (away from edges).
      const int px = int(std::floor(reprojection.x)), py = int(std::floor(reprojection.y));
      if (px < 0 || py < 0 || px >= int(kWidth) || py >= int(kHeight)) continue;
      const float previousViewZ = frames[0].viewZ.at(px, py, 0);
      if (previousViewZ <= 0.0f) continue;
      const glm::vec3 dp = rayThrough(previous, px, py);
      const glm::vec3 seen = first.position + dp * (previousViewZ / glm::dot(dp, glm::vec3(previous.forward)));
      const float pixelSize = previousViewZ * 2.0f * previous.position.w / float(kHeight);
      if (glm::length(seen - world) < 3.0f * pixelSize / std::max(0.2f, std::abs(dp.y))) ++reprojected;
    }
  EXPECT_GT(checked, 2000);
  EXPECT_GT(largest, 1.0f) << "the camera must actually move the image";
  EXPECT_GT(double(reprojected), 0.95 * checked);
}

TEST_F(FrameRendererTest, AnimatedNodeMotionIsInTheMotionVectors) {
  scene::Scene s = planeAndSphere();
  scene::Animation slide;
  slide.channels.push_back({1,
                            scene::AnimatedProperty::Translation,
                            scene::Interpolation::Linear,
                            {0.0f, 1.0f},
                            {glm::vec4(kSphereCenter, 0.0f), glm::vec4(kSphereCenter + glm::vec3(1, 0, 0), 0.0f)}});
  s.animations.push_back(slide);
  const scene::CameraPose pose = testing::cameraAt({0.5f, 2.0f, 6.0f}, {0.0f, 0.8f, 0.0f}, 50.0f);
  const float t0 = 0.25f, t1 = 0.3f;  // the sphere moves 0.05 m
  const std::vector<Frame> frames = render(s, {{pose, t0, true}, {pose, t1, false}});
  const shared::GpuCamera camera = gpuCamera(pose, kWidth, kHeight);
  const glm::vec2 size{float(kWidth), float(kHeight)};
  int spherePixels = 0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      const float viewZ = frames[1].viewZ.at(x, y, 0);
      if (viewZ <= 0.0f) continue;
      const glm::vec3 d = rayThrough(camera, x, y);
      const glm::vec3 world = pose.position + d * (viewZ / glm::dot(d, glm::vec3(camera.forward)));
      const bool onSphere = (std::uint32_t(frames[1].ids.at(x, y, 0)) >> 16) == 1u;
      const glm::vec3 previousWorld = onSphere ? world - glm::vec3(0.05f, 0, 0) : world;
      const glm::vec2 expected = glm::vec2(shared::projectToPixel(camera, previousWorld, size));
      const glm::vec2 motion(frames[1].motion.at(x, y, 0), frames[1].motion.at(x, y, 1));
      EXPECT_LT(glm::length(glm::vec2(float(x) + 0.5f, float(y) + 0.5f) + motion - expected), 0.01f) << x << "," << y;
      if (onSphere) {
        ++spherePixels;
        EXPECT_GT(glm::length(motion), 0.3f) << "the moving sphere must have motion";
      }
    }
  EXPECT_GT(spherePixels, 300);
}

TEST_F(FrameRendererTest, SunLightsThePlaneByTheBrdfAndShadowsAreBlack) {
  const scene::Scene s = planeAndSphere();
  const scene::CameraPose pose = testing::cameraAt({0.5f, 3.0f, 6.0f}, {0.0f, 0.3f, 0.0f}, 50.0f);
  const Frame frame = render(s, {{pose, 0.0f, true}})[0];
  const shared::GpuCamera camera = gpuCamera(pose, kWidth, kHeight);
  const glm::vec3 toSun = s.sun.direction();
  const glm::vec3 baseColor = storedBaseColor(s.materials[0].baseColorFactor);
  int lit = 0, shadowed = 0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      const glm::vec3 d = rayThrough(camera, x, y);
      const float tSphere = shared::intersectSphere(pose.position, d, kSphereCenter, kSphereRadius * 1.02f, 0.0f);
      const float tPlane = shared::intersectPlane(pose.position, d, glm::vec3(0, 1, 0), 0.0f, 0.0f);
      if (tSphere < shared::kNoHit || tPlane >= shared::kNoHit) continue;
      const glm::vec3 hit = pose.position + d * tPlane;
      if (!onPlaneMesh(hit)) continue;
      const glm::vec3 radiance(frame.direct.at(x, y, 0), frame.direct.at(x, y, 1), frame.direct.at(x, y, 2));
      // Shadow of the (slightly enlarged, then shrunk) sphere: clear cases only.
      const bool inShadow =
          shared::intersectSphere(hit, toSun, kSphereCenter, kSphereRadius * 0.97f, 0.0f) < shared::kNoHit;
      const bool clearlyLit =
          shared::intersectSphere(hit, toSun, kSphereCenter, kSphereRadius * 1.03f, 0.0f) >= shared::kNoHit;
      if (inShadow) {
        ++shadowed;
        EXPECT_EQ(radiance, glm::vec3(0.0f)) << x << "," << y;
      } else if (clearlyLit) {
        ++lit;
        const glm::vec3 expected =
            s.sun.illuminance * shared::materialBrdfCosine(glm::vec3(0, 1, 0), -d, toSun, baseColor, 0.0f, 0.8f);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(radiance[c], expected[c], 1e-3f * expected[c]) << x << "," << y;
        // The diffuse part alone is E * albedo / pi * cos.
        const glm::vec3 specular =
            s.sun.illuminance *
            shared::ggxSpecularCosine(glm::vec3(0, 1, 0), -d, toSun, glm::vec3(0.04f), shared::ggxAlpha(0.8f));
        EXPECT_NEAR(radiance.x - specular.x, s.sun.illuminance * baseColor.x / glm::pi<float>() * toSun.y,
                    2e-3f * radiance.x);
      }
    }
  EXPECT_GT(lit, 1000);
  EXPECT_GT(shadowed, 10);
}

TEST_F(FrameRendererTest, PointLightFallsOffWithTheInverseSquare) {
  scene::Scene s = planeAndSphere();
  s.nodes[1].meshes.clear();  // no sphere: nothing casts shadows
  s.hasSun = false;
  scene::Light bulb;
  bulb.type = scene::LightType::Point;
  bulb.intensity = 20.0f;
  s.lights.push_back(bulb);
  scene::Node lightNode;
  lightNode.light = 0;
  lightNode.local.translation = {0.0f, 2.0f, 0.0f};
  s.nodes.push_back(lightNode);
  s.roots.push_back(2);
  const scene::CameraPose pose = testing::cameraAt({0.0f, 4.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, 50.0f);
  const Frame frame = render(s, {{pose, 0.0f, true}})[0];
  const shared::GpuCamera camera = gpuCamera(pose, kWidth, kHeight);
  const glm::vec3 baseColor = storedBaseColor(s.materials[0].baseColorFactor);
  int checked = 0;
  for (int y = 0; y < int(kHeight); y += 3)
    for (int x = 0; x < int(kWidth); x += 3) {
      const glm::vec3 d = rayThrough(camera, x, y);
      const float t = shared::intersectPlane(pose.position, d, glm::vec3(0, 1, 0), 0.0f, 0.0f);
      if (t >= shared::kNoHit) continue;
      const glm::vec3 hit = pose.position + d * t;
      if (!onPlaneMesh(hit)) continue;
      const glm::vec3 toLight = glm::vec3(0, 2, 0) - hit;
      const float distanceSquared = glm::dot(toLight, toLight);
      const glm::vec3 expected =
          bulb.intensity / distanceSquared *
          shared::materialBrdfCosine(glm::vec3(0, 1, 0), -d, glm::normalize(toLight), baseColor, 0.0f, 0.8f);
      const float red = frame.direct.at(x, y, 0);
      EXPECT_NEAR(red, expected.x, 2e-3f * expected.x) << x << "," << y;
      ++checked;
    }
  EXPECT_GT(checked, 300);
}

}  // namespace
}  // namespace bounce::render

namespace bounce::render {
namespace {

TEST_F(FrameRendererTest, TooManyLightsAreRefusedNotDropped) {
  scene::Scene s = planeAndSphere();
  s.lights.push_back({});
  for (std::uint32_t i = 0; i <= FrameRenderer::kMaxLights; ++i) {
    scene::Node node;
    node.light = 0;
    s.nodes.push_back(node);
    s.roots.push_back(int(s.nodes.size()) - 1);
  }
  try {
    FrameRenderer renderer(context(), s, testing::smallRendererOptions(s, kWidth, kHeight));
    ADD_FAILURE() << "expected an error";
  } catch (const gpu::GpuError& e) {
    EXPECT_NE(std::string(e.what()).find("257 punctual lights"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bounce::render

namespace bounce::render {
namespace {

// With jitter the rays move inside their pixels every frame; the motion
// vectors must still describe only the surface's motion.
TEST_F(FrameRendererTest, JitterStaysOutOfMotionVectorsAndCutsZeroThem) {
  const scene::Scene s = planeAndSphere();
  const scene::CameraPose first = testing::cameraAt({0.5f, 2.0f, 6.0f}, {0.0f, 0.8f, 0.0f}, 50.0f);
  const scene::CameraPose second = testing::cameraAt({0.55f, 2.02f, 5.9f}, {0.03f, 0.8f, 0.0f}, 50.0f);
  const std::vector<Frame> frames =
      render(s, {{first, 0.0f, true}, {second, 0.0f, false}, {first, 0.0f, true}}, /*jitter=*/true);
  const shared::GpuCamera previous = gpuCamera(first, kWidth, kHeight);
  const shared::GpuCamera current = gpuCamera(second, kWidth, kHeight);
  const glm::vec2 size{float(kWidth), float(kHeight)};
  const glm::vec2 jitter = jitterOffset(1);  // the FrameLoop's second frame
  ASSERT_GT(glm::length(jitter), 0.05f);
  int checked = 0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      const float viewZ = frames[1].viewZ.at(x, y, 0);
      if (viewZ <= 0.0f) continue;
      const glm::vec2 through = glm::vec2(float(x) + 0.5f, float(y) + 0.5f) + jitter;
      const glm::vec3 d = shared::cameraRayDirection(current, through, size);
      const glm::vec3 world = second.position + d * (viewZ / glm::dot(d, glm::vec3(current.forward)));
      const glm::vec2 expected = glm::vec2(shared::projectToPixel(previous, world, size));
      const glm::vec2 motion(frames[1].motion.at(x, y, 0), frames[1].motion.at(x, y, 1));
      EXPECT_LT(glm::length(through + motion - expected), 0.01f) << x << "," << y;
      ++checked;
      // The third frame is a cut back to the first camera: no history, no motion.
      EXPECT_EQ(frames[2].motion.at(x, y, 0), 0.0f);
      EXPECT_EQ(frames[2].motion.at(x, y, 1), 0.0f);
    }
  EXPECT_GT(checked, 2000);
}

}  // namespace
}  // namespace bounce::render
