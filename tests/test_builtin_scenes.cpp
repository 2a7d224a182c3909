// Tests of src/scene/builtin_scenes: every built-in scene is valid, its meshes
// have exact and consistent attributes, and each scene's lighting set-up does
// what it is for (checked by brute-force ray casting against its triangles).
#include "scene/builtin_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <set>

#include <glm/gtc/constants.hpp>

namespace bounce::scene {
namespace {

struct WorldTriangle {
  std::array<glm::vec3, 3> p;
  glm::vec3 normal;  // geometric, from the winding (counter-clockwise front)
  int mesh = -1;
};

std::vector<WorldTriangle> worldTriangles(const Scene& scene, float time = 0.0f) {
  std::vector<WorldTriangle> triangles;
  for (const Instance& instance : instancesAt(scene, time)) {
    const Mesh& mesh = scene.meshes[std::size_t(instance.mesh)];
    for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
      WorldTriangle triangle;
      for (int k = 0; k < 3; ++k)
        triangle.p[std::size_t(k)] =
            glm::vec3(instance.objectToWorld * glm::vec4(mesh.positions[mesh.indices[i + std::size_t(k)]], 1.0f));
      triangle.normal = glm::normalize(glm::cross(triangle.p[1] - triangle.p[0], triangle.p[2] - triangle.p[0]));
      triangle.mesh = instance.mesh;
      triangles.push_back(triangle);
    }
  }
  return triangles;
}

struct Hit {
  float t = 0.0f;
  const WorldTriangle* triangle = nullptr;
};

// Möller-Trumbore, both sides: the ray parameter of the hit, if it is in (tMin, tMax).
std::optional<float> intersect(const glm::vec3& origin, const glm::vec3& direction, const WorldTriangle& triangle,
                               float tMin, float tMax) {
  const glm::vec3 e1 = triangle.p[1] - triangle.p[0];
  const glm::vec3 e2 = triangle.p[2] - triangle.p[0];
  const glm::vec3 pv = glm::cross(direction, e2);
  const float det = glm::dot(e1, pv);
  if (std::abs(det) < 1e-12f) return std::nullopt;
  const glm::vec3 tv = origin - triangle.p[0];
  const float u = glm::dot(tv, pv) / det;
  if (u < 0.0f || u > 1.0f) return std::nullopt;
  const glm::vec3 qv = glm::cross(tv, e1);
  const float v = glm::dot(direction, qv) / det;
  if (v < 0.0f || u + v > 1.0f) return std::nullopt;
  const float t = glm::dot(e2, qv) / det;
  if (t <= tMin || t >= tMax) return std::nullopt;
  return t;
}

std::optional<Hit> closestHit(const std::vector<WorldTriangle>& triangles, const glm::vec3& origin,
                              const glm::vec3& direction, float tMax = 1e30f) {
  std::optional<Hit> best;
  for (const WorldTriangle& triangle : triangles)
    if (const auto t = intersect(origin, direction, triangle, 1e-4f, best ? best->t : tMax)) best = Hit{*t, &triangle};
  return best;
}

// Whether anything among `triangles` lies strictly between a and b.
bool segmentBlocked(const std::vector<WorldTriangle>& triangles, const glm::vec3& a, const glm::vec3& b) {
  return std::any_of(triangles.begin(), triangles.end(), [&](const WorldTriangle& triangle) {
    return intersect(a, b - a, triangle, 1e-4f, 1.0f - 1e-4f).has_value();
  });
}

std::vector<WorldTriangle> trianglesOf(const Scene& scene, const std::vector<WorldTriangle>& all,
                                       const std::string& meshPrefix, bool matching = true) {
  std::vector<WorldTriangle> selected;
  for (const WorldTriangle& triangle : all)
    if ((scene.meshes[std::size_t(triangle.mesh)].name.rfind(meshPrefix, 0) == 0) == matching)
      selected.push_back(triangle);
  return selected;
}

int meshNamed(const Scene& scene, const std::string& name) {
  for (std::size_t i = 0; i < scene.meshes.size(); ++i)
    if (scene.meshes[i].name == name) return int(i);
  ADD_FAILURE() << scene.name << " has no mesh '" << name << "'";
  return -1;
}

Bounds meshWorldBounds(const Scene& scene, int mesh, float time = 0.0f) {
  Bounds bounds;
  for (const WorldTriangle& triangle : worldTriangles(scene, time))
    if (triangle.mesh == mesh)
      for (const glm::vec3& p : triangle.p) bounds.extend(p);
  return bounds;
}

// The one light of `type` in the scene, with its world position and shining direction.
struct PlacedLight {
  const Light* light = nullptr;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f};
};

