// The built-in scenes of builtin_scenes.h, built from boxes, quads and
// cylinders with exact normals, tangents and texture coordinates.
#include "scene/builtin_scenes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <utility>

#include <glm/gtc/constants.hpp>

namespace bounce::scene {
namespace {

// Appends the parallelogram origin + s * uEdge + t * vEdge (s, t in [0, 1]) as
// two triangles facing cross(uEdge, vEdge). Texture coordinates are in metres:
// u grows along uEdge and v shrinks along vEdge, so that the tangent is uEdge
// with w = +1 in the glTF convention (bitangent towards decreasing v).
void appendQuad(Mesh& mesh, const glm::vec3& origin, const glm::vec3& uEdge, const glm::vec3& vEdge) {
  const glm::vec3 normal = glm::normalize(glm::cross(uEdge, vEdge));
  const glm::vec4 tangent(glm::normalize(uEdge), 1.0f);
  const float width = glm::length(uEdge);
  const float height = glm::length(vEdge);
  const auto first = std::uint32_t(mesh.positions.size());
  const std::array<glm::vec2, 4> corners = {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)};
  for (const glm::vec2& st : corners) {
    mesh.positions.push_back(origin + st.x * uEdge + st.y * vEdge);
    mesh.normals.push_back(normal);
    mesh.tangents.push_back(tangent);
    mesh.texcoords.push_back({st.x * width, (1.0f - st.y) * height});
  }
  for (std::uint32_t corner : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(first + corner);
}

// Appends the closed axis-aligned box [lo, hi], every face pointing out of it;
// side faces have their texture upright (v edge along +Y).
void appendBox(Mesh& mesh, const glm::vec3& lo, const glm::vec3& hi) {
  const glm::vec3 size = hi - lo;
  const glm::vec3 dx(size.x, 0, 0), dy(0, size.y, 0), dz(0, 0, size.z);
  appendQuad(mesh, {hi.x, lo.y, hi.z}, -dz, dy);  // +X
  appendQuad(mesh, {lo.x, lo.y, lo.z}, dz, dy);   // -X
  appendQuad(mesh, {lo.x, lo.y, hi.z}, dx, dy);   // +Z
  appendQuad(mesh, {hi.x, lo.y, lo.z}, -dx, dy);  // -Z
  appendQuad(mesh, {lo.x, hi.y, hi.z}, dx, -dz);  // +Y
  appendQuad(mesh, {lo.x, lo.y, lo.z}, dx, dz);   // -Y
}

// Appends a closed cylinder around +Y standing on y = 0: smooth side (radial
// normals, tangent around the axis, v along the height) and flat caps. The
// ring positions are shared bit for bit by the side and the caps, so the
// surface is closed.
void appendCylinder(Mesh& mesh, float radius, float height, int segments) {
  std::vector<glm::vec2> ring(std::size_t(segments) + 1);  // (x, z), last == first
  for (int i = 0; i <= segments; ++i) {
    const float angle = glm::two_pi<float>() * float(i % segments) / float(segments);
    ring[std::size_t(i)] = {radius * std::sin(angle), radius * std::cos(angle)};
  }
  const auto side = std::uint32_t(mesh.positions.size());
  for (int i = 0; i <= segments; ++i) {
    const glm::vec2 p = ring[std::size_t(i)];
    const glm::vec3 normal = glm::normalize(glm::vec3(p.x, 0.0f, p.y));
    const glm::vec4 tangent(normal.z, 0.0f, -normal.x, 1.0f);  // direction of increasing angle
    const float u = glm::two_pi<float>() * radius * float(i) / float(segments);
    for (float y : {0.0f, height}) {
      mesh.positions.push_back({p.x, y, p.y});
      mesh.normals.push_back(normal);
      mesh.tangents.push_back(tangent);
      mesh.texcoords.push_back({u, height - y});
    }
  }
  for (int i = 0; i < segments; ++i) {
    const std::uint32_t bottom = side + 2 * std::uint32_t(i), top = bottom + 1;
    const std::uint32_t nextBottom = bottom + 2, nextTop = bottom + 3;
    for (std::uint32_t index : {bottom, nextBottom, nextTop, bottom, nextTop, top}) mesh.indices.push_back(index);
  }
  // Caps: fans around the axis. Top: normal +Y, uv (x, z); bottom: normal -Y,
  // uv (x, -z); both keep tangent +X with w = +1.
  for (const bool top : {true, false}) {
    const float y = top ? height : 0.0f;
    const glm::vec3 normal(0.0f, top ? 1.0f : -1.0f, 0.0f);
    const auto centre = std::uint32_t(mesh.positions.size());
    const auto addVertex = [&](glm::vec2 p) {
      mesh.positions.push_back({p.x, y, p.y});
      mesh.normals.push_back(normal);
      mesh.tangents.push_back({1.0f, 0.0f, 0.0f, 1.0f});
      mesh.texcoords.push_back({p.x, top ? p.y : -p.y});
    };
    addVertex({0.0f, 0.0f});
    for (int i = 0; i <= segments; ++i) addVertex(ring[std::size_t(i)]);
    for (std::uint32_t i = 0; i < std::uint32_t(segments); ++i) {
      const std::uint32_t a = centre + 1 + i, b = a + 1;
      for (std::uint32_t index : top ? std::array{centre, a, b} : std::array{centre, b, a})
        mesh.indices.push_back(index);
    }
  }
}

Material diffuse(std::string name, glm::vec3 albedo, float roughness = 0.9f) {
  Material material;
  material.name = std::move(name);
  material.baseColorFactor = glm::vec4(albedo, 1.0f);
  material.metallicFactor = 0.0f;
  material.roughnessFactor = roughness;
  return material;
}

glm::quat yaw(float degrees) { return glm::angleAxis(glm::radians(degrees), glm::vec3(0, 1, 0)); }

// Collects materials, meshes and nodes; every node is a root.
class SceneBuilder {
 public:
  explicit SceneBuilder(std::string name) { scene_.name = std::move(name); }

