// glTF 2.0 export. The scene is turned into a tinygltf model, tinygltf
// writes its JSON, and the files themselves are written here: tinygltf's
// own file writing neither says why it failed nor writes atomically, and
// its stream writer would embed the buffer as base64 (so the model's buffer
// is handed to it empty and its entry filled in afterwards).
#include "scene/gltf_export.h"

#include <stb/stb_image_write.h>
#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>

#include "io/image_io.h"
#include "scene/uri.h"

namespace bounce::scene {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

[[noreturn]] void fail(const fs::path& file, const std::string& reason) {
  throw SceneError(file.string() + ": " + reason);
}

// The files the scene was loaded from: its glTF file and the buffer and
// image files that file names. Only what can still be read is listed; a
// source that is gone cannot be overwritten by mistake either.
std::vector<fs::path> sourceFiles(const Scene& scene) {
  if (scene.source.empty()) return {};
  std::vector<fs::path> files{scene.source};
  std::ifstream stream(scene.source, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
  std::string_view text = bytes;
  if (text.starts_with("glTF")) {
    // GLB: a 12-byte header, then the JSON chunk's length, type and text.
    if (text.size() < 20) return files;
    std::uint32_t length = 0;
    std::memcpy(&length, text.data() + 12, sizeof length);
    text = text.substr(20, length);
  }
  const json document = json::parse(text.begin(), text.end(), nullptr, false);
  if (!document.is_object()) return files;
  for (const char* kind : {"buffers", "images"}) {
    const auto items = document.find(kind);
    if (items == document.end() || !items->is_array()) continue;
    for (const json& item : *items) {
      const auto uri = item.find("uri");
      if (uri == item.end() || !uri->is_string()) continue;
      const std::string value = uri->get<std::string>();
      if (!value.starts_with("data:")) files.push_back(scene.source.parent_path() / percentDecoded(value));
    }
  }
  return files;
}

void refuseSourceFiles(const std::vector<fs::path>& outputs, const std::vector<fs::path>& sources) {
  for (const fs::path& output : outputs)
    for (const fs::path& source : sources) {
      std::error_code error;
      if (fs::equivalent(output, source, error))
        fail(output, "is one of the files the scene was loaded from (" + source.string() +
                         "); an export never overwrites its source, so choose another name or folder");
    }
}

std::vector<std::uint8_t> encodePng(const Texture& texture) {
  std::vector<std::uint8_t> png;
  const auto append = [](void* context, void* data, int size) {
    auto& out = *static_cast<std::vector<std::uint8_t>*>(context);
    const auto* begin = static_cast<const std::uint8_t*>(data);
    out.insert(out.end(), begin, begin + size);
  };
  if (!stbi_write_png_to_func(append, &png, texture.width, texture.height, 4, texture.rgba8.data(),
                              texture.width * 4) ||
      png.empty())
    throw SceneError("texture '" + texture.name + "': cannot encode it as PNG");
  return png;
}

// The rotation that turns -Z towards `forward` and +Y as near `up` as it can
// (a glTF camera looks, and a light shines, down its node's -Z).
glm::quat lookRotation(const glm::vec3& forward, const glm::vec3& up) {
  const glm::vec3 f = glm::normalize(forward);
  glm::vec3 side = glm::cross(f, up);
  if (glm::length(side) < 1e-6f) side = glm::cross(f, std::abs(f.z) < 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0));
  const glm::vec3 right = glm::normalize(side);
  return glm::normalize(glm::quat_cast(glm::mat3(right, glm::cross(right, f), -f)));
}

std::vector<double> doubles(const float* values, int count) { return std::vector<double>(values, values + count); }

// Meshes named "name#N" by the importer are the primitives of glTF mesh "name".
std::string groupName(const std::string& meshName, std::size_t primitives) {
  const std::size_t hash = meshName.rfind('#');
  if (primitives < 2 || hash == std::string::npos || hash + 1 == meshName.size() ||
      !std::all_of(meshName.begin() + long(hash) + 1, meshName.end(), [](char c) { return std::isdigit(c); }))
    return meshName;
  return meshName.substr(0, hash);
}

class Exporter {
 public:
  Exporter(const Scene& scene, const fs::path& file) : scene_(scene), file_(file) {
    binary_ = file.extension() == ".glb";
    stem_ = file.stem().string();
  }