PlacedLight onlyLight(const Scene& scene, LightType type) {
  PlacedLight placed;
  const std::vector<glm::mat4> world = nodeWorldMatrices(scene, 0.0f);
  int found = 0;
  for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
    const int light = scene.nodes[n].light;
    if (light < 0 || scene.lights[std::size_t(light)].type != type) continue;
    ++found;
    placed.light = &scene.lights[std::size_t(light)];
    placed.position = glm::vec3(world[n][3]);
    placed.direction = glm::normalize(glm::vec3(world[n] * glm::vec4(0, 0, -1, 0)));
  }
  EXPECT_EQ(found, 1) << scene.name;
  return placed;
}

// Unit directions spread evenly over the sphere (Fibonacci lattice).
std::vector<glm::vec3> sphereDirections(int count) {
  std::vector<glm::vec3> directions;
  const float golden = glm::pi<float>() * (3.0f - std::sqrt(5.0f));
  for (int i = 0; i < count; ++i) {
    const float y = 1.0f - 2.0f * (float(i) + 0.5f) / float(count);
    const float r = std::sqrt(1.0f - y * y);
    directions.push_back({r * std::cos(golden * float(i)), y, r * std::sin(golden * float(i))});
  }
  return directions;
}

// Directions of rays through a grid over a 16:9 image seen from `pose`.
std::vector<glm::vec3> cameraRays(const CameraPose& pose, int columns, int rows) {
  const glm::vec3 forward = glm::normalize(pose.target - pose.position);
  const glm::vec3 right = glm::normalize(glm::cross(forward, pose.up));
  const glm::vec3 up = glm::cross(right, forward);
  const float tanHalf = std::tan(glm::radians(pose.fovYDegrees) / 2);
  std::vector<glm::vec3> rays;
  for (int row = 0; row < rows; ++row)
    for (int column = 0; column < columns; ++column) {
      const float x = (2.0f * (float(column) + 0.5f) / float(columns) - 1.0f) * tanHalf * 16.0f / 9.0f;
      const float y = (1.0f - 2.0f * (float(row) + 0.5f) / float(rows)) * tanHalf;
      rays.push_back(glm::normalize(forward + x * right + y * up));
    }
  return rays;
}

// Whether `point` shows in a 16:9 image from `pose`, unhidden.
bool visibleFrom(const CameraPose& pose, const std::vector<WorldTriangle>& triangles, const glm::vec3& point) {
  const glm::vec3 forward = glm::normalize(pose.target - pose.position);
  const glm::vec3 right = glm::normalize(glm::cross(forward, pose.up));
  const glm::vec3 up = glm::cross(right, forward);
  const glm::vec3 d = point - pose.position;
  const float depth = glm::dot(d, forward);
  const float tanHalf = std::tan(glm::radians(pose.fovYDegrees) / 2);
  if (depth <= 0.0f || std::abs(glm::dot(d, up)) > depth * tanHalf ||
      std::abs(glm::dot(d, right)) > depth * tanHalf * 16.0f / 9.0f)
    return false;
  return !segmentBlocked(triangles, pose.position, point - 1e-3f * glm::normalize(d));
}

// The window of sun-room, as builtin_scenes.h documents it.
constexpr float kWindowX = 3.0f;
constexpr glm::vec2 kWindowY(0.8f, 2.4f), kWindowZ(-1.2f, 1.2f);

bool throughWindow(const glm::vec3& origin, const glm::vec3& direction) {
  if (direction.x <= 0.0f) return false;
  const glm::vec3 p = origin + direction * ((kWindowX - origin.x) / direction.x);
  return p.y > kWindowY[0] && p.y < kWindowY[1] && p.z > kWindowZ[0] && p.z < kWindowZ[1];
}

