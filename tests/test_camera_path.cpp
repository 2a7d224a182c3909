// Tests of src/scene/camera_path: presets (continuous, looping, clear of the
// built-in scenes' geometry), glTF cameras, JSON keyframes (exact keys,
// smooth motion, cuts on exactly the right frames, every error named).
#include "scene/camera_path.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <glm/gtc/constants.hpp>

#include "scene/builtin_scenes.h"

namespace bounce::scene {
namespace {

namespace fs = std::filesystem;

void expectPoseEq(const CameraPose& a, const CameraPose& b) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(a.position[c], b.position[c]);
    EXPECT_FLOAT_EQ(a.target[c], b.target[c]);
    EXPECT_FLOAT_EQ(a.up[c], b.up[c]);
  }
  EXPECT_FLOAT_EQ(a.fovYDegrees, b.fovYDegrees);
}

float poseDistance(const CameraPose& a, const CameraPose& b) {
  return glm::length(a.position - b.position) + glm::length(a.target - b.target) + glm::length(a.up - b.up) +
         std::abs(a.fovYDegrees - b.fovYDegrees) * 0.01f;
}

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
glm::vec3 closestPointOnTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const glm::vec3 bp = p - b;
  const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const glm::vec3 cp = p - c;
  const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const float denominator = 1.0f / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

// Distance from p to the nearest triangle of the scene at time 0.
float clearance(const Scene& scene, const glm::vec3& p) {
  float nearest = std::numeric_limits<float>::max();
  for (const Instance& instance : instancesAt(scene, 0.0f)) {
    const Mesh& mesh = scene.meshes[std::size_t(instance.mesh)];
    for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
      std::array<glm::vec3, 3> v;
      for (std::size_t k = 0; k < 3; ++k)
        v[k] = glm::vec3(instance.objectToWorld * glm::vec4(mesh.positions[mesh.indices[i + k]], 1.0f));
      nearest = std::min(nearest, glm::length(p - closestPointOnTriangle(p, v[0], v[1], v[2])));
    }
  }
  return nearest;
}

// A one-triangle scene (for scenes that are not built-ins).
Scene triangleScene() {
  Scene scene;
  scene.name = "triangle";
  scene.materials.push_back({});
  Mesh mesh;
  mesh.positions = {{-1, 0, 0}, {1, 0, 0}, {0, 2, 0}};
  mesh.normals.assign(3, {0, 0, 1});
  mesh.tangents.assign(3, {1, 0, 0, 1});
  mesh.texcoords.assign(3, {0, 0});
  mesh.indices = {0, 1, 2};
  scene.meshes.push_back(mesh);
  Node node;
  node.meshes = {0};
  scene.nodes.push_back(node);
  scene.roots = {0};
  return scene;
}