  // The files the export writes, the glTF file last.
  std::vector<fs::path> outputs() const {
    std::vector<fs::path> files;
    if (!binary_) {
      for (std::size_t t = 0; t < scene_.textures.size(); ++t) files.push_back(sibling(textureFileName(t)));
      files.push_back(sibling(binFileName()));
    }
    files.push_back(file_);
    return files;
  }

  void write() {
    convertMaterials();
    convertTextures();
    convertMeshes();
    convertNodes();
    addSunAndSuggestedView();
    convertAnimations();
    tinygltf::Scene gltfScene;
    gltfScene.nodes = roots_;
    model_.scenes.push_back(gltfScene);
    model_.defaultScene = 0;
    model_.asset.version = "2.0";
    model_.asset.generator = "Bounce";
    if (!bytes_.empty()) model_.buffers.emplace_back();  // its bytes are written apart (see the top)

    for (std::size_t t = 0; t < pngs_.size() && !binary_; ++t) writeFile(sibling(textureFileName(t)), pngs_[t]);
    if (!binary_ && !bytes_.empty()) writeFile(sibling(binFileName()), bytes_);
    const std::string text = documentText();
    if (!binary_) {
      writeFile(file_, std::vector<std::uint8_t>(text.begin(), text.end()));
      return;
    }
    writeFile(file_, glb(text));
  }

 private:
  std::string textureFileName(std::size_t index) const { return stem_ + ".texture" + std::to_string(index) + ".png"; }
  std::string binFileName() const { return stem_ + ".bin"; }
  fs::path sibling(const std::string& name) const { return file_.parent_path() / name; }

  static void writeFile(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
    try {
      io::writeFileAtomically(path, bytes.data(), bytes.size());
    } catch (const io::ImageIoError& error) {
      throw SceneError(error.what());  // already "<path>: <reason>"
    }
  }

  // ------------------------------------------------------------ buffer data

  int addBufferView(const void* data, std::size_t size, int target) {
    while (bytes_.size() % 4 != 0) bytes_.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bytes_.size();
    view.byteLength = size;
    view.target = target;
    const auto* begin = static_cast<const std::uint8_t*>(data);
    bytes_.insert(bytes_.end(), begin, begin + size);
    model_.bufferViews.push_back(view);
    return int(model_.bufferViews.size()) - 1;
  }

  // `count` elements of `components` floats each; with their bounds when
  // glTF requires them (positions, animation times).
  int addFloats(const float* values, std::size_t count, int components, int type, int target, bool bounds) {
    tinygltf::Accessor accessor;
    accessor.bufferView = addBufferView(values, count * std::size_t(components) * sizeof(float), target);
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    accessor.count = count;
    accessor.type = type;
    if (bounds) {
      accessor.minValues.assign(std::size_t(components), std::numeric_limits<double>::max());
      accessor.maxValues.assign(std::size_t(components), std::numeric_limits<double>::lowest());
      for (std::size_t i = 0; i < count; ++i)
        for (std::size_t c = 0; c < std::size_t(components); ++c) {
          const double value = values[i * std::size_t(components) + c];
          accessor.minValues[c] = std::min(accessor.minValues[c], value);
          accessor.maxValues[c] = std::max(accessor.maxValues[c], value);
        }
    }
    model_.accessors.push_back(accessor);
    return int(model_.accessors.size()) - 1;
  }