TEST(BuiltinScenes, NamesAreListedAndRecognised) {
  const std::vector<std::string> names = builtinSceneNames();
  EXPECT_EQ(names, (std::vector<std::string>{"cornell", "pillars", "sun-room", "sun-room-animated"}));
  for (const std::string& name : names) EXPECT_TRUE(isBuiltinScene(name)) << name;
  EXPECT_FALSE(isBuiltinScene(""));
  EXPECT_FALSE(isBuiltinScene("Cornell"));
  EXPECT_FALSE(isBuiltinScene("sun-room.gltf"));
  EXPECT_TRUE(isBuiltinScene(defaultBuiltinScene()));
}

TEST(BuiltinScenes, UnknownNameListsTheValidNames) {
  try {
    makeBuiltinScene("cornel");
    FAIL() << "expected SceneError";
  } catch (const SceneError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("'cornel'"), std::string::npos) << message;
    for (const std::string& name : builtinSceneNames()) EXPECT_NE(message.find(name), std::string::npos) << message;
  }
}

TEST(BuiltinScenes, EveryOneIsValidWithACameraAndEveryMeshPlaced) {
  for (const std::string& name : builtinSceneNames()) {
    SCOPED_TRACE(name);
    const Scene scene = makeBuiltinScene(name);
    EXPECT_NO_THROW(validate(scene));
    EXPECT_EQ(scene.name, name);
    EXPECT_TRUE(scene.source.empty());
    EXPECT_TRUE(scene.textures.empty());
    ASSERT_TRUE(scene.suggestedCamera.has_value());
    const CameraPose& camera = *scene.suggestedCamera;
    EXPECT_GT(glm::length(camera.target - camera.position), 1.0f);
    EXPECT_GT(camera.fovYDegrees, 10.0f);
    EXPECT_LT(camera.fovYDegrees, 90.0f);
    EXPECT_FALSE(worldBounds(scene, 0.0f).empty());
    std::set<int> placed;
    for (const Instance& instance : instancesAt(scene, 0.0f)) placed.insert(instance.mesh);
    EXPECT_EQ(placed.size(), scene.meshes.size()) << "a mesh no node draws";
    for (const Material& material : scene.materials) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_GE(material.baseColorFactor[c], 0.0f) << material.name;
        EXPECT_LE(material.baseColorFactor[c], 1.0f) << material.name;
      }
      EXPECT_GE(material.roughnessFactor, 0.0f);
      EXPECT_LE(material.roughnessFactor, 1.0f);
    }
  }
}

// Unit normals agreeing with the winding; tangents unit, perpendicular, along
// increasing u, and w = +1 with the bitangent towards decreasing v (glTF).
TEST(BuiltinScenes, MeshAttributesAreExactAndAgreeWithWindingAndTextureCoordinates) {
  for (const std::string& name : builtinSceneNames()) {
    const Scene scene = makeBuiltinScene(name);
    for (const Mesh& mesh : scene.meshes) {
      SCOPED_TRACE(name + ": " + mesh.name);
      ASSERT_FALSE(mesh.indices.empty());
      for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        EXPECT_NEAR(glm::length(mesh.normals[v]), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::length(glm::vec3(mesh.tangents[v])), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(mesh.normals[v], glm::vec3(mesh.tangents[v])), 0.0f, 1e-5f);
        EXPECT_EQ(mesh.tangents[v].w, 1.0f);
      }
      int bad = 0;
      for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
        const std::array<std::uint32_t, 3> idx = {mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]};
        const glm::vec3 e1 = mesh.positions[idx[1]] - mesh.positions[idx[0]];
        const glm::vec3 e2 = mesh.positions[idx[2]] - mesh.positions[idx[0]];
        const glm::vec2 d1 = mesh.texcoords[idx[1]] - mesh.texcoords[idx[0]];
        const glm::vec2 d2 = mesh.texcoords[idx[2]] - mesh.texcoords[idx[0]];
        const glm::vec3 cross = glm::cross(e1, e2);
        const float uvArea = d1.x * d2.y - d2.x * d1.y;
        if (glm::length(cross) < 1e-6f || std::abs(uvArea) < 1e-8f) {
          ++bad;  // degenerate in space or in texture space
          continue;
        }
        const glm::vec3 faceNormal = glm::normalize(cross);
        const glm::vec3 dPdu = (e1 * d2.y - e2 * d1.y) / uvArea;
        const glm::vec3 dPdv = (e2 * d1.x - e1 * d2.x) / uvArea;
        for (std::uint32_t k : idx) {
          const glm::vec3 n = mesh.normals[k];
          const glm::vec3 t(mesh.tangents[k]);
          if (glm::dot(n, faceNormal) < 0.99f || glm::dot(t, glm::normalize(dPdu)) < 0.99f ||
              glm::dot(glm::cross(n, t) * mesh.tangents[k].w, dPdv) >= 0.0f)
            ++bad;
        }
      }
      EXPECT_EQ(bad, 0);
    }
  }
}