fs::path writeTempFile(const std::string& name, const std::string& text) {
  const fs::path path = fs::path(testing::TempDir()) / name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

const char* const kMovingPresets[] = {"orbit", "dolly", "fly"};

TEST(CameraPath, PresetNames) {
  EXPECT_EQ(cameraPathPresets(), (std::vector<std::string>{"orbit", "dolly", "fly", "static", "gltf"}));
}

TEST(CameraPath, StaticIsTheSuggestedCamera) {
  const Scene scene = makeBuiltinScene("cornell");
  const std::unique_ptr<CameraPath> path = makeCameraPath("static", scene);
  EXPECT_EQ(path->duration(), 0.0f);
  for (float time : {0.0f, 1.0f, 100.0f}) expectPoseEq(path->pose(time), *scene.suggestedCamera);
  // Built-in scenes have no glTF camera, so the default is the same.
  expectPoseEq(defaultCameraPath(scene)->pose(3.0f), *scene.suggestedCamera);
}

TEST(CameraPath, WithoutASuggestedCameraStaticFramesTheWholeScene) {
  const Scene scene = triangleScene();
  const CameraPose pose = makeCameraPath("static", scene)->pose(0.0f);
  const Bounds bounds = worldBounds(scene, 0.0f);
  const glm::vec3 forward = glm::normalize(pose.target - pose.position);
  for (const glm::vec3& corner : {bounds.min, bounds.max, glm::vec3(bounds.min.x, bounds.max.y, bounds.min.z)}) {
    const glm::vec3 toCorner = glm::normalize(corner - pose.position);
    EXPECT_LT(std::acos(glm::dot(toCorner, forward)), glm::radians(pose.fovYDegrees) / 2);
  }
  EXPECT_GT(glm::length(pose.position - bounds.center()), glm::length(bounds.extent()));
}

// Framing in floats overflowed for bounds whose size squared passes float's
// range (1e30 here) and gave an infinite camera without a word; now such
// bounds are framed, and bounds no float camera can frame are refused.
TEST(CameraPath, HugeBoundsAreFramedOrRefusedNamingTheScene) {
  const auto sceneAt = [](const glm::vec3& offset, float size) {
    Scene scene = triangleScene();
    scene.name = "huge";
    for (glm::vec3& p : scene.meshes[0].positions) p = offset + p * size;
    return scene;
  };
  const Scene huge = sceneAt(glm::vec3(0.0f), 1e30f);
  const CameraPose pose = makeCameraPath("static", huge)->pose(0.0f);
  const Bounds bounds = worldBounds(huge, 0.0f);
  ASSERT_TRUE(std::isfinite(pose.position.x) && std::isfinite(pose.position.y) && std::isfinite(pose.position.z));
  const glm::dvec3 extent = glm::dvec3(bounds.max) - glm::dvec3(bounds.min);
  const double expected = 1.1 * 0.5 * glm::length(extent) / std::sin(glm::radians(22.5));
  EXPECT_NEAR(glm::length(glm::dvec3(pose.position) - glm::dvec3(pose.target)) / expected, 1.0, 1e-5);

  for (const Scene& unframeable : {sceneAt(glm::vec3(0.0f), 1e38f), sceneAt(glm::vec3(1e30f), 1.0f)}) {
    try {
      makeCameraPath("static", unframeable);
      ADD_FAILURE() << "expected SceneError";
    } catch (const SceneError& error) {
      EXPECT_EQ(std::string(error.what()).rfind("scene 'huge': its bounds, (", 0), 0u) << error.what();
      EXPECT_NE(std::string(error.what()).find("too large"), std::string::npos) << error.what();
    }
  }
}

TEST(CameraPath, OrbitCirclesAtConstantDistanceAndHeightAndLoops) {
  for (const char* name : {"cornell", "sun-room"}) {
    SCOPED_TRACE(name);
    const Scene scene = makeBuiltinScene(name);
    const std::unique_ptr<CameraPath> orbit = makeCameraPath("orbit", scene);
    const float period = orbit->duration();
    EXPECT_GT(period, 0.0f);
    const CameraPose start = orbit->pose(0.0f);
    const float distance = glm::length(start.target - start.position);
    const Bounds bounds = worldBounds(scene, 0.0f);
    float turned = 0.0f;
    glm::vec2 previous(start.position.x - start.target.x, start.position.z - start.target.z);
    for (int step = 1; step <= 400; ++step) {
      const CameraPose pose = orbit->pose(period * float(step) / 400);
      EXPECT_NEAR(glm::length(pose.target - pose.position), distance, 1e-4f * distance);
      EXPECT_NEAR(pose.position.y, scene.suggestedCamera->position.y, 1e-5f);
      EXPECT_LT(glm::length(pose.target - start.target), 1e-6f);
      const glm::vec2 offset(pose.position.x - pose.target.x, pose.position.z - pose.target.z);
      turned += std::atan2(previous.x * offset.y - previous.y * offset.x, glm::dot(previous, offset));
      previous = offset;
    }
    EXPECT_NEAR(std::abs(turned), glm::two_pi<float>(), 1e-3f) << "one revolution per duration";
    EXPECT_LT(poseDistance(orbit->pose(period), start), 1e-4f);
    // It looks at the middle of the scene.
    EXPECT_NEAR(start.target.x, bounds.center().x, 1e-5f);
    EXPECT_NEAR(start.target.z, bounds.center().z, 1e-5f);
  }
  // From outside, it starts where the suggested camera stands.
  const Scene cornell = makeBuiltinScene("cornell");
  EXPECT_LT(glm::length(makeCameraPath("orbit", cornell)->pose(0.0f).position - cornell.suggestedCamera->position),
            1e-4f);
}

TEST(CameraPath, DollyMovesStraightTowardsTheTargetAndBack) {
  const Scene scene = makeBuiltinScene("pillars");
  const CameraPose& start = *scene.suggestedCamera;
  const std::unique_ptr<CameraPath> dolly = makeCameraPath("dolly", scene);
  const glm::vec3 towards = glm::normalize(start.target - start.position);
  float closest = glm::length(start.target - start.position);
  for (int step = 0; step <= 100; ++step) {
    const CameraPose pose = dolly->pose(dolly->duration() * float(step) / 100);
    const glm::vec3 moved = pose.position - start.position;
    EXPECT_LT(glm::length(moved - glm::dot(moved, towards) * towards), 1e-4f) << "off the line";
    EXPECT_GE(glm::dot(moved, towards), -1e-5f);
    EXPECT_EQ(pose.target, start.target);
    EXPECT_EQ(pose.up, start.up);
    EXPECT_EQ(pose.fovYDegrees, start.fovYDegrees);
    closest = std::min(closest, glm::length(pose.target - pose.position));
  }
  EXPECT_LT(closest, 0.6f * glm::length(start.target - start.position));
  EXPECT_LT(poseDistance(dolly->pose(dolly->duration()), dolly->pose(0.0f)), 1e-4f);
}

// Small time steps give small moves everywhere, across the loop point included.
TEST(CameraPath, PresetsMoveContinuouslyAndLoopSeamlessly) {
  for (const std::string& name : builtinSceneNames()) {
    const Scene scene = makeBuiltinScene(name);
    for (const char* preset : kMovingPresets) {
      SCOPED_TRACE(name + " " + preset);
      const std::unique_ptr<CameraPath> path = makeCameraPath(preset, scene);
      const float period = path->duration();
      ASSERT_GT(period, 0.0f);
      const float dt = period / 4000;
      float fastest = 0.0f;
      CameraPose previous = path->pose(-period / 2);
      for (float time = -period / 2 + dt; time < 2.5f * period; time += dt) {
        const CameraPose pose = path->pose(time);
        fastest = std::max(fastest, poseDistance(pose, previous) / dt);
        previous = pose;
        EXPECT_EQ(path->segment(time), 0);
      }
      EXPECT_LT(fastest, 15.0f) << "metres per second";
      EXPECT_GT(fastest, 0.1f) << "it should move";
      for (float time : {0.0f, 0.3f * period, 0.9f * period})
        EXPECT_LT(poseDistance(path->pose(time), path->pose(time + period)), 1e-3f) << "periodic";
    }
  }
}

// Every preset keeps the camera inside the built-in scenes' rooms, clear of
// every surface, with a usable view (target away from the eye, up not along it).
TEST(CameraPath, PresetsStayClearOfTheBuiltinScenesGeometry) {
  for (const std::string& name : builtinSceneNames()) {
    const Scene scene = makeBuiltinScene(name);
    for (const char* preset : {"static", "orbit", "dolly", "fly"}) {
      SCOPED_TRACE(name + " " + preset);
      const std::unique_ptr<CameraPath> path = makeCameraPath(preset, scene);
      float nearest = std::numeric_limits<float>::max();
      for (int step = 0; step < 96; ++step) {
        const CameraPose pose = path->pose(path->duration() * float(step) / 96);
        nearest = std::min(nearest, clearance(scene, pose.position));
        const glm::vec3 view = pose.target - pose.position;
        ASSERT_GT(glm::length(view), 0.1f);
        EXPECT_GT(glm::length(glm::cross(glm::normalize(view), pose.up)), 0.3f);
        EXPECT_NEAR(glm::length(pose.up), 1.0f, 1e-5f);
      }
      EXPECT_GT(nearest, 0.25f) << "metres from the nearest surface";
    }
  }
}

TEST(CameraPath, SunRoomPresetsStayInsideTheRoom) {
  const Scene scene = makeBuiltinScene("sun-room");
  for (const char* preset : kMovingPresets) {
    const std::unique_ptr<CameraPath> path = makeCameraPath(preset, scene);
    for (int step = 0; step < 200; ++step) {
      const glm::vec3 p = path->pose(path->duration() * float(step) / 200).position;
      EXPECT_TRUE(p.x > -3 && p.x < 3 && p.y > 0 && p.y < 3 && p.z > -4 && p.z < 4) << preset << " at step " << step;
    }
  }
}

const char* const kFourKeys = R"({"keyframes": [
  {"time": 0, "position": [0, 1, 5], "target": [0, 1, 0], "fovY": 40},
  {"time": 1.5, "position": [2, 1.5, 4], "target": [0.5, 1, 0]},
  {"time": 2, "position": [3, 2, 1], "target": [0, 0.5, 0], "fovY": 60, "up": [0.1, 1, 0]},
  {"time": 4, "position": [1, 1, -2], "target": [0, 1, 0]}
]})";

