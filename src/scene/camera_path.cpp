// The camera paths of camera_path.h: presets derived from the scene, glTF
// cameras, and JSON keyframes.
#include "scene/camera_path.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include <glm/gtc/constants.hpp>
#include <nlohmann/json.hpp>

#include "util/json_error.h"
#include "util/json_parse.h"

namespace bounce::scene {
namespace {

constexpr glm::vec3 kWorldUp(0.0f, 1.0f, 0.0f);
constexpr float kOrbitSeconds = 8.0f;
constexpr float kDollySeconds = 8.0f;
constexpr float kFlySeconds = 16.0f;

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::string vectorText(const glm::vec3& v) { return "(" + number(v.x) + ", " + number(v.y) + ", " + number(v.z) + ")"; }

// A pose that shows the whole of the scene's `bounds` from the front (+Z) and
// a little above, for scenes that suggest no camera. Worked out in double,
// since the bounds' size may overflow a float when squared; refused when the
// pose cannot be held in floats: bounds near float's range give infinity,
// and bounds far from the origin for their size a position that rounds onto
// the target.
CameraPose framingPose(const Scene& scene, const Bounds& bounds) {
  CameraPose pose;
  if (bounds.empty()) return pose;
  const glm::dvec3 min(bounds.min), max(bounds.max);
  const double radius = std::max(0.5 * glm::length(max - min), 0.1);
  const double distance = 1.1 * radius / std::sin(glm::radians(double(pose.fovYDegrees)) / 2);
  const glm::dvec3 target = 0.5 * (min + max);
  pose.target = glm::vec3(target);
  pose.position = glm::vec3(target + glm::normalize(glm::dvec3(0.0, 0.35, 1.0)) * distance);
  const double kept = glm::length(glm::dvec3(pose.position) - glm::dvec3(pose.target));
  if (!(std::abs(kept - distance) <= 0.01 * distance))
    throw SceneError("scene '" + scene.name + "': its bounds, " + vectorText(bounds.min) + " to " +
                     vectorText(bounds.max) +
                     ", are too large (or too far from the origin for their size) to frame with a camera in 32-bit "
                     "floats; give a camera (--camera FILE.json)");
  return pose;
}

CameraPose startingPose(const Scene& scene, const Bounds& bounds) {
  return scene.suggestedCamera ? *scene.suggestedCamera : framingPose(scene, bounds);
}

// Seconds into the current repetition of a path `period` seconds long.
float wrap(float time, float period) {
  const float local = std::fmod(time, period);
  return local < 0.0f ? local + period : local;
}

class StaticPath final : public CameraPath {
 public:
  explicit StaticPath(const CameraPose& pose) : pose_(pose) {}
  CameraPose pose(float) const override { return pose_; }
  float duration() const override { return 0.0f; }

 private:
  CameraPose pose_;
};

class OrbitPath final : public CameraPath {
 public:
  OrbitPath(const CameraPose& start, const Bounds& bounds) : fovY_(start.fovYDegrees) {
    const glm::vec3 centre = bounds.empty() ? start.target : bounds.center();
    const glm::vec3 halfExtent = bounds.empty() ? glm::vec3(1.0f) : 0.5f * bounds.extent();
    const glm::vec2 offset(start.position.x - centre.x, start.position.z - centre.z);
    const bool inside = !bounds.empty() && start.position.x > bounds.min.x && start.position.x < bounds.max.x &&
                        start.position.z > bounds.min.z && start.position.z < bounds.max.z;
    // Inside a room, a circle at the camera's distance would go through the walls.
    const float roomRadius = 0.75f * std::min(halfExtent.x, halfExtent.z);
    radius_ = glm::length(offset);
    if (inside) radius_ = std::min(radius_, roomRadius);
    if (radius_ < 1e-3f) radius_ = inside ? roomRadius : 1.5f * std::max(halfExtent.x, halfExtent.z);
    radius_ = std::max(radius_, 1e-2f);
    startAngle_ = glm::length(offset) > 1e-6f ? std::atan2(offset.x, offset.y) : 0.0f;
    centre_ = {centre.x, start.position.y, centre.z};
    target_ = {centre.x, start.target.y, centre.z};
  }

  CameraPose pose(float time) const override {
    const float angle = startAngle_ + glm::two_pi<float>() * wrap(time, kOrbitSeconds) / kOrbitSeconds;
    return {centre_ + radius_ * glm::vec3(std::sin(angle), 0.0f, std::cos(angle)), target_, kWorldUp, fovY_};
  }
  float duration() const override { return kOrbitSeconds; }