// Every mesh but the Cornell box's light (a single quad) is made of closed
// solids with outward normals: each directed edge is matched by its reverse,
// and the signed volume is positive.
TEST(BuiltinScenes, SolidsAreClosedWithOutwardNormals) {
  for (const std::string& name : builtinSceneNames()) {
    const Scene scene = makeBuiltinScene(name);
    for (const Mesh& mesh : scene.meshes) {
      if (name == "cornell" && mesh.name == "ceiling light") continue;
      SCOPED_TRACE(name + ": " + mesh.name);
      std::map<std::array<float, 6>, int> edges;
      double volume = 0.0;
      for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
        const std::array<glm::vec3, 3> p = {mesh.positions[mesh.indices[i]], mesh.positions[mesh.indices[i + 1]],
                                            mesh.positions[mesh.indices[i + 2]]};
        volume += glm::dot(p[0], glm::cross(p[1], p[2])) / 6.0;
        for (std::size_t k = 0; k < 3; ++k) {
          const glm::vec3 a = p[k], b = p[(k + 1) % 3];
          ++edges[{a.x, a.y, a.z, b.x, b.y, b.z}];
        }
      }
      int unmatched = 0;
      for (const auto& [edge, count] : edges) {
        const auto reverse = edges.find({edge[3], edge[4], edge[5], edge[0], edge[1], edge[2]});
        if (reverse == edges.end() || reverse->second != count) ++unmatched;
      }
      EXPECT_EQ(unmatched, 0);
      EXPECT_GT(volume, 0.0);
    }
  }
}

// What the suggested camera sees faces it: no back faces, and no view of the
// outside except through the Cornell box's open front and the sun-room's window.
TEST(BuiltinScenes, TheSuggestedCameraSeesOnlyFrontFaces) {
  for (const std::string& name : builtinSceneNames()) {
    SCOPED_TRACE(name);
    const Scene scene = makeBuiltinScene(name);
    const std::vector<WorldTriangle> triangles = worldTriangles(scene);
    const CameraPose& camera = *scene.suggestedCamera;
    const bool sunRoom = name.rfind("sun-room", 0) == 0;
    int backFaces = 0, leaks = 0, throughOpening = 0;
    for (const glm::vec3& ray : cameraRays(camera, 48, 27)) {
      const std::optional<Hit> hit = closestHit(triangles, camera.position, ray);
      if (hit) {
        backFaces += glm::dot(hit->triangle->normal, ray) >= 0.0f ? 1 : 0;
      } else if (name == "cornell" || (sunRoom && throughWindow(camera.position, ray))) {
        ++throughOpening;
      } else {
        ++leaks;
      }
    }
    EXPECT_EQ(backFaces, 0);
    EXPECT_EQ(leaks, 0);
    if (name == "cornell" || sunRoom) {
      EXPECT_GT(throughOpening, 0) << "the opening should be in view";
    }
  }
}