TEST(CameraKeyframes, PassThroughEveryKeyExactlyAtItsTime) {
  const std::unique_ptr<CameraPath> path = parseCameraKeyframes(kFourKeys, "four.json");
  EXPECT_EQ(path->duration(), 4.0f);
  const glm::vec3 tiltedUp = glm::normalize(glm::vec3(0.1f, 1.0f, 0.0f));
  expectPoseEq(path->pose(0.0f), {{0, 1, 5}, {0, 1, 0}, {0, 1, 0}, 40});
  expectPoseEq(path->pose(1.5f), {{2, 1.5f, 4}, {0.5f, 1, 0}, {0, 1, 0}, 40});  // fovY carries over
  expectPoseEq(path->pose(2.0f), {{3, 2, 1}, {0, 0.5f, 0}, tiltedUp, 60});
  expectPoseEq(path->pose(4.0f), {{1, 1, -2}, {0, 1, 0}, {0, 1, 0}, 60});
  // Held before the first key and after the last.
  expectPoseEq(path->pose(-1.0f), path->pose(0.0f));
  expectPoseEq(path->pose(9.0f), path->pose(4.0f));
  // fovY is linear in time between keys.
  EXPECT_FLOAT_EQ(path->pose(1.75f).fovYDegrees, 50.0f);
  EXPECT_FLOAT_EQ(path->pose(3.0f).fovYDegrees, 60.0f);
  EXPECT_EQ(path->segment(0.0f), 0);
  EXPECT_EQ(path->segment(10.0f), 0);
}