 private:
  glm::vec3 centre_{0.0f};  // of the camera's circle, at its height
  glm::vec3 target_{0.0f};
  float radius_ = 1.0f;
  float startAngle_ = 0.0f;  // from +Z towards +X, as Sun::azimuthDegrees
  float fovY_ = 45.0f;
};

class DollyPath final : public CameraPath {
 public:
  explicit DollyPath(const CameraPose& start) : start_(start) {}

  CameraPose pose(float time) const override {
    const float ease = 0.5f - 0.5f * std::cos(glm::two_pi<float>() * wrap(time, kDollySeconds) / kDollySeconds);
    CameraPose pose = start_;
    pose.position = start_.position + 0.5f * ease * (start_.target - start_.position);
    return pose;
  }
  float duration() const override { return kDollySeconds; }

 private:
  CameraPose start_;
};

// Uniform Catmull-Rom between p1 and p2 (f in [0, 1]).
glm::vec3 catmullRom(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3, float f) {
  const float f2 = f * f;
  const float f3 = f2 * f;
  return 0.5f * (2.0f * p1 + (p2 - p0) * f + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * f2 +
                 (3.0f * p1 - p0 - 3.0f * p2 + p3) * f3);
}

class FlyPath final : public CameraPath {
 public:
  FlyPath(const CameraPose& start, const Bounds& bounds) : fovY_(start.fovYDegrees) {
    const Bounds box = bounds.empty() ? Bounds{start.target - 1.0f, start.target + 1.0f} : bounds;
    centre_ = box.center();
    const glm::vec3 extent = box.extent();
    const glm::vec2 radii = glm::max(0.3f * glm::vec2(extent.x, extent.z), glm::vec2(0.5f));
    // Alternating radius and height make the curve swoop rather than circle.
    for (std::size_t k = 0; k < waypoints_.size(); ++k) {
      const float angle = glm::two_pi<float>() * float(k) / float(waypoints_.size());
      const float reach = k % 2 == 0 ? 1.0f : 0.8f;
      const float height = box.min.y + extent.y * (k % 2 == 0 ? 0.65f : 0.78f);
      waypoints_[k] = {centre_.x + reach * radii.x * std::sin(angle), height,
                       centre_.z + reach * radii.y * std::cos(angle)};
    }
  }

  CameraPose pose(float time) const override {
    const glm::vec3 position = curve(time);
    glm::vec3 target = curve(time + kLookAheadSeconds);
    target.y -= 0.5f * (target.y - centre_.y);  // look down towards the middle of the scene
    return {position, target, kWorldUp, fovY_};
  }
  float duration() const override { return kFlySeconds; }

 private:
  static constexpr float kLookAheadSeconds = 1.0f;

  glm::vec3 curve(float time) const {
    const std::size_t count = waypoints_.size();
    const float u = wrap(time, kFlySeconds) / kFlySeconds * float(count);
    const std::size_t i = std::min(std::size_t(u), count - 1);
    const auto point = [&](std::size_t k) { return waypoints_[(k + count) % count]; };
    return catmullRom(point(i + count - 1), point(i), point(i + 1), point(i + 2), u - float(i));
  }

  std::array<glm::vec3, 6> waypoints_{};
  glm::vec3 centre_{0.0f};
  float fovY_ = 45.0f;
};

float animationLength(const Animation& animation) {
  float length = 0.0f;
  for (const AnimationChannel& channel : animation.channels)
    if (!channel.times.empty()) length = std::max(length, channel.times.back());
  return length;
}

// A glTF camera node: its world transform at each time. Keeps its own copy of
// the node graph and animations (no meshes), so it does not depend on the
// scene outliving it.
class GltfCameraPath final : public CameraPath {
 public:
  GltfCameraPath(const Scene& scene, int node)
      : node_(node), fovY_(glm::degrees(scene.cameras[std::size_t(scene.nodes[std::size_t(node)].camera)].yfov)) {
    motion_.name = scene.name;
    motion_.nodes = scene.nodes;
    std::vector<bool> chain(scene.nodes.size(), false);
    for (int n = node; n >= 0; n = scene.nodes[std::size_t(n)].parent) chain[std::size_t(n)] = true;
    // Only animations that move the camera matter: they set its duration and cuts.
    for (const Animation& animation : scene.animations)
      for (const AnimationChannel& channel : animation.channels)
        if (chain[std::size_t(channel.node)]) {
          motion_.animations.push_back(animation);
          break;
        }
  }