TEST(BuiltinScenes, CornellHasItsLightInsideTheBoxBelowTheCeilingPointingDown) {
  const Scene scene = makeBuiltinScene("cornell");
  EXPECT_FALSE(scene.hasSun);
  const float size = 5.55f, half = size / 2;
  const Bounds emitterBounds = meshWorldBounds(scene, meshNamed(scene, "ceiling light"));
  const Bounds tallBox = meshWorldBounds(scene, meshNamed(scene, "tall box"));
  EXPECT_NEAR(tallBox.max.y, 3.30f, 1e-4f);
  EXPECT_NEAR(meshWorldBounds(scene, meshNamed(scene, "short box")).max.y, 1.65f, 1e-4f);

  // The emissive quad: just under the ceiling, facing down, radiance 10-20.
  EXPECT_LT(emitterBounds.max.y, size);
  EXPECT_GT(emitterBounds.min.y, size - 0.05f);
  const Mesh& quad = scene.meshes[std::size_t(meshNamed(scene, "ceiling light"))];
  for (const glm::vec3& normal : quad.normals) EXPECT_LT(glm::length(normal - glm::vec3(0, -1, 0)), 1e-6f);
  const Material& emitter = scene.materials[std::size_t(quad.material)];
  const glm::vec3 radiance = emitter.emissiveFactor * emitter.emissiveStrength;
  const float peak = std::max({radiance.x, radiance.y, radiance.z});
  EXPECT_GE(peak, 10.0f);
  EXPECT_LE(peak, 20.0f);

  // The spot light: inside the box, under the quad, above the tall box, shining down.
  const PlacedLight spot = onlyLight(scene, LightType::Spot);
  ASSERT_NE(spot.light, nullptr);
  EXPECT_GT(spot.position.x, -half);
  EXPECT_LT(spot.position.x, half);
  EXPECT_GT(spot.position.z, -size);
  EXPECT_LT(spot.position.z, 0.0f);
  EXPECT_LT(spot.position.y, emitterBounds.min.y);
  EXPECT_GT(spot.position.y, tallBox.max.y);
  EXPECT_GT(spot.position.x, emitterBounds.min.x);
  EXPECT_LT(spot.position.x, emitterBounds.max.x);
  EXPECT_GT(spot.position.z, emitterBounds.min.z);
  EXPECT_LT(spot.position.z, emitterBounds.max.z);
  EXPECT_NEAR(spot.direction.y, -1.0f, 1e-6f);
  // Its intensity straight down is the quad's: radiance * area, in every channel.
  const glm::vec2 quadSize(emitterBounds.extent().x, emitterBounds.extent().z);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(spot.light->color[c] * spot.light->intensity, radiance[c] * quadSize.x * quadSize.y, 1e-3f);
  EXPECT_NEAR(spot.light->outerConeAngle, glm::half_pi<float>(), 1e-6f);

  // Its light reaches the floor, and the red wall is on the camera's left.
  const std::vector<WorldTriangle> triangles = worldTriangles(scene);
  EXPECT_FALSE(segmentBlocked(triangles, spot.position, {0.0f, 1e-3f, -size / 2}));
  const CameraPose& camera = *scene.suggestedCamera;
  const glm::vec3 right = glm::cross(camera.target - camera.position, camera.up);
  EXPECT_LT(glm::dot(meshWorldBounds(scene, meshNamed(scene, "red wall")).center() - camera.position, right), 0.0f);
  EXPECT_GT(glm::dot(meshWorldBounds(scene, meshNamed(scene, "green wall")).center() - camera.position, right), 0.0f);
}

TEST(BuiltinScenes, PillarsAreGoldOnAGlossyFloor) {
  const Scene scene = makeBuiltinScene("pillars");
  EXPECT_FALSE(scene.hasSun);
  std::vector<std::pair<float, float>> xAndRoughness;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    if (scene.meshes[m].name.rfind("pillar", 0) != 0) continue;
    const Material& gold = scene.materials[std::size_t(scene.meshes[m].material)];
    EXPECT_EQ(gold.metallicFactor, 1.0f);
    EXPECT_EQ(gold.baseColorFactor, glm::vec4(1.0f, 0.78f, 0.34f, 1.0f));
    xAndRoughness.push_back({meshWorldBounds(scene, int(m)).center().x, gold.roughnessFactor});
  }
  ASSERT_EQ(xAndRoughness.size(), 5u);
  std::sort(xAndRoughness.begin(), xAndRoughness.end());
  for (std::size_t i = 0; i < 5; ++i) EXPECT_NEAR(xAndRoughness[i].second, 0.2f * float(i + 1), 1e-6f);
  const Material& floor = scene.materials[std::size_t(scene.meshes[std::size_t(meshNamed(scene, "floor"))].material)];
  EXPECT_EQ(floor.metallicFactor, 0.0f);
  EXPECT_GE(floor.roughnessFactor, 0.1f);
  EXPECT_LE(floor.roughnessFactor, 0.2f);
}