TEST(CameraKeyframes, VelocityIsContinuousThroughInnerKeys) {
  const std::unique_ptr<CameraPath> path = parseCameraKeyframes(kFourKeys, "four.json");
  const float h = 1e-3f;
  for (float key : {1.5f, 2.0f}) {
    const glm::vec3 before = (path->pose(key).position - path->pose(key - h).position) / h;
    const glm::vec3 after = (path->pose(key + h).position - path->pose(key).position) / h;
    EXPECT_LT(glm::length(after - before), 0.05f * glm::length(before)) << "at key time " << key;
  }
  // Smooth between keys: no step larger than the speed allows.
  float fastest = 0.0f;
  for (float time = 0.0f; time < 4.0f; time += 1e-3f)
    fastest = std::max(fastest, glm::length(path->pose(time + 1e-3f).position - path->pose(time).position) / 1e-3f);
  EXPECT_LT(fastest, 10.0f);
}

TEST(CameraKeyframes, TwoKeysMoveInAStraightLineAtConstantSpeed) {
  const std::unique_ptr<CameraPath> path = parseCameraKeyframes(
      R"({"keyframes": [{"time": 1, "position": [0, 1, 4], "target": [0, 1, 0]},
                        {"time": 3, "position": [4, 1, 4], "target": [4, 1, 0]}]})",
      "two.json");
  for (float time : {1.5f, 2.0f, 2.5f}) {
    const CameraPose pose = path->pose(time);
    EXPECT_NEAR(pose.position.x, 2.0f * (time - 1.0f), 1e-5f);
    EXPECT_NEAR(pose.position.z, 4.0f, 1e-6f);
    EXPECT_NEAR(pose.target.x, 2.0f * (time - 1.0f), 1e-5f);
  }
}

