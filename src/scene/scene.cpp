// Scene evaluation at a moment (animation sampling, node transforms) and the
// invariant check every scene passes before it reaches the GPU.
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

namespace bounce::scene {
namespace {

std::string where(const Scene& scene) { return scene.source.empty() ? scene.name : scene.source.string(); }

[[noreturn]] void fail(const Scene& scene, const std::string& reason) {
  throw SceneError(where(scene) + ": " + reason);
}

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

// Refuses a light whose strength (value times its colour's largest channel)
// is beyond kMaxLightStrength, naming it: "light 0 'Sun': intensity 3e+38 is
// above ..." or "...: intensity 1e+20 times colour 5 (5e+20) is above ...".
void checkStrength(const Scene& scene, const std::string& what, const char* quantity, float value,
                   const glm::vec3& colour) {
  const double peak = std::max({double(colour.x), double(colour.y), double(colour.z)});
  const double strength = double(value) * peak;
  const std::string problem = lightStrengthProblem(strength);
  if (problem.empty()) return;
  fail(scene, what + ": " + quantity + " " + number(value) +
                  (peak == 1.0 ? "" : " times colour " + number(peak) + " (" + number(strength) + ")") + " is " +
                  problem);
}

glm::vec4 hermite(const glm::vec4& p0, const glm::vec4& m0, const glm::vec4& p1, const glm::vec4& m1, float t,
                  float dt) {
  const float t2 = t * t;
  const float t3 = t2 * t;
  return (2.0f * t3 - 3.0f * t2 + 1.0f) * p0 + (t3 - 2.0f * t2 + t) * dt * m0 + (-2.0f * t3 + 3.0f * t2) * p1 +
         (t3 - t2) * dt * m1;
}

// The channel's value at `time` (clamped to its first and last key).
glm::vec4 sampleChannel(const AnimationChannel& channel, float time) {
  const std::vector<float>& times = channel.times;
  const bool cubic = channel.interpolation == Interpolation::CubicSpline;
  const auto value = [&](std::size_t key) { return channel.values[cubic ? key * 3 + 1 : key]; };
  if (time <= times.front()) return value(0);
  if (time >= times.back()) return value(times.size() - 1);
  const std::size_t next = std::size_t(std::upper_bound(times.begin(), times.end(), time) - times.begin());
  const std::size_t prev = next - 1;
  const float dt = times[next] - times[prev];
  const float t = (time - times[prev]) / dt;
  switch (channel.interpolation) {
    case Interpolation::Step:
      return value(prev);
    case Interpolation::CubicSpline:
      return hermite(value(prev), channel.values[prev * 3 + 2], value(next), channel.values[next * 3], t, dt);
    case Interpolation::Linear:
      break;
  }
  if (channel.property == AnimatedProperty::Rotation) {
    const glm::vec4 a = value(prev);
    const glm::vec4 b = value(next);
    const glm::quat q = glm::slerp(glm::quat(a.w, a.x, a.y, a.z), glm::quat(b.w, b.x, b.y, b.z), t);
    return {q.x, q.y, q.z, q.w};
  }
  return glm::mix(value(prev), value(next), t);
}

float animationLength(const Animation& animation) {
  float length = 0.0f;
  for (const AnimationChannel& channel : animation.channels)
    if (!channel.times.empty()) length = std::max(length, channel.times.back());
  return length;
}

}  // namespace

glm::mat4 Transform::matrix() const {
  return glm::translate(glm::mat4(1.0f), translation) * glm::mat4_cast(rotation) * glm::scale(glm::mat4(1.0f), scale);
}

glm::vec3 Sun::direction() const {
  const float elevation = glm::radians(elevationDegrees);
  const float azimuth = glm::radians(azimuthDegrees);
  return {std::cos(elevation) * std::sin(azimuth), std::sin(elevation), std::cos(elevation) * std::cos(azimuth)};
}

std::vector<Transform> animatedLocalTransforms(const Scene& scene, float time) {
  std::vector<Transform> locals(scene.nodes.size());
  for (std::size_t i = 0; i < scene.nodes.size(); ++i) locals[i] = scene.nodes[i].local;
  for (const Animation& animation : scene.animations) {
    const float length = animationLength(animation);
    const float local = length > 0.0f ? std::fmod(std::max(time, 0.0f), length) : 0.0f;
    for (const AnimationChannel& channel : animation.channels) {
      if (channel.times.empty()) continue;
      const glm::vec4 v = sampleChannel(channel, local);
      Transform& target = locals[std::size_t(channel.node)];
      switch (channel.property) {
        case AnimatedProperty::Translation:
          target.translation = glm::vec3(v);
          break;
        case AnimatedProperty::Rotation:
          target.rotation = glm::normalize(glm::quat(v.w, v.x, v.y, v.z));
          break;
        case AnimatedProperty::Scale:
          target.scale = glm::vec3(v);
          break;
      }
    }
  }
  return locals;
}

std::vector<glm::mat4> nodeWorldMatrices(const Scene& scene, float time) {
  const std::vector<Transform> locals = animatedLocalTransforms(scene, time);
  std::vector<glm::mat4> world(scene.nodes.size(), glm::mat4(1.0f));
  // Depth-first from every parentless node; validate() has ruled out cycles.
  std::vector<int> stack;
  for (std::size_t i = 0; i < scene.nodes.size(); ++i)
    if (scene.nodes[i].parent < 0) stack.push_back(int(i));
  while (!stack.empty()) {
    const int index = stack.back();
    stack.pop_back();
    const Node& node = scene.nodes[std::size_t(index)];
    const glm::mat4 parent = node.parent >= 0 ? world[std::size_t(node.parent)] : glm::mat4(1.0f);
    world[std::size_t(index)] = parent * locals[std::size_t(index)].matrix();
    for (int child : node.children) stack.push_back(child);
  }
  return world;
}

std::vector<Instance> instancesAt(const Scene& scene, float time) {
  const std::vector<glm::mat4> world = nodeWorldMatrices(scene, time);
  std::vector<Instance> instances;
  std::vector<int> stack(scene.roots.rbegin(), scene.roots.rend());
  while (!stack.empty()) {
    const int index = stack.back();
    stack.pop_back();
    const Node& node = scene.nodes[std::size_t(index)];
    for (int mesh : node.meshes) instances.push_back({mesh, index, world[std::size_t(index)]});
    for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) stack.push_back(*child);
  }
  return instances;
}