// The heart of the scene: no point of any pillar has a line to the light that
// misses the ceiling, while the floor in front of the pillars, in view of the
// camera, is lit directly.
TEST(BuiltinScenes, PillarsSeeTheLightOnlyThroughBounces) {
  const Scene scene = makeBuiltinScene("pillars");
  const PlacedLight light = onlyLight(scene, LightType::Point);
  ASSERT_NE(light.light, nullptr);
  EXPECT_GT(light.light->intensity, 100.0f);
  const std::vector<WorldTriangle> all = worldTriangles(scene);
  const std::vector<WorldTriangle> pillars = trianglesOf(scene, all, "pillar");
  const std::vector<WorldTriangle> ceiling = trianglesOf(scene, all, "ceiling");
  ASSERT_FALSE(pillars.empty());
  ASSERT_FALSE(ceiling.empty());

  // Every vertex, centroid and random interior point of every pillar triangle,
  // lifted 1 mm off the surface.
  std::mt19937 random(3);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<glm::vec3> samples;
  for (const WorldTriangle& triangle : pillars) {
    std::vector<glm::vec3> barycentrics = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, glm::vec3(1.0f / 3)};
    for (int k = 0; k < 4; ++k) {
      float a = uniform(random), b = uniform(random);
      if (a + b > 1.0f) {  // fold the square onto the triangle
        a = 1.0f - a;
        b = 1.0f - b;
      }
      barycentrics.push_back({1.0f - a - b, a, b});
    }
    for (const glm::vec3& w : barycentrics)
      samples.push_back(w.x * triangle.p[0] + w.y * triangle.p[1] + w.z * triangle.p[2] + 1e-3f * triangle.normal);
  }
  int seeTheLight = 0;
  for (const glm::vec3& point : samples)
    if (!segmentBlocked(ceiling, point, light.position)) ++seeTheLight;
  EXPECT_EQ(seeTheLight, 0) << "of " << samples.size() << " pillar points";

  const glm::vec3 litFloor(0.0f, 1e-3f, 3.0f);
  EXPECT_FALSE(segmentBlocked(all, litFloor, light.position));
  EXPECT_TRUE(visibleFrom(*scene.suggestedCamera, all, litFloor));
  for (const WorldTriangle& triangle : pillars)
    for (const glm::vec3& p : triangle.p) EXPECT_LT(p.z, litFloor.z - 1.0f);
}

// Floor points (1 mm up) on a 10 cm grid over the room, and whether the sun reaches them.
std::vector<std::pair<glm::vec3, bool>> sunOnTheFloor(const Scene& scene, float time) {
  const std::vector<WorldTriangle> triangles = worldTriangles(scene, time);
  const glm::vec3 toSun = scene.sun.direction();
  std::vector<std::pair<glm::vec3, bool>> points;
  for (float x = -2.95f; x < 3.0f; x += 0.1f)
    for (float z = -3.95f; z < 4.0f; z += 0.1f) {
      const glm::vec3 p(x, 1e-3f, z);
      points.push_back({p, !closestHit(triangles, p, toSun).has_value()});
    }
  return points;
}

TEST(BuiltinScenes, SunRoomSunComesThroughTheWindowOntoASmallPatchOfFloor) {
  const Scene scene = makeBuiltinScene("sun-room");
  EXPECT_TRUE(scene.hasSun);
  EXPECT_GT(scene.sun.illuminance, 0.0f);
  const std::vector<std::pair<glm::vec3, bool>> floor = sunOnTheFloor(scene, 0.0f);
  glm::vec3 patchCentre(0.0f);
  int sunlit = 0;
  for (const auto& [point, lit] : floor) {
    if (!lit) continue;
    ++sunlit;
    patchCentre += point;
    EXPECT_TRUE(throughWindow(point, scene.sun.direction())) << point.x << ", " << point.z;
  }
  ASSERT_GT(sunlit, 0);
  patchCentre /= float(sunlit);
  // A patch, not the whole floor: bounce light lights most of the room.
  const float fraction = float(sunlit) / float(floor.size());
  EXPECT_GT(fraction, 0.02f);
  EXPECT_LT(fraction, 0.25f);
  EXPECT_TRUE(visibleFrom(*scene.suggestedCamera, worldTriangles(scene), patchCentre));
}