TEST(CameraKeyframes, CutsStartNewSegmentsAndAreFlaggedOnTheFirstFrameAtOrAfterThem) {
  const std::string json = R"({"keyframes": [
    {"time": 0, "position": [0, 1, 5], "target": [0, 1, 0]},
    {"time": 1, "position": [1, 1, 5], "target": [0, 1, 0]},
    {"time": 1.05, "position": [10, 3, 0], "target": [0, 1, 0], "cut": true},
    {"time": 2, "position": [10, 3, 4], "target": [0, 1, 0], "cut": false},
    {"time": 3, "position": [-5, 1, 0], "target": [0, 1, 0], "cut": true},
    {"time": 4, "position": [-5, 2, 2], "target": [0, 1, 0]}
  ]})";
  const fs::path file = writeTempFile("bounce_cuts.json", json);
  const std::unique_ptr<CameraPath> path = makeCameraPath(file.string(), makeBuiltinScene("cornell"));
  // No interpolation across a cut: the last key of a segment holds until the jump.
  expectPoseEq(path->pose(1.02f), path->pose(1.0f));
  EXPECT_FLOAT_EQ(path->pose(1.05f).position.x, 10.0f);
  expectPoseEq(path->pose(2.99f), path->pose(2.0f));
  EXPECT_EQ(path->segment(0.5f), 0);
  EXPECT_EQ(path->segment(1.04f), 0);
  EXPECT_EQ(path->segment(1.05f), 1);
  EXPECT_EQ(path->segment(2.5f), 1);
  EXPECT_EQ(path->segment(3.0f), 2);
  // Inside a segment the velocity at its ends is one-sided: 1.05 -> 2 is a straight line.
  EXPECT_NEAR(path->pose(1.525f).position.z, 2.0f, 1e-5f);

  const std::vector<CameraFrame> frames = sampleCameraPath(*path, 45, 10.0f);
  ASSERT_EQ(frames.size(), 45u);
  std::vector<int> cuts;
  for (std::size_t i = 0; i < frames.size(); ++i)
    if (frames[i].cut) cuts.push_back(int(i));
  // Frame 0 (no history), frame 11 (t = 1.1, the first at or after 1.05), frame 30 (t = 3).
  EXPECT_EQ(cuts, (std::vector<int>{0, 11, 30}));
}

TEST(CameraKeyframes, SampledFramesArePosesAtFrameTimes) {
  const std::unique_ptr<CameraPath> path = parseCameraKeyframes(kFourKeys, "four.json");
  const std::vector<CameraFrame> frames = sampleCameraPath(*path, 100, 24.0f);
  ASSERT_EQ(frames.size(), 100u);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    expectPoseEq(frames[i].pose, path->pose(float(i) / 24.0f));
    EXPECT_EQ(frames[i].cut, i == 0);
  }
  EXPECT_TRUE(sampleCameraPath(*path, 0, 24.0f).empty());
  EXPECT_THROW(sampleCameraPath(*path, -1, 24.0f), std::invalid_argument);
  EXPECT_THROW(sampleCameraPath(*path, 10, 0.0f), std::invalid_argument);
  EXPECT_THROW(sampleCameraPath(*path, 10, std::numeric_limits<float>::infinity()), std::invalid_argument);
  EXPECT_THROW(sampleCameraPath(*path, 10, std::numeric_limits<float>::quiet_NaN()), std::invalid_argument);
}

struct KeyframeErrorCase {
  const char* keyframes;  // the JSON array's contents
  int index;              // the keyframe the message must name
  const char* problem;    // a fragment the message must contain
};