Bounds worldBounds(const Scene& scene, float time) {
  Bounds bounds;
  for (const Instance& instance : instancesAt(scene, time))
    for (const glm::vec3& p : scene.meshes[std::size_t(instance.mesh)].positions)
      bounds.extend(glm::vec3(instance.objectToWorld * glm::vec4(p, 1.0f)));
  return bounds;
}

std::string lightStrengthProblem(double strength) {
  if (strength <= kMaxLightStrength) return {};
  return "above " + number(kMaxLightStrength) +
         ", the brightest light Bounce renders (radiance beyond it would overflow 32-bit floats)";
}

bool adoptDirectionalLightAsSun(Scene& scene, float time) {
  const std::vector<glm::mat4> world = nodeWorldMatrices(scene, time);
  for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
    const int index = scene.nodes[n].light;
    if (index < 0 || scene.lights[std::size_t(index)].type != LightType::Directional) continue;
    const Light& light = scene.lights[std::size_t(index)];
    // The light shines down its node's -Z; the sun direction points back up the beam.
    const glm::vec3 toSun = glm::normalize(glm::vec3(world[n] * glm::vec4(0.0f, 0.0f, 1.0f, 0.0f)));
    if (!std::isfinite(toSun.x)) continue;
    scene.sun.elevationDegrees = glm::degrees(std::asin(std::clamp(toSun.y, -1.0f, 1.0f)));
    scene.sun.azimuthDegrees = glm::degrees(std::atan2(toSun.x, toSun.z));
    scene.sun.illuminance = light.intensity;
    scene.sun.color = light.color;
    scene.hasSun = true;
    scene.nodes[n].light = -1;
    return true;
  }
  return false;
}