// From anywhere inside, every direction meets a wall's inner face, except through the window.
TEST(BuiltinScenes, SunRoomIsClosedExceptForTheWindow) {
  const Scene scene = makeBuiltinScene("sun-room");
  const std::vector<WorldTriangle> triangles = worldTriangles(scene);
  for (const glm::vec3& origin : {glm::vec3(0.0f, 1.5f, 0.0f), glm::vec3(2.5f, 0.3f, 3.5f),
                                  glm::vec3(-2.0f, 2.8f, -3.0f), scene.suggestedCamera->position}) {
    int leaks = 0, backFaces = 0, escapes = 0;
    for (const glm::vec3& direction : sphereDirections(2000)) {
      const std::optional<Hit> hit = closestHit(triangles, origin, direction);
      if (!hit) {
        ++escapes;
        if (!throughWindow(origin, direction)) ++leaks;
      } else if (glm::dot(hit->triangle->normal, direction) >= 0.0f) {
        ++backFaces;
      }
    }
    EXPECT_EQ(leaks, 0) << origin.x << ", " << origin.y << ", " << origin.z;
    EXPECT_EQ(backFaces, 0);
    EXPECT_GT(escapes, 0) << "the window should be visible from everywhere tested";
  }
}

TEST(BuiltinScenes, SunRoomAnimatedBoxSlidesThroughTheSunPatchAndLoops) {
  const Scene scene = makeBuiltinScene("sun-room-animated");
  ASSERT_TRUE(isAnimated(scene));
  const int box = meshNamed(scene, "sliding box");
  const std::vector<Animation>& animations = scene.animations;
  ASSERT_EQ(animations.size(), 1u);
  float loop = 0.0f;
  for (const AnimationChannel& channel : animations[0].channels) loop = std::max(loop, channel.times.back());
  EXPECT_NEAR(loop, 6.0f, 1e-6f);

  // Seamless: the end of the loop is where it starts.
  const Bounds start = meshWorldBounds(scene, box, 0.0f);
  const Bounds nearEnd = meshWorldBounds(scene, box, loop - 1e-3f);
  EXPECT_LT(glm::length(start.min - nearEnd.min) + glm::length(start.max - nearEnd.max), 1e-2f);
  EXPECT_GT(glm::length(meshWorldBounds(scene, box, loop / 4).center() - start.center()), 1.0f);

  // Never inside the furniture or the walls.
  std::vector<Bounds> furniture;
  for (const char* name : {"table", "cabinet", "ottoman"})
    furniture.push_back(meshWorldBounds(scene, meshNamed(scene, name)));
  for (int step = 0; step < 120; ++step) {
    const Bounds moving = meshWorldBounds(scene, box, loop * float(step) / 120);
    EXPECT_GE(moving.min.x, -3.0f);
    EXPECT_LE(moving.max.x, 3.0f);
    EXPECT_GE(moving.min.z, -4.0f);
    EXPECT_LE(moving.max.z, 4.0f);
    for (const Bounds& other : furniture) {
      const bool overlap =
          glm::all(glm::lessThan(moving.min, other.max)) && glm::all(glm::lessThan(other.min, moving.max));
      EXPECT_FALSE(overlap) << "at step " << step;
    }
  }

  // At the turn-around of the loop the box is out of the sun patch; half way it shades part of it.
  const std::vector<std::pair<glm::vec3, bool>> atStart = sunOnTheFloor(scene, 0.0f);
  const std::vector<std::pair<glm::vec3, bool>> halfWay = sunOnTheFloor(scene, loop / 4);
  const std::vector<std::pair<glm::vec3, bool>> still = sunOnTheFloor(makeBuiltinScene("sun-room"), 0.0f);
  int shaded = 0;
  for (std::size_t i = 0; i < atStart.size(); ++i) {
    EXPECT_EQ(atStart[i].second, still[i].second);
    if (atStart[i].second && !halfWay[i].second) ++shaded;
  }
  EXPECT_GT(shaded, 10);
}

}  // namespace
}  // namespace bounce::scene