TEST(CameraKeyframes, EveryKeyframeErrorNamesTheFileTheKeyframeAndTheProblem) {
  const std::string good = R"({"time": 0, "position": [0, 1, 5], "target": [0, 1, 0]})";
  const KeyframeErrorCase cases[] = {
      {R"({"position": [0, 1, 5], "target": [0, 1, 0]})", 0, "missing 'time'"},
      {R"({"time": 1, "target": [0, 1, 0]})", 1, "missing 'position'"},
      {R"({"time": 1, "position": [0, 1, 5]})", 1, "missing 'target'"},
      {R"({"time": "1", "position": [0, 1, 5], "target": [0, 1, 0]})", 1, "'time' must be a finite number"},
      {R"({"time": 1e39, "position": [0, 1, 5], "target": [0, 1, 0]})", 1, "'time' must be a finite number"},
      {R"({"time": 1, "position": [0, 1], "target": [0, 1, 0]})", 1, "'position' must be an array of 3"},
      {R"({"time": 1, "position": [0, 1, 5, 2], "target": [0, 1, 0]})", 1, "'position' must be an array of 3"},
      {R"({"time": 1, "position": [0, 1, 5], "target": [0, null, 0]})", 1, "'target' must be an array of 3"},
      {R"({"time": 1, "position": [0, -1e39, 5], "target": [0, 1, 0]})", 1, "'position' must be an array of 3"},
      {R"({"time": 1, "position": {"x": 0}, "target": [0, 1, 0]})", 1, "'position' must be an array of 3"},
      {R"({"time": 0, "position": [0, 1, 5], "target": [0, 1, 0]})", 1, "times must strictly increase"},
      {R"({"time": -1, "position": [0, 1, 5], "target": [0, 1, 0]})", 1, "times must strictly increase"},
      {R"({"time": 1, "position": [0, 1, 5], "target": [0, 1, 0], "fovY": 0})", 1, "outside (0, 180)"},
      {R"({"time": 1, "position": [0, 1, 5], "target": [0, 1, 0], "fovY": 180})", 1, "outside (0, 180)"},
      {R"({"time": 1, "position": [0, 1, 5], "target": [0, 1, 0], "fovY": -30})", 1, "outside (0, 180)"},
      {R"({"time": 1, "position": [0, 1, 5], "target": [0, 1, 0], "fovY": 1e40})", 1, "'fovY' must be a finite"},
      {R"({"time": 1, "position": [0, 1, 5], "target": [0, 1, 0], "cut": 1})", 1, "'cut' must be true or false"},
      {R"({"time": 1, "position": [0, 1, 5], "target": [0, 1, 0], "fov": 50})", 1, "unknown field 'fov'"},
      {R"({"time": 1, "position": [2, 2, 2], "target": [2, 2, 2]})", 1, "the same point"},
      {R"({"time": 1, "position": [0, 5, 0], "target": [0, 0, 0]})", 1, "parallel to the default up"},
      {R"({"time": 1, "position": [0, 1, 5], "target": [0, 1, 0], "up": [0, 0, 2]})", 1, "parallel to 'up'"},
      {R"({"time": 1, "position": [0, 1, 5], "target": [0, 1, 0], "up": [0, 0, 0]})", 1, "zero vector"},
      {R"([0, 1, 5])", 1, "expected an object"},
      // JSON keeps the last of a key given twice; the file's author meant one of them.
      {R"({"time": 1, "time": 2, "position": [0, 1, 5], "target": [0, 1, 0]})", 1, "'time' is given more than once"},
      {R"({"time": 0, "position": [0, 1, 5], "target": [0, 1, 0], "position": [0, 1, 6]})", 0,
       "'position' is given more than once"},
  };
  int caseNumber = 0;
  for (const KeyframeErrorCase& c : cases) {
    const std::string json = c.index == 0 ? std::string("{\"keyframes\": [") + c.keyframes + "]}"
                                          : "{\"keyframes\": [" + good + ", " + c.keyframes + "]}";
    const fs::path file = writeTempFile("bounce_bad_keyframe_" + std::to_string(caseNumber++) + ".json", json);
    SCOPED_TRACE(json);
    try {
      makeCameraPath(file.string(), Scene{});
      ADD_FAILURE() << "expected SceneError";
    } catch (const SceneError& error) {
      const std::string message = error.what();
      EXPECT_EQ(message.rfind(file.string() + ": keyframe " + std::to_string(c.index) + ": ", 0), 0u) << message;
      EXPECT_NE(message.find(c.problem), std::string::npos) << message;
    }
  }
}

TEST(CameraKeyframes, DocumentErrorsNameTheFileAndTheProblem) {
  const std::string deep = std::string(20, '[') + std::string(20, ']');
  const std::pair<const char*, const char*> cases[] = {
      {R"({"keyframes": [)", "invalid JSON"},
      {R"({"keyframes": [{"time": 1e999}]})", "invalid JSON"},
      {R"([])", "expected an object"},
      {R"({})", "\"keyframes\" must be an array"},
      {R"({"keyframes": {"time": 0}})", "\"keyframes\" must be an array"},
      {R"({"keyframes": []})", "\"keyframes\" is empty"},
      {R"({"keyframes": [], "loop": true})", "unknown field 'loop'"},
      {R"({"keyframes": [], "keyframes": []})", "'keyframes' is given more than once"},
      {deep.c_str(), "nested deeper than 16 levels"},
  };
  int caseNumber = 0;
  for (const auto& [json, problem] : cases) {
    const fs::path file = writeTempFile("bounce_bad_document_" + std::to_string(caseNumber++) + ".json", json);
    SCOPED_TRACE(json);
    try {
      loadCameraKeyframes(file);
      ADD_FAILURE() << "expected SceneError";
    } catch (const SceneError& error) {
      const std::string message = error.what();
      EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
      EXPECT_NE(message.find(problem), std::string::npos) << message;
    }
  }
  const fs::path missing = fs::path(testing::TempDir()) / "bounce_no_such_path.json";
  try {
    loadCameraKeyframes(missing);
    ADD_FAILURE() << "expected SceneError";
  } catch (const SceneError& error) {
    EXPECT_NE(std::string(error.what()).find(missing.string()), std::string::npos) << error.what();
  }
}