  int addIndices(const std::vector<std::uint32_t>& indices) {
    tinygltf::Accessor accessor;
    accessor.bufferView =
        addBufferView(indices.data(), indices.size() * sizeof(std::uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    accessor.count = indices.size();
    accessor.type = TINYGLTF_TYPE_SCALAR;
    model_.accessors.push_back(accessor);
    return int(model_.accessors.size()) - 1;
  }

  // ------------------------------------------------------------ materials and textures

  void convertMaterials() {
    for (const Material& source : scene_.materials) {
      tinygltf::Material material;
      material.name = source.name;
      material.pbrMetallicRoughness.baseColorFactor = doubles(&source.baseColorFactor.x, 4);
      material.pbrMetallicRoughness.metallicFactor = source.metallicFactor;
      material.pbrMetallicRoughness.roughnessFactor = source.roughnessFactor;
      material.pbrMetallicRoughness.baseColorTexture.index = source.baseColorTexture;
      material.pbrMetallicRoughness.metallicRoughnessTexture.index = source.metallicRoughnessTexture;
      material.normalTexture.index = source.normalTexture;
      material.normalTexture.scale = source.normalScale;
      material.occlusionTexture.index = source.occlusionTexture;
      material.occlusionTexture.strength = source.occlusionStrength;
      material.emissiveTexture.index = source.emissiveTexture;
      // glTF's emissiveFactor is at most 1; the strength extension carries
      // the rest, so the emitted radiance (their product) stays the same.
      const float largest = std::max({source.emissiveFactor.x, source.emissiveFactor.y, source.emissiveFactor.z});
      const float scale = largest > 1.0f ? largest : 1.0f;
      const glm::vec3 factor = source.emissiveFactor / scale;
      const double strength = double(source.emissiveStrength) * double(scale);
      material.emissiveFactor = doubles(&factor.x, 3);
      if (strength != 1.0 && largest > 0.0f) {
        tinygltf::Value::Object extension;
        extension["emissiveStrength"] = tinygltf::Value(strength);
        material.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(extension);
        useExtension("KHR_materials_emissive_strength");
      }
      material.alphaMode = source.alphaMode == AlphaMode::Opaque ? "OPAQUE"
                           : source.alphaMode == AlphaMode::Mask ? "MASK"
                                                                 : "BLEND";
      material.alphaCutoff = source.alphaCutoff;
      material.doubleSided = source.doubleSided;
      model_.materials.push_back(material);
    }
  }

  void convertTextures() {
    for (std::size_t t = 0; t < scene_.textures.size(); ++t) {
      std::vector<std::uint8_t> png = encodePng(scene_.textures[t]);
      tinygltf::Image image;
      image.name = scene_.textures[t].name;
      if (binary_) {
        image.bufferView = addBufferView(png.data(), png.size(), 0);
        image.mimeType = "image/png";
      } else {
        image.uri = percentEncoded(textureFileName(t));
      }
      model_.images.push_back(image);
      tinygltf::Texture texture;
      texture.source = int(t);
      model_.textures.push_back(texture);
      pngs_.push_back(std::move(png));
    }
  }

  // ------------------------------------------------------------ meshes

  // glTF mesh i has the scene meshes groups[i] as its primitives.
  void convertMeshes() {
    const std::size_t meshCount = scene_.meshes.size();
    const auto drawn = [&](const std::vector<int>& meshes) {
      std::vector<int> list;
      for (int m : meshes)
        if (!scene_.meshes[std::size_t(m)].indices.empty()) list.push_back(m);
      return list;
    };
    // A node's list is a group of its own when it is consecutive and shares
    // no mesh with another group; the importer then makes the same meshes
    // in the same order from it.
    std::vector<std::vector<int>> groups;
    std::vector<bool> grouped(meshCount, false);
    for (const Node& node : scene_.nodes) {
      const std::vector<int> list = drawn(node.meshes);
      if (list.empty() || std::find(groups.begin(), groups.end(), list) != groups.end()) continue;
      bool consecutive = true;
      for (std::size_t k = 0; k < list.size(); ++k)
        consecutive = consecutive && !grouped[std::size_t(list[k])] && (k == 0 || list[k] == list[k - 1] + 1);
      if (!consecutive) continue;
      for (int m : list) grouped[std::size_t(m)] = true;
      groups.push_back(list);
    }
    for (std::size_t m = 0; m < meshCount; ++m)
      if (!grouped[m] && !scene_.meshes[m].indices.empty()) groups.push_back({int(m)});
    std::sort(groups.begin(), groups.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
    std::map<std::vector<int>, int> groupOfList;
    for (std::size_t g = 0; g < groups.size(); ++g) groupOfList[groups[g]] = int(g);
    // Any other list becomes a glTF mesh of its own, after those.
    nodeMesh_.assign(scene_.nodes.size(), -1);
    for (std::size_t n = 0; n < scene_.nodes.size(); ++n) {
      const std::vector<int> list = drawn(scene_.nodes[n].meshes);
      if (list.empty()) continue;
      const auto [found, added] = groupOfList.try_emplace(list, int(groups.size()));
      if (added) groups.push_back(list);
      nodeMesh_[n] = found->second;
    }

    primitives_.assign(meshCount, {});
    for (const std::vector<int>& group : groups) {
      tinygltf::Mesh mesh;
      mesh.name = groupName(scene_.meshes[std::size_t(group.front())].name, group.size());
      for (int m : group) mesh.primitives.push_back(primitive(std::size_t(m)));
      model_.meshes.push_back(mesh);
    }
  }

  // Each scene mesh's accessors are written once, however many glTF meshes use them.
  tinygltf::Primitive primitive(std::size_t index) {
    if (!primitives_[index]) {
      const Mesh& mesh = scene_.meshes[index];
      const std::size_t count = mesh.positions.size();
      tinygltf::Primitive made;
      made.attributes["POSITION"] =
          addFloats(&mesh.positions.data()->x, count, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, true);
      made.attributes["NORMAL"] =
          addFloats(&mesh.normals.data()->x, count, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, false);
      made.attributes["TANGENT"] =
          addFloats(&mesh.tangents.data()->x, count, 4, TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER, false);
      made.attributes["TEXCOORD_0"] =
          addFloats(&mesh.texcoords.data()->x, count, 2, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER, false);
      made.indices = addIndices(mesh.indices);
      made.material = mesh.material;
      made.mode = TINYGLTF_MODE_TRIANGLES;
      primitives_[index] = made;
    }
    return *primitives_[index];
  }

  // ------------------------------------------------------------ nodes, lights, cameras

  void convertNodes() {
    std::vector<int> lightIndex(scene_.lights.size(), -1);
    for (const Node& node : scene_.nodes)
      if (node.light >= 0) lightIndex[std::size_t(node.light)] = 0;
    // Only lights that a node holds: a light the sun was made from is no
    // longer on its node, and the sun is written as itself.
    for (std::size_t l = 0; l < scene_.lights.size(); ++l)
      if (lightIndex[l] == 0) lightIndex[l] = addLight(scene_.lights[l]);
    for (const CameraDesc& camera : scene_.cameras) addCamera(camera);

    for (std::size_t n = 0; n < scene_.nodes.size(); ++n) {
      const Node& source = scene_.nodes[n];
      tinygltf::Node node;
      node.name = source.name;
      node.children = source.children;
      node.mesh = nodeMesh_[n];
      node.camera = source.camera;
      if (source.light >= 0) holdLight(node, lightIndex[std::size_t(source.light)]);
      setTransform(node, source.local);
      model_.nodes.push_back(node);
    }
    roots_ = scene_.roots;
  }

  static void setTransform(tinygltf::Node& node, const Transform& local) {
    if (local.translation != glm::vec3(0.0f)) node.translation = doubles(&local.translation.x, 3);
    if (local.rotation != glm::quat(1.0f, 0.0f, 0.0f, 0.0f))
      node.rotation = {local.rotation.x, local.rotation.y, local.rotation.z, local.rotation.w};
    if (local.scale != glm::vec3(1.0f)) node.scale = doubles(&local.scale.x, 3);
  }

  int addLight(const Light& source) {
    tinygltf::Light light;
    light.name = source.name;
    light.type = source.type == LightType::Directional ? "directional"
                 : source.type == LightType::Point     ? "point"
                                                       : "spot";
    // glTF's colour is at most 1; the intensity carries the rest, so the
    // emitted light (their product) stays the same.
    const float largest = std::max({source.color.x, source.color.y, source.color.z});
    const float scale = largest > 1.0f ? largest : 1.0f;
    const glm::vec3 color = source.color / scale;
    light.color = doubles(&color.x, 3);
    light.intensity = double(source.intensity) * double(scale);
    // A directional light has no range in glTF (and 0 means none here).
    if (source.type != LightType::Directional) light.range = source.range;
    // glTF: 0 <= inner < outer <= pi/2, compared as the doubles written. The
    // float nearest pi/2 is above it, so the bound is written exactly.
    const double outer = std::min(double(source.outerConeAngle), glm::half_pi<double>());
    const double inner = std::max(double(source.innerConeAngle), 0.0);
    light.spot.outerConeAngle = outer;
    light.spot.innerConeAngle = inner < outer ? inner : std::nextafter(outer, 0.0);
    model_.lights.push_back(light);
    return int(model_.lights.size()) - 1;
  }

  static void holdLight(tinygltf::Node& node, int light) {
    tinygltf::Value::Object extension;
    extension["light"] = tinygltf::Value(light);
    node.extensions["KHR_lights_punctual"] = tinygltf::Value(extension);
  }

  int addCamera(const CameraDesc& source) {
    tinygltf::Camera camera;
    camera.name = source.name;
    camera.type = "perspective";
    camera.perspective.yfov = source.yfov;
    camera.perspective.znear = source.znear;
    model_.cameras.push_back(camera);
    return int(model_.cameras.size()) - 1;
  }

  void addSunAndSuggestedView() {
    Light sunLight;
    sunLight.name = "sun";
    sunLight.type = LightType::Directional;
    sunLight.color = scene_.sun.color;
    sunLight.intensity = scene_.hasSun ? scene_.sun.illuminance : 0.0f;
    tinygltf::Node sun;
    sun.name = "sun";
    holdLight(sun, addLight(sunLight));
    const glm::quat toward = lookRotation(-scene_.sun.direction(), glm::vec3(0.0f, 1.0f, 0.0f));
    sun.rotation = {toward.x, toward.y, toward.z, toward.w};
    roots_.push_back(int(model_.nodes.size()));
    model_.nodes.push_back(sun);

    if (!scene_.cameras.empty() || !scene_.suggestedCamera) return;
    const CameraPose& pose = *scene_.suggestedCamera;
    tinygltf::Node view;
    view.name = "suggested view";
    view.camera = addCamera({.name = "suggested view", .yfov = glm::radians(pose.fovYDegrees)});
    Transform local;
    local.translation = pose.position;
    local.rotation = lookRotation(pose.target - pose.position, pose.up);
    setTransform(view, local);
    roots_.push_back(int(model_.nodes.size()));
    model_.nodes.push_back(view);
  }

  void useExtension(const std::string& name) {
    if (std::find(model_.extensionsUsed.begin(), model_.extensionsUsed.end(), name) == model_.extensionsUsed.end())
      model_.extensionsUsed.push_back(name);
  }

  // ------------------------------------------------------------ animations

  void convertAnimations() {
    for (const Animation& source : scene_.animations) {
      tinygltf::Animation animation;
      animation.name = source.name;
      for (const AnimationChannel& channel : source.channels) {
        const bool rotation = channel.property == AnimatedProperty::Rotation;
        // Scene values are vec4s: xyz for translation and scale, quaternion xyzw for rotation.
        std::vector<float> values;
        for (const glm::vec4& v : channel.values) values.insert(values.end(), &v.x, &v.x + (rotation ? 4 : 3));
        tinygltf::AnimationSampler sampler;
        sampler.input = addFloats(channel.times.data(), channel.times.size(), 1, TINYGLTF_TYPE_SCALAR, 0, true);
        sampler.output = addFloats(values.data(), channel.values.size(), rotation ? 4 : 3,
                                   rotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, 0, false);
        sampler.interpolation = channel.interpolation == Interpolation::Linear ? "LINEAR"
                                : channel.interpolation == Interpolation::Step ? "STEP"
                                                                               : "CUBICSPLINE";
        tinygltf::AnimationChannel target;
        target.sampler = int(animation.samplers.size());
        target.target_node = channel.node;
        target.target_path = channel.property == AnimatedProperty::Translation ? "translation"
                             : rotation                                        ? "rotation"
                                                                               : "scale";
        animation.samplers.push_back(sampler);
        animation.channels.push_back(target);
      }
      model_.animations.push_back(animation);
    }
  }

  // ------------------------------------------------------------ the files

  std::string documentText() {
    tinygltf::TinyGLTF writer;
    writer.SetImageWriter(nullptr, nullptr);  // images carry their URI or buffer view as they are
    std::ostringstream stream;
    if (!writer.WriteGltfSceneToStream(&model_, stream, false, false))
      fail(file_, "tinygltf could not serialise the scene");
    json document = json::parse(stream.str());
    if (!bytes_.empty()) {
      json& buffer = document["buffers"][0];
      buffer = {{"byteLength", bytes_.size()}};
      if (!binary_) buffer["uri"] = percentEncoded(binFileName());
    }
    // tinygltf writes "zfar": 0 for an infinite projection, which glTF
    // expresses by leaving zfar out.
    if (const auto cameras = document.find("cameras"); cameras != document.end())
      for (json& camera : *cameras) camera["perspective"].erase("zfar");
    return binary_ ? document.dump() : document.dump(2) + "\n";
  }

  // GLB: the header, the JSON chunk (padded with spaces) and the BIN chunk
  // (padded with zeros), each chunk 4-byte aligned.
  std::vector<std::uint8_t> glb(std::string text) const {
    while (text.size() % 4 != 0) text += ' ';
    std::vector<std::uint8_t> bin = bytes_;
    while (bin.size() % 4 != 0) bin.push_back(0);
    const std::size_t total = 12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size());
    if (total > 0xffffffffu) fail(file_, "a GLB file holds at most 4 GiB; write a .gltf instead");
    std::vector<std::uint8_t> out;
    const auto word = [&](std::uint32_t value) {
      for (int i = 0; i < 4; ++i) out.push_back(std::uint8_t(value >> (8 * i)));
    };
    word(0x46546C67u);  // "glTF"
    word(2);
    word(std::uint32_t(total));
    word(std::uint32_t(text.size()));
    word(0x4E4F534Au);  // "JSON"
    out.insert(out.end(), text.begin(), text.end());
    if (!bin.empty()) {
      word(std::uint32_t(bin.size()));
      word(0x004E4942u);  // "BIN"
      out.insert(out.end(), bin.begin(), bin.end());
    }
    return out;
  }

  const Scene& scene_;
  const fs::path file_;
  bool binary_ = false;
  std::string stem_;
  tinygltf::Model model_;
  std::vector<std::uint8_t> bytes_;              // the one buffer
  std::vector<std::vector<std::uint8_t>> pngs_;  // texture i's PNG file
  std::vector<std::optional<tinygltf::Primitive>> primitives_;
  std::vector<int> nodeMesh_;  // the glTF mesh of scene node i, -1 for none
  std::vector<int> roots_;
};

}  // namespace

void writeGltf(const Scene& scene, const fs::path& file, ExistingFiles existing) {
  const std::string extension = file.extension().string();
  if (extension != ".gltf" && extension != ".glb")
    fail(file, "a glTF export is named .gltf or .glb (got '" + extension + "')");
  Exporter exporter(scene, file);
  const std::vector<fs::path> outputs = exporter.outputs();
  refuseSourceFiles(outputs, sourceFiles(scene));
  // Every file is looked at before the first is written, so a refusal
  // leaves the folder as it was; symlink_status, so that a link (even one
  // leading nowhere) counts as a file that exists.
  for (const fs::path& output : outputs) {
    std::error_code error;
    const fs::file_status status = fs::symlink_status(output, error);
    if (fs::is_symlink(status))
      fail(output, "is a symbolic link; not replaced (an export writes regular files only): choose another name");
    if (existing == ExistingFiles::Refuse && fs::exists(status)) {
      std::string names;
      for (std::size_t i = 0; i < outputs.size(); ++i) {
        if (outputs.size() > 4 && i > 0 && i + 2 < outputs.size()) {
          if (i == 1) names += ", ...";  // the textures between the first and the .bin
          continue;
        }
        names += (names.empty() ? "" : ", ") + outputs[i].filename().string();
      }
      fail(output, "exists; not overwritten (this export writes " + names + "): choose another name");
    }
  }
  exporter.write();
}

}  // namespace bounce::scene
