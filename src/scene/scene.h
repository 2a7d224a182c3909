// The scene: what a glTF file or a built-in generator produces, and what the
// renderer draws. Plain data on the CPU; nothing here knows Vulkan.
//
// Shapes follow glTF 2.0 closely (nodes with local transforms, meshes made of
// triangle primitives, metallic-roughness materials, KHR_lights_punctual
// lights, node animations), so an importer fills it without translation and
// a reader who knows glTF knows this. Units: metres, radians, glTF light
// units (directional: illuminance; point/spot: intensity, irradiance falls
// off as intensity / distance^2).
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace bounce::scene {

// Any problem with a scene: what() names the file (or built-in scene) and the reason.
class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An 8-bit RGBA texture as decoded from its file. Whether the values are sRGB
// (base colour, emissive) or linear (metallic-roughness, normal, occlusion)
// follows from how materials use it (Texture::srgb), as in glTF.
struct Texture {
  std::string name;  // the file, or "image N of scene.gltf"; used in messages
  int width = 0;
  int height = 0;
  bool srgb = false;
  std::vector<std::uint8_t> rgba8;  // width * height * 4, row 0 at the top
};

enum class AlphaMode { Opaque, Mask, Blend };  // Blend is drawn as Mask (no transparency yet)

// glTF metallic-roughness material; texture indices are into Scene::textures
// (-1 = none) and always use texture coordinate set 0.
struct Material {
  std::string name;
  glm::vec4 baseColorFactor{1.0f};  // linear
  float metallicFactor = 1.0f;
  float roughnessFactor = 1.0f;  // perceptual roughness; GGX alpha = r * r
  glm::vec3 emissiveFactor{0.0f};
  float emissiveStrength = 1.0f;  // KHR_materials_emissive_strength
  float normalScale = 1.0f;
  float occlusionStrength = 1.0f;
  AlphaMode alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;
  bool doubleSided = false;
  int baseColorTexture = -1;
  int metallicRoughnessTexture = -1;  // G = roughness, B = metallic
  int normalTexture = -1;             // tangent space, +Y up (glTF)
  int emissiveTexture = -1;
  int occlusionTexture = -1;  // R
};

// One triangle primitive. Every attribute array is filled (normals and
// tangents are generated when the file has none), one entry per vertex.
struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;      // unit length
  std::vector<glm::vec4> tangents;     // xyz unit, w = bitangent sign (+1 or -1)
  std::vector<glm::vec2> texcoords;    // set 0; zeros when the file has none
  std::vector<std::uint32_t> indices;  // triangle list, 3 per triangle
  int material = 0;                    // index into Scene::materials
};

struct Transform {
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // w, x, y, z
  glm::vec3 scale{1.0f};
  glm::mat4 matrix() const;  // T * R * S
};

struct Node {
  std::string name;
  int parent = -1;
  std::vector<int> children;
  Transform local;          // rest pose (animations override per property)
  std::vector<int> meshes;  // indices into Scene::meshes (a glTF mesh's primitives)
  int camera = -1;          // index into Scene::cameras
  int light = -1;           // index into Scene::lights
};

enum class AnimatedProperty { Translation, Rotation, Scale };
enum class Interpolation { Linear, Step, CubicSpline };

struct AnimationChannel {
  int node = -1;
  AnimatedProperty property = AnimatedProperty::Translation;
  Interpolation interpolation = Interpolation::Linear;
  std::vector<float> times;  // seconds, strictly increasing
  // One value per key (xyz, or quaternion xyzw for rotation); CubicSpline keys
  // hold three values each (in-tangent, value, out-tangent), as in glTF.
  std::vector<glm::vec4> values;
};

struct Animation {
  std::string name;
  std::vector<AnimationChannel> channels;
};

enum class LightType { Directional, Point, Spot };

// KHR_lights_punctual. Position and direction come from the node that holds
// the light; a light shines down its node's -Z axis.
struct Light {
  std::string name;
  LightType type = LightType::Point;
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  float range = 0.0f;  // 0 = infinite
  float innerConeAngle = 0.0f;
  float outerConeAngle = 0.7853982f;
};

struct CameraDesc {
  std::string name;
  float yfov = 0.7853982f;  // radians
  float znear = 0.05f;
};