  CameraPose pose(float time) const override {
    const glm::mat4 world = nodeWorldMatrices(motion_, time)[std::size_t(node_)];
    const glm::vec3 position(world[3]);
    const glm::vec3 forward = glm::normalize(-glm::vec3(world[2]));
    return {position, position + forward, glm::normalize(glm::vec3(world[1])), fovY_};
  }

  // Each animation jumps back to its start when it loops; a periodic one
  // does not really jump, but one extra history reset per loop is harmless.
  int segment(float time) const override {
    int loops = 0;
    for (const Animation& animation : motion_.animations) {
      const float length = animationLength(animation);
      if (length > 0.0f) loops += int(std::floor(std::max(time, 0.0f) / length));
    }
    return loops;
  }

  float duration() const override {
    float longest = 0.0f;
    for (const Animation& animation : motion_.animations) longest = std::max(longest, animationLength(animation));
    return longest;
  }

 private:
  Scene motion_;
  int node_ = -1;
  float fovY_ = 45.0f;
};

// The nodes with a camera, depth-first from the roots in order: the order
// "gltf:N" counts in.
std::vector<int> cameraNodes(const Scene& scene) {
  std::vector<int> cameras;
  std::vector<int> stack(scene.roots.rbegin(), scene.roots.rend());
  while (!stack.empty()) {
    const int index = stack.back();
    stack.pop_back();
    const Node& node = scene.nodes[std::size_t(index)];
    if (node.camera >= 0) cameras.push_back(index);
    for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) stack.push_back(*child);
  }
  return cameras;
}

// "1 'CameraTableTop'", with its node's name when that differs: how the
// error for a camera that does not exist lists those that do.
std::string cameraLabel(const Scene& scene, std::size_t number, int node) {
  const std::string& nodeName = scene.nodes[std::size_t(node)].name;
  const std::string& cameraName = scene.cameras[std::size_t(scene.nodes[std::size_t(node)].camera)].name;
  std::string label = std::to_string(number);
  if (!cameraName.empty()) label += " '" + cameraName + "'";
  if (!nodeName.empty() && nodeName != cameraName) label += " (node '" + nodeName + "')";
  return label;
}

// The camera node a "gltf", "gltf:N" or "gltf:NAME" spec chooses.
int chosenCameraNode(const Scene& scene, std::string_view spec) {
  const std::vector<int> nodes = cameraNodes(scene);
  if (nodes.empty())
    throw SceneError("scene '" + scene.name + "' has no glTF camera (camera path '" + std::string(spec) + "')");
  if (spec == "gltf") return nodes.front();
  const std::string_view wanted = spec.substr(std::string_view("gltf:").size());
  const bool byNumber =
      !wanted.empty() && std::all_of(wanted.begin(), wanted.end(), [](char c) { return c >= '0' && c <= '9'; });
  if (byNumber) {
    std::size_t number = 0;
    const auto [end, error] = std::from_chars(wanted.data(), wanted.data() + wanted.size(), number);
    if (error == std::errc() && end == wanted.data() + wanted.size() && number < nodes.size()) return nodes[number];
  } else if (!wanted.empty()) {
    for (int node : nodes)
      if (scene.nodes[std::size_t(node)].name == wanted ||
          scene.cameras[std::size_t(scene.nodes[std::size_t(node)].camera)].name == wanted)
        return node;
  }
  std::string cameras;
  for (std::size_t k = 0; k < nodes.size(); ++k) cameras += (k ? ", " : "") + cameraLabel(scene, k, nodes[k]);
  throw SceneError("scene '" + scene.name + "' has no glTF camera " +
                   (byNumber ? "number " + std::string(wanted) : "named '" + std::string(wanted) + "'") +
                   " (camera path '" + std::string(spec) + "'); its cameras, by number and name: " + cameras);
}

// ---- JSON keyframes

struct Keyframe {
  float time = 0.0f;
  glm::vec3 position{0.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up = kWorldUp;
  float fovY = 45.0f;
  bool cut = false;
};

// The most keyframes a camera file may hold: a keyframe a frame for over an
// hour at 24 fps. The parsed JSON of a keyframe takes several hundred bytes;
// counted while the file is read, the limit keeps `bounce render` under
// about 75 MB while it reads the largest file allowed, or refuses a larger
// one (a million keyframes took 806 MB).
constexpr std::size_t kMaxKeyframes = 100000;
// The format needs four levels (keyframes, one keyframe, a vector); deeper
// JSON is refused as it is read, before it is built.
constexpr int kMaxJsonDepth = 16;

// Watches the file as it is parsed (util::parseJson): refuses a key given
// twice in one object, which nlohmann would otherwise settle silently by
// keeping the last, and counts the keyframes, refusing one past the limit
// before its value is built.
class KeyframeFileCheck {
 public:
  explicit KeyframeFileCheck(const std::string& source) : source_(source) {}

