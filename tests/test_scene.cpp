// Tests of src/scene/scene: transforms, animation sampling, instances, validation.
#include "scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

namespace bounce::scene {
namespace {

Mesh triangleMesh() {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.normals.assign(3, {0, 0, 1});
  mesh.tangents.assign(3, {1, 0, 0, 1});
  mesh.texcoords.assign(3, {0, 0});
  mesh.indices = {0, 1, 2};
  return mesh;
}

// parent (translated by +x 2) -> child (rotated 90 degrees about y) holding the triangle.
Scene twoNodeScene() {
  Scene scene;
  scene.name = "test";
  scene.materials.push_back({});
  scene.meshes.push_back(triangleMesh());
  Node parent;
  parent.local.translation = {2, 0, 0};
  parent.children = {1};
  Node child;
  child.parent = 0;
  child.local.rotation = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 1, 0));
  child.meshes = {0};
  scene.nodes = {parent, child};
  scene.roots = {0};
  return scene;
}

// What validate() says of a scene: its error, or "no error".
std::string messageOf(const Scene& scene) {
  try {
    validate(scene);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "no error";
}

void expectNear(const glm::vec3& a, const glm::vec3& b, float tolerance = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(Scene, ChildTransformsComposeParentFirst) {
  const Scene scene = twoNodeScene();
  const std::vector<Instance> instances = instancesAt(scene, 0.0f);
  ASSERT_EQ(instances.size(), 1u);
  // Rotating (1,0,0) by 90 degrees about +y gives (0,0,-1); then +2 in x.
  expectNear(glm::vec3(instances[0].objectToWorld * glm::vec4(1, 0, 0, 1)), {2, 0, -1});
  const Bounds bounds = worldBounds(scene, 0.0f);
  expectNear(bounds.min, {2, 0, -1});
  expectNear(bounds.max, {2, 1, 0});
}

TEST(Scene, LinearStepAndRotationChannelsInterpolate) {
  Scene scene = twoNodeScene();
  Animation animation;
  animation.channels.push_back({0,
                                AnimatedProperty::Translation,
                                Interpolation::Linear,
                                {0.0f, 2.0f},
                                {glm::vec4(0, 0, 0, 0), glm::vec4(4, 0, 0, 0)}});
  animation.channels.push_back({1,
                                AnimatedProperty::Scale,
                                Interpolation::Step,
                                {0.0f, 1.0f, 2.0f},
                                {glm::vec4(1), glm::vec4(3), glm::vec4(5)}});
  const glm::quat turn = glm::angleAxis(glm::radians(120.0f), glm::vec3(0, 0, 1));
  animation.channels.push_back({1,
                                AnimatedProperty::Rotation,
                                Interpolation::Linear,
                                {0.0f, 2.0f},
                                {glm::vec4(0, 0, 0, 1), glm::vec4(turn.x, turn.y, turn.z, turn.w)}});
  scene.animations.push_back(animation);
  validate(scene);

  const std::vector<Transform> at = animatedLocalTransforms(scene, 0.5f);
  expectNear(at[0].translation, {1, 0, 0});
  expectNear(at[1].scale, glm::vec3(1));  // step holds the earlier key
  // A quarter of the way to 120 degrees about z is 30 degrees (slerp, not lerp).
  expectNear(at[1].rotation * glm::vec3(1, 0, 0), {std::cos(glm::radians(30.0f)), std::sin(glm::radians(30.0f)), 0});
  expectNear(animatedLocalTransforms(scene, 1.5f)[1].scale, glm::vec3(3));
  // The animation is 2 s long and loops.
  expectNear(animatedLocalTransforms(scene, 2.5f)[0].translation, {1, 0, 0});
}

TEST(Scene, CubicSplineUsesTangents) {
  Scene scene = twoNodeScene();
  // p0 = 0, p1 = 0, out-tangent of key 0 = 1, in-tangent of key 1 = 0: the
  // Hermite curve at t = 0.5 over dt = 1 is (t^3 - 2t^2 + t) * 1 = 0.125.
  Animation animation;
  animation.channels.push_back({0,
                                AnimatedProperty::Translation,
                                Interpolation::CubicSpline,
                                {0.0f, 1.0f},
                                {glm::vec4(0), glm::vec4(0), glm::vec4(1, 0, 0, 0),  //
                                 glm::vec4(0), glm::vec4(0), glm::vec4(0)}});
  scene.animations.push_back(animation);
  validate(scene);
  EXPECT_NEAR(animatedLocalTransforms(scene, 0.5f)[0].translation.x, 0.125f, 1e-6f);
}

TEST(Scene, ValidateNamesTheProblem) {
  EXPECT_EQ(messageOf(twoNodeScene()), "no error");

  Scene badIndex = twoNodeScene();
  badIndex.meshes[0].indices[2] = 7;
  EXPECT_EQ(messageOf(badIndex), "test: mesh 0: index 7 out of range (3 vertices)");

  Scene nan = twoNodeScene();
  nan.meshes[0].positions[1].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(messageOf(nan), "test: mesh 0: vertex 1 has a NaN or infinite attribute");

  Scene cycle = twoNodeScene();
  cycle.nodes[0].parent = 1;
  cycle.nodes[1].children = {0};
  cycle.roots = {};
  EXPECT_NE(messageOf(cycle).find("cycle"), std::string::npos) << messageOf(cycle);

  Scene badMaterial = twoNodeScene();
  badMaterial.meshes[0].material = 3;
  EXPECT_EQ(messageOf(badMaterial), "test: mesh 0: material index 3 out of range");

  Scene listedTwice = twoNodeScene();
  listedTwice.nodes[0].children = {1, 1};
  EXPECT_EQ(messageOf(listedTwice), "test: node 0: lists child 1 twice");

  Scene disowned = twoNodeScene();
  disowned.nodes[0].children = {};
  EXPECT_EQ(messageOf(disowned), "test: node 1: its parent 0 does not list it as a child");

  // Node 1 -> 2 -> 3 -> 1 is a cycle, node 4 hangs below it: the cycle is named.
  Scene loop = twoNodeScene();
  loop.nodes.resize(5);
  loop.nodes[0].children = {};
  for (const auto& [parent, child] : {std::pair{1, 2}, {2, 3}, {3, 1}, {3, 4}}) {
    loop.nodes[std::size_t(parent)].children.push_back(child);
    loop.nodes[std::size_t(child)].parent = parent;
  }
  EXPECT_EQ(messageOf(loop), "test: node 1 is part of a cycle in the node graph");
}

// A chain of a million nodes, each a step up from its parent, with the
// triangle at its end: validation and everything else that walks the
// hierarchy must be linear in the node count (validate() used to climb every
// node's parent chain, which on this chain takes hours).
TEST(Scene, AMillionNodeChainIsValidatedAndPlacedInLinearTime) {
  constexpr int kNodes = 1000000;
  Scene chain;
  chain.name = "chain";
  chain.materials.push_back({});
  chain.meshes.push_back(triangleMesh());
  chain.nodes.resize(kNodes);
  for (int i = 0; i < kNodes; ++i) {
    Node& node = chain.nodes[std::size_t(i)];
    node.local.translation = {0, 1, 0};
    node.parent = i - 1;
    if (i + 1 < kNodes) node.children = {i + 1};
  }
  chain.nodes.back().meshes = {0};
  chain.roots = {0};
  validate(chain);
  // Sums of whole numbers below 2^24 are exact in float.
  const std::vector<Instance> instances = instancesAt(chain, 0.0f);
  ASSERT_EQ(instances.size(), 1u);
  EXPECT_EQ(glm::vec3(instances[0].objectToWorld[3]), glm::vec3(0, kNodes, 0));
  EXPECT_EQ(worldBounds(chain, 0.0f).max, glm::vec3(1, kNodes + 1, 0));

  // Closed into a ring, it is refused just as quickly.
  chain.nodes.front().parent = kNodes - 1;
  chain.nodes.back().children = {0};
  chain.roots = {};
  EXPECT_THROW(validate(chain), SceneError);
}

// Lights whose radiance would overflow 32-bit floats are refused by name;
// at the limit they are accepted.
TEST(Scene, LightsBeyondTheStrengthLimitAreRefusedByName) {
  Scene lit = twoNodeScene();
  Light lamp;
  lamp.name = "lamp";
  lamp.intensity = 1e20f;
  lit.lights = {lamp};
  EXPECT_EQ(messageOf(lit), "no error");
  lit.lights[0].intensity = 3e38f;
  EXPECT_EQ(messageOf(lit),
            "test: light 0 'lamp': intensity 3e+38 is above 1e+20, the brightest light Bounce renders (radiance "
            "beyond it would overflow 32-bit floats)");
  lit.lights[0].intensity = 1e20f;
  lit.lights[0].color = glm::vec3(1.0f, 5.0f, 1.0f);
  EXPECT_EQ(messageOf(lit).rfind("test: light 0 'lamp': intensity 1e+20 times colour 5 (5e+20) is above 1e+20", 0), 0u)
      << messageOf(lit);

  Scene sunny = twoNodeScene();
  sunny.sun.illuminance = 1e30f;
  EXPECT_NE(messageOf(sunny).find("the sun: illuminance 1e+30"), std::string::npos) << messageOf(sunny);
  sunny.hasSun = false;
  EXPECT_EQ(messageOf(sunny), "no error") << "a scene without sun does not use it";

  Scene glowing = twoNodeScene();
  glowing.materials[0].emissiveFactor = glm::vec3(1.0f);
  glowing.materials[0].emissiveStrength = 2e38f;
  EXPECT_NE(messageOf(glowing).find("material 0"), std::string::npos) << messageOf(glowing);
  EXPECT_NE(messageOf(glowing).find("emissive strength 2e+38"), std::string::npos) << messageOf(glowing);
}

TEST(Scene, SunDirectionFollowsElevationAndAzimuth) {
  Sun sun;
  sun.elevationDegrees = 90.0f;
  expectNear(sun.direction(), {0, 1, 0});
  sun.elevationDegrees = 0.0f;
  sun.azimuthDegrees = 90.0f;
  expectNear(sun.direction(), {1, 0, 0});
}

TEST(Scene, DirectionalLightBecomesTheSun) {
  Scene scene = twoNodeScene();
  EXPECT_FALSE(adoptDirectionalLightAsSun(scene));
  Light light;
  light.type = LightType::Directional;
  light.intensity = 7.0f;
  light.color = {1.0f, 0.5f, 0.25f};
  scene.lights.push_back(light);
  // Tilted 30 degrees down from the horizon about x: the beam goes down-ish
  // along -z, so the sun is up at 30 degrees toward +z.
  scene.nodes[0].local.rotation = glm::angleAxis(glm::radians(-30.0f), glm::vec3(1, 0, 0));
  scene.nodes[0].light = 0;
  ASSERT_TRUE(adoptDirectionalLightAsSun(scene));
  EXPECT_NEAR(scene.sun.elevationDegrees, 30.0f, 1e-4f);
  EXPECT_NEAR(scene.sun.azimuthDegrees, 0.0f, 1e-4f);
  EXPECT_EQ(scene.sun.illuminance, 7.0f);
  EXPECT_EQ(scene.nodes[0].light, -1) << "the light must not be drawn a second time";
}

}  // namespace
}  // namespace bounce::scene