void validate(const Scene& scene) {
  const auto finite = [](const auto& v) {
    for (int i = 0; i < v.length(); ++i)
      if (!std::isfinite(v[i])) return false;
    return true;
  };
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    const std::string name = "mesh " + std::to_string(m) + (mesh.name.empty() ? "" : " '" + mesh.name + "'");
    const std::size_t vertices = mesh.positions.size();
    if (mesh.normals.size() != vertices || mesh.tangents.size() != vertices || mesh.texcoords.size() != vertices)
      fail(scene, name + ": attribute arrays differ in length");
    if (mesh.indices.size() % 3 != 0) fail(scene, name + ": index count is not a multiple of 3");
    for (std::uint32_t index : mesh.indices)
      if (index >= vertices)
        fail(scene,
             name + ": index " + std::to_string(index) + " out of range (" + std::to_string(vertices) + " vertices)");
    for (std::size_t v = 0; v < vertices; ++v)
      if (!finite(mesh.positions[v]) || !finite(mesh.normals[v]) || !finite(mesh.tangents[v]) ||
          !finite(mesh.texcoords[v]))
        fail(scene, name + ": vertex " + std::to_string(v) + " has a NaN or infinite attribute");
    if (mesh.material < 0 || std::size_t(mesh.material) >= scene.materials.size())
      fail(scene, name + ": material index " + std::to_string(mesh.material) + " out of range");
  }
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const Material& material = scene.materials[i];
    for (int texture : {material.baseColorTexture, material.metallicRoughnessTexture, material.normalTexture,
                        material.emissiveTexture, material.occlusionTexture})
      if (texture < -1 || texture >= int(scene.textures.size()))
        fail(scene, "material " + std::to_string(i) + ": texture index " + std::to_string(texture) + " out of range");
    if (!finite(material.baseColorFactor) || !finite(material.emissiveFactor) ||
        !std::isfinite(material.metallicFactor) || !std::isfinite(material.roughnessFactor) ||
        !std::isfinite(material.emissiveStrength))
      fail(scene, "material " + std::to_string(i) + ": a factor is NaN or infinite");
    checkStrength(scene, "material " + std::to_string(i) + (material.name.empty() ? "" : " '" + material.name + "'"),
                  "emissive strength", material.emissiveStrength, material.emissiveFactor);
  }
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& light = scene.lights[i];
    const std::string what = "light " + std::to_string(i) + (light.name.empty() ? "" : " '" + light.name + "'");
    if (!finite(light.color) || !std::isfinite(light.intensity) || light.intensity < 0.0f ||
        !(light.color.x >= 0.0f && light.color.y >= 0.0f && light.color.z >= 0.0f))
      fail(scene, what + ": colour and intensity must be finite and not negative");
    checkStrength(scene, what, "intensity", light.intensity, light.color);
  }
  if (scene.hasSun) checkStrength(scene, "the sun", "illuminance", scene.sun.illuminance, scene.sun.color);
  for (const Texture& texture : scene.textures)
    if (texture.width <= 0 || texture.height <= 0 ||
        texture.rgba8.size() != std::size_t(texture.width) * std::size_t(texture.height) * 4)
      fail(scene, "texture '" + texture.name + "': size and pixel data disagree");

  // Node graph: indices in range, parent and child links that agree, no
  // cycles. Linear in the node count, however deep the hierarchy: a chain of
  // 100,000 nodes is a valid file.
  const int nodeCount = int(scene.nodes.size());
  std::vector<int> timesListed(scene.nodes.size(), 0);
  for (int i = 0; i < nodeCount; ++i) {
    const Node& node = scene.nodes[std::size_t(i)];
    if (node.parent >= nodeCount) fail(scene, "node " + std::to_string(i) + ": parent index out of range");
    for (int child : node.children) {
      if (child < 0 || child >= nodeCount || scene.nodes[std::size_t(child)].parent != i)
        fail(scene, "node " + std::to_string(i) + ": child " + std::to_string(child) + " is invalid");
      if (++timesListed[std::size_t(child)] > 1)
        fail(scene, "node " + std::to_string(i) + ": lists child " + std::to_string(child) + " twice");
    }
    for (int mesh : node.meshes)
      if (mesh < 0 || mesh >= int(scene.meshes.size())) fail(scene, "node " + std::to_string(i) + ": bad mesh index");
    if (node.camera >= int(scene.cameras.size()) || node.light >= int(scene.lights.size()))
      fail(scene, "node " + std::to_string(i) + ": bad camera or light index");
    if (!finite(node.local.translation) || !finite(node.local.scale) ||
        !finite(glm::vec4(node.local.rotation.x, node.local.rotation.y, node.local.rotation.z, node.local.rotation.w)))
      fail(scene, "node " + std::to_string(i) + ": transform has a NaN or infinite value");
  }
  for (int i = 0; i < nodeCount; ++i) {
    const int parent = scene.nodes[std::size_t(i)].parent;
    if (parent >= 0 && timesListed[std::size_t(i)] == 0)
      fail(scene,
           "node " + std::to_string(i) + ": its parent " + std::to_string(parent) + " does not list it as a child");
  }
  // With the links agreeing, the nodes reachable from the parentless ones
  // form trees; any other node lies on a cycle or below one.
  std::vector<bool> reached(scene.nodes.size(), false);
  std::vector<int> stack;
  for (int i = 0; i < nodeCount; ++i)
    if (scene.nodes[std::size_t(i)].parent < 0) stack.push_back(i);
  while (!stack.empty()) {
    const int index = stack.back();
    stack.pop_back();
    reached[std::size_t(index)] = true;
    for (int child : scene.nodes[std::size_t(index)].children) stack.push_back(child);
  }
  if (const auto unreached = std::find(reached.begin(), reached.end(), false); unreached != reached.end()) {
    // Climbing parents from there repeats a node, and that node is on the cycle.
    std::vector<bool> climbed(scene.nodes.size(), false);
    std::size_t onCycle = std::size_t(unreached - reached.begin());
    while (!climbed[onCycle]) {
      climbed[onCycle] = true;
      onCycle = std::size_t(scene.nodes[onCycle].parent);
    }
    fail(scene, "node " + std::to_string(onCycle) + " is part of a cycle in the node graph");
  }
  for (int root : scene.roots)
    if (root < 0 || root >= nodeCount || scene.nodes[std::size_t(root)].parent >= 0)
      fail(scene, "scene root " + std::to_string(root) + " is not a parentless node");
  for (const Animation& animation : scene.animations)
    for (const AnimationChannel& channel : animation.channels) {
      if (channel.node < 0 || channel.node >= nodeCount) fail(scene, "animation '" + animation.name + "': bad node");
      const std::size_t perKey = channel.interpolation == Interpolation::CubicSpline ? 3 : 1;
      if (channel.values.size() != channel.times.size() * perKey)
        fail(scene, "animation '" + animation.name + "': key count and value count disagree");
      for (std::size_t k = 0; k < channel.times.size(); ++k)
        if (!std::isfinite(channel.times[k]) || (k > 0 && !(channel.times[k] > channel.times[k - 1])))
          fail(scene, "animation '" + animation.name + "': key times are not finite and increasing");
      for (const glm::vec4& v : channel.values)
        if (!finite(v)) fail(scene, "animation '" + animation.name + "': a key value is NaN or infinite");
    }
}

}  // namespace bounce::scene