  void objectStart() {
    if (open_.size() == 1 && open_.front().lastKey == "keyframes") {
      if (++keyframes_ > kMaxKeyframes)
        throw SceneError(source_ + ": more than " + std::to_string(kMaxKeyframes) +
                         " keyframes (the most a camera file may hold)");
    }
    open_.emplace_back();
  }
  void objectEnd() { open_.pop_back(); }
  void key(const std::string& name) {
    OpenObject& object = open_.back();
    object.lastKey = name;
    if (object.keys.insert(name).second) return;
    // Inside the keyframes' array, the message says which keyframe.
    const bool inKeyframe = open_.size() > 1 && open_.front().lastKey == "keyframes";
    throw SceneError(source_ + ": " + (inKeyframe ? "keyframe " + std::to_string(keyframes_ - 1) + ": " : "") + "'" +
                     name + "' is given more than once");
  }

 private:
  struct OpenObject {
    std::unordered_set<std::string> keys;
    std::string lastKey;
  };
  const std::string& source_;
  std::vector<OpenObject> open_;
  std::size_t keyframes_ = 0;
};

class KeyframeParser {
 public:
  explicit KeyframeParser(std::string source) : source_(std::move(source)) {}

  // `input` is JSON text or a stream of it (anything util::parseJson reads).
  template <class Input>
  std::vector<Keyframe> parse(Input&& input) {
    nlohmann::json document;
    try {
      document = util::parseJson(std::forward<Input>(input), kMaxJsonDepth, KeyframeFileCheck(source_));
    } catch (const util::JsonTooDeep& error) {
      fail(error.what());
    } catch (const nlohmann::json::exception& error) {
      fail("invalid JSON: " + util::withoutJsonExceptionTag(error.what()));
    }
    if (!document.is_object()) fail("expected an object {\"keyframes\": [...]}");
    for (const auto& [key, value] : document.items())
      if (key != "keyframes") fail("unknown field '" + key + "' (expected only \"keyframes\")");
    const auto list = document.find("keyframes");
    if (list == document.end() || !list->is_array()) fail("\"keyframes\" must be an array");
    if (list->empty()) fail("\"keyframes\" is empty");

    std::vector<Keyframe> keys;
    keys.reserve(list->size());
    for (std::size_t i = 0; i < list->size(); ++i) {
      index_ = int(i);
      keys.push_back(parseKeyframe((*list)[i], keys.empty() ? nullptr : &keys.back()));
    }
    return keys;
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw SceneError(source_ + ": " + (index_ >= 0 ? "keyframe " + std::to_string(index_) + ": " : "") + problem);
  }

  // A JSON number that is finite as a float (JSON has no NaN or infinity, but
  // 1e39 is a finite double and an infinite float).
  static bool isFiniteFloat(const nlohmann::json& value) {
    return value.is_number() && std::abs(value.get<double>()) <= double(std::numeric_limits<float>::max());
  }

  float finiteNumber(const nlohmann::json& value, const char* field) const {
    if (!isFiniteFloat(value)) fail(std::string("'") + field + "' must be a finite number (as a 32-bit float)");
    return float(value.get<double>());
  }

  glm::vec3 vector3(const nlohmann::json& value, const char* field) const {
    const bool ok = value.is_array() && value.size() == 3 && std::all_of(value.begin(), value.end(), isFiniteFloat);
    if (!ok) fail(std::string("'") + field + "' must be an array of 3 finite numbers");
    return {float(value[0].get<double>()), float(value[1].get<double>()), float(value[2].get<double>())};
  }