// {"keyframes": [...]} of `count` keys one second apart along +X, every
// `cutEvery`-th a cut (none for 0).
std::string straightKeyframes(std::size_t count, std::size_t cutEvery = 0) {
  std::string json = "{\"keyframes\": [";
  for (std::size_t k = 0; k < count; ++k) {
    const std::string x = std::to_string(k);
    json += (k ? ",\n" : "") + std::string("{\"time\": ") + x + ", \"position\": [" + x + ", 1, 5], \"target\": [" + x +
            ", 1, 0]" + (cutEvery && k > 0 && k % cutEvery == 0 ? ", \"cut\": true" : "") + "}";
  }
  return json + "]}";
}

// A file of more than 100,000 keyframes is refused while it is read (a
// million took 823 MB); 100,000 load, and every frame's cut flag is found by
// bisection, equal to counting the cuts before it.
TEST(CameraKeyframes, AtMostAHundredThousandKeyframesLoadAndCutsAreCountedRight) {
  const fs::path over = writeTempFile("bounce_keyframes_over.json", straightKeyframes(100001));
  try {
    loadCameraKeyframes(over);
    ADD_FAILURE() << "expected SceneError";
  } catch (const SceneError& error) {
    EXPECT_EQ(std::string(error.what()),
              over.string() + ": more than 100000 keyframes (the most a camera file may hold)");
  }
  fs::remove(over);

  const fs::path most = writeTempFile("bounce_keyframes_most.json", straightKeyframes(100000, 7));
  const std::unique_ptr<CameraPath> path = loadCameraKeyframes(most);
  fs::remove(most);
  EXPECT_EQ(path->duration(), 99999.0f);
  EXPECT_EQ(path->pose(54321.0f).position, glm::vec3(54321, 1, 5));
  for (const float time : {-1.0f, 0.0f, 6.5f, 7.0f, 13.9f, 14.0f, 70000.0f, 99998.5f, 99999.0f, 1e6f})
    EXPECT_EQ(path->segment(time), time < 0.0f ? 0 : int(std::min(time, 99999.0f)) / 7) << "at " << time;
  EXPECT_EQ(path->segment(std::numeric_limits<float>::quiet_NaN()), 0);
  const std::vector<CameraFrame> frames = sampleCameraFrames(*path, 0, 1000, 4.0f);
  for (std::size_t i = 0; i < frames.size(); ++i)
    EXPECT_EQ(frames[i].cut, i == 0 || (i % 4 == 0 && (i / 4) % 7 == 0)) << "frame " << i;
}

TEST(CameraPath, UnknownSpecListsThePresets) {
  try {
    makeCameraPath("orbitt", makeBuiltinScene("cornell"));
    FAIL() << "expected SceneError";
  } catch (const SceneError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("'orbitt'"), std::string::npos) << message;
    for (const std::string& preset : cameraPathPresets()) EXPECT_NE(message.find(preset), std::string::npos) << message;
  }
}

// A parent moved +x 2 and, when animated, along +z; a child turned 90
// degrees about +Y (so it looks down -X) holding the camera.
Scene sceneWithCamera(bool animated) {
  Scene scene = triangleScene();
  scene.cameras.push_back({"lens", glm::radians(30.0f), 0.1f});
  Node parent;
  parent.name = "rig";
  parent.local.translation = {2, 1, 0};
  parent.children = {2};
  Node child;
  child.name = "camera";
  child.parent = 1;
  child.camera = 0;
  child.local.rotation = glm::angleAxis(glm::half_pi<float>(), glm::vec3(0, 1, 0));
  scene.nodes.push_back(parent);
  scene.nodes.push_back(child);
  scene.roots = {0, 1};
  if (animated) {
    Animation animation;
    animation.name = "truck";
    animation.channels.push_back({1,
                                  AnimatedProperty::Translation,
                                  Interpolation::Linear,
                                  {0.0f, 2.0f},
                                  {glm::vec4(2, 1, 0, 0), glm::vec4(2, 1, 4, 0)}});
    scene.animations.push_back(animation);
  }
  validate(scene);
  return scene;
}

TEST(CameraPath, GltfCameraFollowsItsNode) {
  const Scene scene = sceneWithCamera(false);
  for (const std::unique_ptr<CameraPath>& path : {makeCameraPath("gltf", scene), defaultCameraPath(scene)}) {
    const CameraPose pose = path->pose(0.0f);
    EXPECT_LT(glm::length(pose.position - glm::vec3(2, 1, 0)), 1e-6f);
    EXPECT_LT(glm::length(glm::normalize(pose.target - pose.position) - glm::vec3(-1, 0, 0)), 1e-6f);
    EXPECT_LT(glm::length(pose.up - glm::vec3(0, 1, 0)), 1e-6f);
    EXPECT_NEAR(pose.fovYDegrees, 30.0f, 1e-4f);
    EXPECT_EQ(path->duration(), 0.0f);
  }
}