  int material(Material material) {
    scene_.materials.push_back(std::move(material));
    return int(scene_.materials.size()) - 1;
  }

  // A node holding `mesh` (drawn with `material`) placed by `transform`; returns the node index.
  int object(std::string name, Mesh mesh, int material, const Transform& transform = {}) {
    mesh.name = name;
    mesh.material = material;
    scene_.meshes.push_back(std::move(mesh));
    Node node;
    node.name = std::move(name);
    node.local = transform;
    node.meshes = {int(scene_.meshes.size()) - 1};
    return addRoot(std::move(node));
  }

  int light(Light light, const Transform& transform) {
    Node node;
    node.name = light.name;
    node.local = transform;
    scene_.lights.push_back(std::move(light));
    node.light = int(scene_.lights.size()) - 1;
    return addRoot(std::move(node));
  }

  Scene& scene() { return scene_; }

 private:
  int addRoot(Node node) {
    scene_.nodes.push_back(std::move(node));
    const int index = int(scene_.nodes.size()) - 1;
    scene_.roots.push_back(index);
    return index;
  }

  Scene scene_;
};

Mesh box(const glm::vec3& lo, const glm::vec3& hi) {
  Mesh mesh;
  appendBox(mesh, lo, hi);
  return mesh;
}

// A box of the given size standing on y = 0, centred on the Y axis (for nodes that place and turn it).
Mesh standingBox(const glm::vec3& size) {
  return box({-size.x / 2, 0.0f, -size.z / 2}, {size.x / 2, size.y, size.z / 2});
}

Transform at(const glm::vec3& translation, const glm::quat& rotation = {1, 0, 0, 0}) {
  Transform transform;
  transform.translation = translation;
  transform.rotation = rotation;
  return transform;
}

// Light node rotation that turns its -Z (the direction a spot shines) to -Y.
const glm::quat kPointDown = glm::angleAxis(-glm::half_pi<float>(), glm::vec3(1, 0, 0));

Scene makeCornell() {
  constexpr float kSize = 5.55f;  // the original 555 mm, scaled by 10 to a room-sized box
  constexpr float kHalf = kSize / 2;
  constexpr float kWall = 0.1f;  // slab thickness, outside the interior
  SceneBuilder builder("cornell");
  // Reflectances commonly used for the Cornell box in RGB renderers.
  const int white = builder.material(diffuse("cornell white", {0.73f, 0.73f, 0.73f}, 1.0f));
  const int red = builder.material(diffuse("cornell red", {0.63f, 0.065f, 0.05f}, 1.0f));
  const int green = builder.material(diffuse("cornell green", {0.14f, 0.45f, 0.091f}, 1.0f));
  Material emitter = diffuse("cornell light", {0.78f, 0.78f, 0.78f}, 1.0f);
  emitter.emissiveFactor = {1.0f, 0.85f, 0.6f};  // warm, like the original's incandescent light
  emitter.emissiveStrength = 17.0f;
  const glm::vec3 emittedRadiance = emitter.emissiveFactor * emitter.emissiveStrength;
  const int light = builder.material(emitter);

  Mesh shell;  // floor, ceiling and back wall; open at the front (z = 0)
  appendBox(shell, {-kHalf - kWall, -kWall, -kSize - kWall}, {kHalf + kWall, 0.0f, 0.0f});
  appendBox(shell, {-kHalf - kWall, kSize, -kSize - kWall}, {kHalf + kWall, kSize + kWall, 0.0f});
  appendBox(shell, {-kHalf - kWall, 0.0f, -kSize - kWall}, {kHalf + kWall, kSize, -kSize});
  builder.object("floor, ceiling and back wall", std::move(shell), white);
  builder.object("red wall", box({-kHalf - kWall, 0.0f, -kSize}, {-kHalf, kSize, 0.0f}), red);
  builder.object("green wall", box({kHalf, 0.0f, -kSize}, {kHalf + kWall, kSize, 0.0f}), green);
  // The original blocks' centres and turns. This frame is the original's turned half a turn about +Y
  // (x and z negated, so the camera looks down -Z), which keeps the turns' signs.
  builder.object("tall box", standingBox({1.65f, 3.30f, 1.65f}), white, at({-0.905f, 0.0f, -3.5125f}, yaw(17.0f)));
  builder.object("short box", standingBox({1.65f, 1.65f, 1.65f}), white, at({0.925f, 0.0f, -1.69f}, yaw(-17.0f)));

  // The original's 130 x 105 mm light, facing down 1 cm below the ceiling.
  const glm::vec2 lightSize(1.30f, 1.05f);
  const float lightY = kSize - 0.01f;
  const float lightZ = -kSize / 2;
  Mesh quad;
  appendQuad(quad, {-lightSize.x / 2, lightY, lightZ - lightSize.y / 2}, {lightSize.x, 0, 0}, {0, 0, lightSize.y});
  builder.object("ceiling light", std::move(quad), light);

  Light spot;
  spot.name = "ceiling light (punctual)";
  spot.type = LightType::Spot;
  const float peak = std::max({emittedRadiance.x, emittedRadiance.y, emittedRadiance.z});
  spot.color = emittedRadiance / peak;
  spot.intensity = peak * lightSize.x * lightSize.y;
  spot.innerConeAngle = 0.0f;
  spot.outerConeAngle = glm::half_pi<float>();
  builder.light(spot, at({0.0f, lightY - 0.1f, lightZ}, kPointDown));

  Scene& scene = builder.scene();
  scene.hasSun = false;
  scene.suggestedCamera = CameraPose{{0.0f, 2.73f, 8.0f}, {0.0f, 2.73f, 0.0f}, {0.0f, 1.0f, 0.0f}, 39.3f};
  return std::move(scene);
}

Scene makePillars() {
  constexpr float kWall = 0.2f;
  const glm::vec3 lo(-7.0f, 0.0f, -4.0f), hi(7.0f, 5.0f, 9.0f);  // the hall's interior
  const float slotZ0 = 2.5f, slotZ1 = 3.5f, slotHalfWidth = 5.0f;
  SceneBuilder builder("pillars");
  const int floorMaterial = builder.material(diffuse("polished dark stone", {0.3f, 0.3f, 0.32f}, 0.15f));
  const int wallMaterial = builder.material(diffuse("plaster", {0.75f, 0.75f, 0.75f}));

  builder.object("floor", box({lo.x - kWall, lo.y - kWall, lo.z - kWall}, {hi.x + kWall, lo.y, hi.z + kWall}),
                 floorMaterial);
  Mesh walls;
  appendBox(walls, {lo.x - kWall, lo.y, lo.z - kWall}, {hi.x + kWall, hi.y, lo.z});  // back
  appendBox(walls, {lo.x - kWall, lo.y, hi.z}, {hi.x + kWall, hi.y, hi.z + kWall});  // front
  appendBox(walls, {lo.x - kWall, lo.y, lo.z}, {lo.x, hi.y, hi.z});                  // left
  appendBox(walls, {hi.x, lo.y, lo.z}, {hi.x + kWall, hi.y, hi.z});                  // right
  builder.object("walls", std::move(walls), wallMaterial);
  // The ceiling is the wall that hides the light: four slabs around the slot.
  Mesh ceiling;
  const float top = hi.y + kWall;
  appendBox(ceiling, {lo.x - kWall, hi.y, lo.z - kWall}, {hi.x + kWall, top, slotZ0});
  appendBox(ceiling, {lo.x - kWall, hi.y, slotZ1}, {hi.x + kWall, top, hi.z + kWall});
  appendBox(ceiling, {lo.x - kWall, hi.y, slotZ0}, {-slotHalfWidth, top, slotZ1});
  appendBox(ceiling, {slotHalfWidth, hi.y, slotZ0}, {hi.x + kWall, top, slotZ1});
  builder.object("ceiling", std::move(ceiling), wallMaterial);

  for (int i = 0; i < 5; ++i) {
    const float roughness = 0.2f * float(i + 1);
    Material gold;
    char name[32];
    std::snprintf(name, sizeof name, "gold, roughness %.1f", roughness);
    gold.name = name;
    gold.baseColorFactor = {1.0f, 0.78f, 0.34f, 1.0f};
    gold.metallicFactor = 1.0f;
    gold.roughnessFactor = roughness;
    Mesh pillar;
    appendCylinder(pillar, 0.3f, 2.5f, 48);
    builder.object("pillar " + std::to_string(i + 1), std::move(pillar), builder.material(gold),
                   at({-3.2f + 1.6f * float(i), 0.0f, 0.0f}));
  }

  Light bulb;
  bulb.name = "light above the ceiling slot";
  bulb.type = LightType::Point;
  bulb.color = {1.0f, 0.95f, 0.85f};
  bulb.intensity = 1200.0f;
  builder.light(bulb, at({0.0f, 8.0f, (slotZ0 + slotZ1) / 2}));

  Scene& scene = builder.scene();
  scene.hasSun = false;
  scene.suggestedCamera = CameraPose{{0.0f, 1.6f, 7.5f}, {0.0f, 1.1f, 0.0f}, {0.0f, 1.0f, 0.0f}, 45.0f};
  return std::move(scene);
}

// The room of sun-room; returns the builder so that sun-room-animated can add to it.
SceneBuilder sunRoomBuilder(std::string name) {
  constexpr float kWall = 0.2f;
  const glm::vec3 lo(-3.0f, 0.0f, -4.0f), hi(3.0f, 3.0f, 4.0f);  // the room's interior
  const glm::vec2 windowZ(-1.2f, 1.2f), windowY(0.8f, 2.4f);     // the opening in the +X wall
  SceneBuilder builder(std::move(name));
  const int wood = builder.material(diffuse("oak floor", {0.6f, 0.42f, 0.28f}, 0.5f));
  const int paint = builder.material(diffuse("white paint", {0.8f, 0.8f, 0.8f}));
  const int ceilingPaint = builder.material(diffuse("ceiling paint", {0.85f, 0.85f, 0.85f}));

  builder.object("floor", box({lo.x - kWall, lo.y - kWall, lo.z - kWall}, {hi.x + kWall, lo.y, hi.z + kWall}), wood);
  builder.object("ceiling", box({lo.x - kWall, hi.y, lo.z - kWall}, {hi.x + kWall, hi.y + kWall, hi.z + kWall}),
                 ceilingPaint);
  Mesh walls;
  appendBox(walls, {lo.x - kWall, lo.y, lo.z - kWall}, {hi.x + kWall, hi.y, lo.z});  // -Z
  appendBox(walls, {lo.x - kWall, lo.y, hi.z}, {hi.x + kWall, hi.y, hi.z + kWall});  // +Z
  appendBox(walls, {lo.x - kWall, lo.y, lo.z}, {lo.x, hi.y, hi.z});                  // -X
  // +X: the window wall, four slabs around the opening.
  appendBox(walls, {hi.x, lo.y, lo.z}, {hi.x + kWall, windowY[0], hi.z});
  appendBox(walls, {hi.x, windowY[1], lo.z}, {hi.x + kWall, hi.y, hi.z});
  appendBox(walls, {hi.x, windowY[0], lo.z}, {hi.x + kWall, windowY[1], windowZ[0]});
  appendBox(walls, {hi.x, windowY[0], windowZ[1]}, {hi.x + kWall, windowY[1], hi.z});
  builder.object("walls", std::move(walls), paint);

  // Furniture, all away from the sun patch so that it falls on the floor.
  const int tableWood = builder.material(diffuse("walnut", {0.35f, 0.2f, 0.12f}, 0.6f));
  Mesh table;
  const glm::vec2 tableX(-2.3f, -1.1f), tableZ(-2.8f, -2.0f);
  const float tableHeight = 0.75f, topThickness = 0.05f, leg = 0.06f;
  appendBox(table, {tableX[0], tableHeight - topThickness, tableZ[0]}, {tableX[1], tableHeight, tableZ[1]});
  for (float x : {tableX[0], tableX[1] - leg})
    for (float z : {tableZ[0], tableZ[1] - leg})
      appendBox(table, {x, 0.0f, z}, {x + leg, tableHeight - topThickness, z + leg});
  builder.object("table", std::move(table), tableWood);
  builder.object("cabinet", box({lo.x, 0.0f, 1.6f}, {lo.x + 0.55f, 1.9f, 2.8f}),
                 builder.material(diffuse("blue lacquer", {0.1f, 0.2f, 0.5f}, 0.4f)));
  builder.object("ottoman", standingBox({0.7f, 0.45f, 0.7f}),
                 builder.material(diffuse("red fabric", {0.7f, 0.15f, 0.1f}, 1.0f)), at({1.6f, 0.0f, -2.8f}));

  Scene& scene = builder.scene();
  scene.hasSun = true;
  // Low enough to reach the middle of the floor through the window, from
  // slightly behind the window's -Z side so the patch is a parallelogram.
  scene.sun.elevationDegrees = 35.0f;
  scene.sun.azimuthDegrees = 105.0f;
  // Brighter than the default sun so that the bounce-lit room reads at exposure 1.
  scene.sun.illuminance = 10.0f;
  scene.suggestedCamera = CameraPose{{-2.5f, 1.65f, 3.5f}, {1.2f, 0.9f, -0.8f}, {0.0f, 1.0f, 0.0f}, 55.0f};
  return builder;
}

Scene makeSunRoom() { return std::move(sunRoomBuilder("sun-room").scene()); }

Scene makeSunRoomAnimated() {
  SceneBuilder builder = sunRoomBuilder("sun-room-animated");
  const float size = 0.5f;
  const int node =
      builder.object("sliding box", standingBox(glm::vec3(size)),
                     builder.material(diffuse("yellow paint", {0.8f, 0.6f, 0.1f}, 0.5f)), at({0.8f, 0.0f, -2.5f}));
  Animation animation;
  animation.name = "box slides through the sun patch";
  constexpr float kLoop = 6.0f;
  // There and back again, so the loop is seamless.
  animation.channels.push_back(
      {node,
       AnimatedProperty::Translation,
       Interpolation::Linear,
       {0.0f, kLoop / 2, kLoop},
       {glm::vec4(0.8f, 0.0f, -2.5f, 0.0f), glm::vec4(0.8f, 0.0f, 2.5f, 0.0f), glm::vec4(0.8f, 0.0f, -2.5f, 0.0f)}});
  // A full turn in quarter turns: slerp takes the short way, and 360 degrees ends where 0 began.
  AnimationChannel turn{node, AnimatedProperty::Rotation, Interpolation::Linear, {}, {}};
  for (int quarter = 0; quarter <= 4; ++quarter) {
    const glm::quat q = yaw(90.0f * float(quarter));
    turn.times.push_back(kLoop * float(quarter) / 4);
    turn.values.push_back({q.x, q.y, q.z, q.w});
  }
  animation.channels.push_back(std::move(turn));
  builder.scene().animations.push_back(std::move(animation));
  return std::move(builder.scene());
}

struct BuiltinScene {
  const char* name;
  Scene (*make)();
};

constexpr std::array<BuiltinScene, 4> kBuiltins = {{
    {"cornell", makeCornell},
    {"pillars", makePillars},
    {"sun-room", makeSunRoom},
    {"sun-room-animated", makeSunRoomAnimated},
}};

}  // namespace

std::vector<std::string> builtinSceneNames() {
  std::vector<std::string> names;
  for (const BuiltinScene& builtin : kBuiltins) names.emplace_back(builtin.name);
  return names;
}

bool isBuiltinScene(std::string_view name) {
  return std::any_of(kBuiltins.begin(), kBuiltins.end(), [&](const BuiltinScene& b) { return name == b.name; });
}

// sun-room: nearly all of the room is lit only by bounce light from a small
// sun patch, so indirect light is most of the picture (in cornell the spot
// light reaches almost every visible surface directly), and it exercises the
// sun and sky too.
const char* defaultBuiltinScene() { return "sun-room"; }

Scene makeBuiltinScene(std::string_view name) {
  for (const BuiltinScene& builtin : kBuiltins)
    if (name == builtin.name) {
      Scene scene = builtin.make();
      validate(scene);
      return scene;
    }
  std::string names;
  for (const BuiltinScene& builtin : kBuiltins) names += std::string(names.empty() ? "" : ", ") + builtin.name;
  throw SceneError("unknown built-in scene '" + std::string(name) + "' (built-in scenes: " + names + ")");
}

}  // namespace bounce::scene