  Keyframe parseKeyframe(const nlohmann::json& entry, const Keyframe* previous) const {
    if (!entry.is_object()) fail("expected an object with time, position and target");
    static const std::array<const char*, 6> kFields = {"time", "position", "target", "fovY", "up", "cut"};
    for (const auto& [key, value] : entry.items())
      if (std::find(kFields.begin(), kFields.end(), key) == kFields.end())
        fail("unknown field '" + key + "' (known: time, position, target, fovY, up, cut)");
    for (const char* required : {"time", "position", "target"})
      if (!entry.contains(required)) fail(std::string("missing '") + required + "'");

    Keyframe key;
    key.time = finiteNumber(entry["time"], "time");
    key.position = vector3(entry["position"], "position");
    key.target = vector3(entry["target"], "target");
    key.fovY = previous ? previous->fovY : key.fovY;
    if (entry.contains("fovY")) key.fovY = finiteNumber(entry["fovY"], "fovY");
    if (entry.contains("up")) key.up = vector3(entry["up"], "up");
    if (entry.contains("cut")) {
      if (!entry["cut"].is_boolean()) fail("'cut' must be true or false");
      key.cut = entry["cut"].get<bool>();
    }

    if (previous && !(key.time > previous->time))
      fail("time " + number(key.time) + " is not after the previous keyframe's time " + number(previous->time) +
           " (times must strictly increase)");
    if (!(key.fovY > 0.0f && key.fovY < 180.0f)) fail("fovY " + number(key.fovY) + " is outside (0, 180) degrees");
    const glm::vec3 view = key.target - key.position;
    if (glm::length(view) < 1e-6f) fail("position and target are the same point");
    if (glm::length(key.up) < 1e-6f) fail("'up' is a zero vector");
    key.up = glm::normalize(key.up);
    if (glm::length(glm::cross(glm::normalize(view), key.up)) < 1e-4f)
      fail(std::string("the view direction is parallel to ") +
           (entry.contains("up") ? "'up'" : "the default up (0, 1, 0); give an 'up'"));
    return key;
  }

  std::string source_;
  int index_ = -1;  // the keyframe being read; -1 while reading the document
};

// Cubic Hermite on [t0, t1] with tangents m0, m1 (per second).
glm::vec3 hermite(const glm::vec3& p0, const glm::vec3& m0, const glm::vec3& p1, const glm::vec3& m1, float t0,
                  float t1, float time) {
  const float dt = t1 - t0;
  const float s = (time - t0) / dt;
  const float s2 = s * s;
  const float s3 = s2 * s;
  return (2.0f * s3 - 3.0f * s2 + 1.0f) * p0 + (s3 - 2.0f * s2 + s) * dt * m0 + (-2.0f * s3 + 3.0f * s2) * p1 +
         (s3 - s2) * dt * m1;
}

class KeyframePath final : public CameraPath {
 public:
  explicit KeyframePath(std::vector<Keyframe> keys) : keys_(std::move(keys)), cutsUpTo_(keys_.size(), 0) {
    for (std::size_t k = 1; k < keys_.size(); ++k) cutsUpTo_[k] = cutsUpTo_[k - 1] + (keys_[k].cut ? 1 : 0);
  }

  CameraPose pose(float time) const override {
    if (!(time > keys_.front().time)) return poseOf(keys_.front());  // NaN too: no key lies after it
    if (time >= keys_.back().time) return poseOf(keys_.back());
    const auto after =
        std::upper_bound(keys_.begin(), keys_.end(), time, [](float t, const Keyframe& key) { return t < key.time; });
    const std::size_t next = std::size_t(after - keys_.begin());
    const std::size_t prev = next - 1;
    const Keyframe& a = keys_[prev];
    const Keyframe& b = keys_[next];
    if (b.cut) return poseOf(a);  // the segment has ended; hold until the jump

    const float t0 = a.time, t1 = b.time;
    const float f = (time - t0) / (t1 - t0);
    CameraPose pose;
    pose.position = hermite(a.position, tangent(prev, &Keyframe::position), b.position,
                            tangent(next, &Keyframe::position), t0, t1, time);
    pose.target =
        hermite(a.target, tangent(prev, &Keyframe::target), b.target, tangent(next, &Keyframe::target), t0, t1, time);
    pose.fovYDegrees = a.fovY + (b.fovY - a.fovY) * f;
    const glm::vec3 up = glm::mix(a.up, b.up, f);
    pose.up = glm::length(up) > 1e-4f ? glm::normalize(up) : a.up;
    return pose;
  }

  // The cuts at or before `time`: found by bisection, since a render asks
  // once a frame and a path may hold kMaxKeyframes keys.
  int segment(float time) const override {
    if (!(time >= keys_.front().time)) return 0;
    const auto after =
        std::upper_bound(keys_.begin(), keys_.end(), time, [](float t, const Keyframe& key) { return t < key.time; });
    return cutsUpTo_[std::size_t(after - keys_.begin()) - 1];
  }