TEST(CameraPath, AnimatedGltfCameraMovesAndCutsWhereItsAnimationLoops) {
  std::unique_ptr<CameraPath> path;
  {
    const Scene scene = sceneWithCamera(true);
    path = makeCameraPath("gltf", scene);
  }  // the path keeps what it needs
  EXPECT_EQ(path->duration(), 2.0f);
  EXPECT_LT(glm::length(path->pose(1.0f).position - glm::vec3(2, 1, 2)), 1e-5f);
  const std::vector<CameraFrame> frames = sampleCameraPath(*path, 9, 2.0f);  // t = 0, 0.5, ... 4
  std::vector<int> cuts;
  for (std::size_t i = 0; i < frames.size(); ++i)
    if (frames[i].cut) cuts.push_back(int(i));
  EXPECT_EQ(cuts, (std::vector<int>{0, 4, 8}));  // t = 0, 2, 4: the animation jumps back to z = 0
}

// Three cameras whose depth-first order (front, side, top) is not their
// node order: "gltf:N" counts depth-first, "gltf:NAME" matches a node's or a
// camera's name.
TEST(CameraPath, GltfCamerasArePickedByNumberOrName) {
  Scene scene = triangleScene();
  scene.cameras = {{"side", 0.5f, 0.1f}, {"front", 0.6f, 0.1f}, {"top", 0.7f, 0.1f}};
  const auto cameraNode = [](const char* name, int camera, int parent, glm::vec3 at) {
    Node node;
    node.name = name;
    node.camera = camera;
    node.parent = parent;
    node.local.translation = at;
    return node;
  };
  Node rig;
  rig.name = "rig";
  rig.children = {3, 2};
  scene.nodes.push_back(rig);                                        // 1
  scene.nodes.push_back(cameraNode("side", 0, 1, {5, 0, 0}));        // 2
  scene.nodes.push_back(cameraNode("front node", 1, 1, {0, 0, 5}));  // 3
  scene.nodes.push_back(cameraNode("", 2, -1, {0, 5, 0}));           // 4
  scene.roots = {0, 1, 4};
  validate(scene);
  const auto position = [&](const std::string& spec) { return makeCameraPath(spec, scene)->pose(0.0f).position; };
  EXPECT_EQ(position("gltf"), glm::vec3(0, 0, 5));
  EXPECT_EQ(position("gltf:0"), glm::vec3(0, 0, 5));
  EXPECT_EQ(position("gltf:1"), glm::vec3(5, 0, 0));
  EXPECT_EQ(position("gltf:2"), glm::vec3(0, 5, 0));
  EXPECT_EQ(position("gltf:top"), glm::vec3(0, 5, 0));         // the camera's name
  EXPECT_EQ(position("gltf:front node"), glm::vec3(0, 0, 5));  // the node's name
  EXPECT_NEAR(makeCameraPath("gltf:side", scene)->pose(0.0f).fovYDegrees, glm::degrees(0.5f), 1e-4f);

  const std::string cameras = "its cameras, by number and name: 0 'front' (node 'front node'), 1 'side', 2 'top'";
  for (const auto& [spec, problem] :
       {std::pair{"gltf:3", "has no glTF camera number 3"},
        {"gltf:lens", "has no glTF camera named 'lens'"},
        {"gltf:", "has no glTF camera named ''"},
        {"gltf:99999999999999999999999", "has no glTF camera number 99999999999999999999999"}}) {
    try {
      makeCameraPath(spec, scene);
      ADD_FAILURE() << spec << ": expected SceneError";
    } catch (const SceneError& error) {
      EXPECT_EQ(std::string(error.what()),
                "scene 'triangle' " + std::string(problem) + " (camera path '" + spec + "'); " + cameras);
    }
  }
}

TEST(CameraPath, GltfWithoutACameraNamesTheScene) {
  const Scene scene = makeBuiltinScene("pillars");
  try {
    makeCameraPath("gltf", scene);
    FAIL() << "expected SceneError";
  } catch (const SceneError& error) {
    EXPECT_NE(std::string(error.what()).find("pillars"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace bounce::scene
