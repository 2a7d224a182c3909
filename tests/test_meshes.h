// Meshes with known geometry for tests that need analytic answers, and the
// cameras and renderer options those tests look at them with.
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/gtc/constants.hpp>

#include "render/frame_renderer.h"
#include "scene/scene.h"

namespace bounce::testing {

// A square in the y = 0 plane, halfSize to either side of the origin, facing +Y.
inline scene::Mesh planeMesh(float halfSize) {
  scene::Mesh mesh;
  mesh.positions = {
      {-halfSize, 0, -halfSize}, {halfSize, 0, -halfSize}, {halfSize, 0, halfSize}, {-halfSize, 0, halfSize}};
  mesh.normals.assign(4, {0, 1, 0});
  mesh.tangents.assign(4, {1, 0, 0, 1});
  mesh.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.indices = {0, 2, 1, 0, 3, 2};
  return mesh;
}

// A UV sphere of unit radius around the origin, smooth normals.
inline scene::Mesh sphereMesh(int segments, int rings) {
  scene::Mesh mesh;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const float theta = glm::pi<float>() * float(r) / float(rings);
      const float phi = 2.0f * glm::pi<float>() * float(s) / float(segments);
      const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      mesh.positions.push_back(n);
      mesh.normals.push_back(n);
      mesh.tangents.emplace_back(-std::sin(phi), 0.0f, std::cos(phi), 1.0f);
      mesh.texcoords.emplace_back(float(s) / float(segments), float(r) / float(rings));
    }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const std::uint32_t a = std::uint32_t(r * (segments + 1) + s), b = a + std::uint32_t(segments + 1);
      mesh.indices.insert(mesh.indices.end(), {a, a + 1, b, a + 1, b + 1, b});
    }
  return mesh;
}

// A camera at `position` looking at `target`.
inline scene::CameraPose cameraAt(glm::vec3 position, glm::vec3 target, float fovYDegrees) {
  scene::CameraPose pose;
  pose.position = position;
  pose.target = target;
  pose.fovYDegrees = fovYDegrees;
  return pose;
}

// Options to render `s` at a test's small size: its sun, and a sky baked
// 32 pixels wide (plenty for images this small, and quick on lavapipe);
// `environment` carries any other environment setting (a map, intensity).
inline render::FrameRendererOptions smallRendererOptions(const scene::Scene& s, std::uint32_t width,
                                                         std::uint32_t height,
                                                         render::EnvironmentDesc environment = {}) {
  render::FrameRendererOptions options;
  options.width = width;
  options.height = height;
  options.environment = environment;
  options.environment.sun = s.sun;
  options.environment.hasSun = s.hasSun;
  options.environment.skyWidth = 32;
  return options;
}

}  // namespace bounce::testing