  float duration() const override { return std::max(0.0f, keys_.back().time); }

 private:
  static CameraPose poseOf(const Keyframe& key) { return {key.position, key.target, key.up, key.fovY}; }

  // Catmull-Rom velocity at key k from its neighbours within its segment; one-sided at the segment's ends.
  glm::vec3 tangent(std::size_t k, glm::vec3 Keyframe::*field) const {
    const bool hasPrevious = k > 0 && !keys_[k].cut;
    const bool hasNext = k + 1 < keys_.size() && !keys_[k + 1].cut;
    const std::size_t lo = hasPrevious ? k - 1 : k;
    const std::size_t hi = hasNext ? k + 1 : k;
    if (lo == hi) return glm::vec3(0.0f);
    return (keys_[hi].*field - keys_[lo].*field) / (keys_[hi].time - keys_[lo].time);
  }

  std::vector<Keyframe> keys_;
  std::vector<int> cutsUpTo_;  // cutsUpTo_[k]: keys 1..k that are cuts
};

}  // namespace

std::vector<std::string> cameraPathPresets() { return {"orbit", "dolly", "fly", "static", "gltf"}; }

std::unique_ptr<CameraPath> makeCameraPath(std::string_view spec, const Scene& scene) {
  const auto bounds = [&] { return worldBounds(scene, 0.0f); };
  if (spec == "static") return std::make_unique<StaticPath>(startingPose(scene, bounds()));
  if (spec == "orbit") {
    const Bounds b = bounds();
    return std::make_unique<OrbitPath>(startingPose(scene, b), b);
  }
  if (spec == "dolly") return std::make_unique<DollyPath>(startingPose(scene, bounds()));
  if (spec == "fly") {
    const Bounds b = bounds();
    return std::make_unique<FlyPath>(startingPose(scene, b), b);
  }
  if (spec == "gltf" || spec.starts_with("gltf:"))
    return std::make_unique<GltfCameraPath>(scene, chosenCameraNode(scene, spec));
  const std::filesystem::path file{std::string(spec)};
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) {
    std::string presets;
    for (const std::string& preset : cameraPathPresets()) presets += (presets.empty() ? "" : ", ") + preset;
    throw SceneError("camera path '" + std::string(spec) + "' is neither a preset (" + presets +
                     ", gltf:N, gltf:NAME) nor an existing JSON keyframe file");
  }
  return loadCameraKeyframes(file);
}

std::unique_ptr<CameraPath> defaultCameraPath(const Scene& scene) {
  const std::vector<int> cameras = cameraNodes(scene);
  if (!cameras.empty()) return std::make_unique<GltfCameraPath>(scene, cameras.front());
  return std::make_unique<StaticPath>(startingPose(scene, worldBounds(scene, 0.0f)));
}

std::unique_ptr<CameraPath> parseCameraKeyframes(const std::string& json, const std::string& source) {
  return std::make_unique<KeyframePath>(KeyframeParser(source).parse(json));
}

std::unique_ptr<CameraPath> loadCameraKeyframes(const std::filesystem::path& file) {
  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw SceneError(file.string() + ": cannot open the camera keyframe file");
  // Parsed from the stream, without a copy of the whole text in memory.
  return std::make_unique<KeyframePath>(KeyframeParser(file.string()).parse(stream));
}

std::vector<CameraFrame> sampleCameraPath(const CameraPath& path, int frameCount, float fps) {
  if (frameCount < 0) throw std::invalid_argument("sampleCameraPath: negative frame count");
  return sampleCameraFrames(path, 0, std::uint32_t(frameCount), fps);
}

std::vector<CameraFrame> sampleCameraFrames(const CameraPath& path, std::uint32_t first, std::uint32_t count,
                                            float fps) {
  if (!(fps > 0.0f) || !std::isfinite(fps)) throw std::invalid_argument("sampleCameraPath: fps must be positive");
  const auto timeOf = [fps](std::uint64_t frame) { return float(frame) / fps; };
  std::vector<CameraFrame> frames(count);
  int previousSegment = first > 0 ? path.segment(timeOf(first - 1)) : 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::uint64_t frame = std::uint64_t(first) + i;
    const float time = timeOf(frame);
    const int segment = path.segment(time);
    frames[i] = {path.pose(time), frame == 0 || segment != previousSegment};
    previousSegment = segment;
  }
  return frames;
}

}  // namespace bounce::scene