// The sun: a directional light that the sky model also uses, so the two agree.
struct Sun {
  float elevationDegrees = 50.0f;  // above the horizon
  float azimuthDegrees = 30.0f;    // from +Z towards +X
  float illuminance = 3.0f;        // irradiance on a surface facing the sun
  glm::vec3 color{1.0f, 0.96f, 0.9f};
  glm::vec3 direction() const;  // unit vector towards the sun
};

// A camera placement at one moment.
struct CameraPose {
  glm::vec3 position{0.0f, 1.6f, 5.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovYDegrees = 45.0f;
};

struct Scene {
  std::string name;              // "cornell", or the file name
  std::filesystem::path source;  // empty for built-in scenes
  // Every file the scene was read from: the glTF or GLB file, then each
  // buffer and image file it refers to. No command may write over them.
  std::vector<std::filesystem::path> files;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Node> nodes;
  std::vector<int> roots;  // nodes of the displayed glTF scene without a parent
  std::vector<Animation> animations;
  std::vector<CameraDesc> cameras;
  std::vector<Light> lights;
  Sun sun;
  bool hasSun = true;  // false: no sunlight (and a night-dark sky), e.g. a closed room
  // Where the camera starts when the user names no path and the file has no camera.
  std::optional<CameraPose> suggestedCamera;
};

// A mesh placed in the world at one moment.
struct Instance {
  int mesh = -1;
  int node = -1;
  glm::mat4 objectToWorld{1.0f};
};

struct Bounds {
  glm::vec3 min{std::numeric_limits<float>::max()};
  glm::vec3 max{-std::numeric_limits<float>::max()};
  bool empty() const { return min.x > max.x; }
  void extend(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  glm::vec3 center() const { return (min + max) * 0.5f; }
  glm::vec3 extent() const { return max - min; }
};

// The local transform of every node at `time` seconds, every animation
// playing from t = 0 and looping over its own length.
std::vector<Transform> animatedLocalTransforms(const Scene& scene, float time);
// World matrices of every node at `time` (parents before children).
std::vector<glm::mat4> nodeWorldMatrices(const Scene& scene, float time);
// Every mesh of every node reachable from the roots, placed at `time`.
std::vector<Instance> instancesAt(const Scene& scene, float time);
// World-space bounds of everything at `time`.
Bounds worldBounds(const Scene& scene, float time);
// True when any animation channel exists (motion vectors then include object motion).
inline bool isAnimated(const Scene& scene) { return !scene.animations.empty(); }

// The sky model has one sun, and a scene's directional light must agree with
// it: the first directional light found (in node order) becomes scene.sun
// (direction from its node at `time`, illuminance = intensity, colour) and is
// detached from its node, so it is not drawn twice. Returns false, leaving
// the scene as it is, when there is none.
bool adoptDirectionalLightAsSun(Scene& scene, float time = 0.0f);

// The brightest light the renderer takes, in its radiance units: a sun's
// illuminance, a punctual light's intensity, a material's emission (each
// times its colour's largest channel) and the environment's intensity (for
// the sky, times the sun's) must not exceed it. Radiance is computed in
// 32-bit floats (largest 3.4e38), and on the way multiplied by BRDF peaks
// (below 1e7 at the smallest GGX roughness) and inverse-square falloff (up to
// 1e8, distances are clamped at 1e-4): 1e20 keeps all of it finite, and is
// 1e15 times the sun's real illuminance in lux. Whatever is stored in a
// 16-bit image saturates at 65504 anyway (docs/conventions.md, "Non-finite
// values"), so nothing visible is lost by the limit.
// (The float 1e20, so that a value given as 1e20 is within it.)
inline constexpr double kMaxLightStrength = 1e20f;

// "" when a light of this strength (everything multiplied together) is
// within kMaxLightStrength, else why not, to follow "... is": "above 1e+20,
// the brightest light Bounce renders (...)".
std::string lightStrengthProblem(double strength);

// Checks the invariants the renderer relies on (indices in range, attribute
// arrays the right length, finite positions, material and texture indices
// valid, no cycles in the node graph, lights and emission within
// kMaxLightStrength) and throws SceneError naming the scene and the first
// problem.
void validate(const Scene& scene);

}  // namespace bounce::scene
