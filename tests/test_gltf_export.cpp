// Tests of src/scene/gltf_export: scenes written as .gltf and .glb and read
// back by the project's importer come back the same (meshes, materials with
// an edit, textures texel for texel, transforms, animation, lights, the sun
// and the suggested view), and the export refuses to overwrite the scene's
// own files and names the file when it cannot write.
#include "scene/gltf_export.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/constants.hpp>

#include "scene/builtin_scenes.h"
#include "scene/gltf_import.h"

namespace bounce::scene {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A fresh folder for one test's files, removed afterwards.
class ExportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = fs::temp_directory_path() / ("bounce_gltf_export_" + std::to_string(::getpid()) + "_" + test->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(folder_, ignored);
  }

  static Scene load(const fs::path& file) {
    return loadGltf(file, {.warn = [&](const std::string& line) { ADD_FAILURE() << "import warning: " << line; }});
  }

  static json documentOf(const fs::path& file) {
    std::ifstream stream(file);
    return json::parse(stream);
  }

  fs::path folder_;
};

std::string messageOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const SceneError& error) {
    return error.what();
  }
  return "no exception";
}

void expectSameMeshes(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (std::size_t m = 0; m < a.meshes.size(); ++m) {
    SCOPED_TRACE("mesh " + std::to_string(m) + " '" + a.meshes[m].name + "'");
    EXPECT_EQ(a.meshes[m].name, b.meshes[m].name);
    EXPECT_EQ(a.meshes[m].indices, b.meshes[m].indices);
    EXPECT_EQ(a.meshes[m].positions, b.meshes[m].positions);
    EXPECT_EQ(a.meshes[m].texcoords, b.meshes[m].texcoords);
    EXPECT_EQ(a.meshes[m].material, b.meshes[m].material);
    ASSERT_EQ(a.meshes[m].normals.size(), b.meshes[m].normals.size());
    for (std::size_t v = 0; v < a.meshes[m].normals.size(); ++v) {
      EXPECT_LT(glm::length(a.meshes[m].normals[v] - b.meshes[m].normals[v]), 1e-6f);
      EXPECT_LT(glm::length(a.meshes[m].tangents[v] - b.meshes[m].tangents[v]), 1e-6f);
    }
  }
}

void expectSameMaterial(const Material& a, const Material& b) {
  SCOPED_TRACE("material '" + a.name + "'");
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.baseColorFactor, b.baseColorFactor);
  EXPECT_EQ(a.metallicFactor, b.metallicFactor);
  EXPECT_EQ(a.roughnessFactor, b.roughnessFactor);
  const glm::vec3 emission = a.emissiveFactor * a.emissiveStrength;
  const glm::vec3 back = b.emissiveFactor * b.emissiveStrength;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(back[c], emission[c], 1e-6f * emission[c]);
  EXPECT_EQ(a.normalScale, b.normalScale);
  EXPECT_EQ(a.occlusionStrength, b.occlusionStrength);
  EXPECT_EQ(a.alphaMode, b.alphaMode);
  EXPECT_EQ(a.alphaCutoff, b.alphaCutoff);
  EXPECT_EQ(a.doubleSided, b.doubleSided);
  EXPECT_EQ(a.baseColorTexture, b.baseColorTexture);
  EXPECT_EQ(a.metallicRoughnessTexture, b.metallicRoughnessTexture);
  EXPECT_EQ(a.normalTexture, b.normalTexture);
  EXPECT_EQ(a.emissiveTexture, b.emissiveTexture);
  EXPECT_EQ(a.occlusionTexture, b.occlusionTexture);
}

// Node i of `a` is node i of `b` (the export appends its own nodes after
// them), with the same name, links, meshes and local transform.
void expectSameNodes(const Scene& a, const Scene& b) {
  ASSERT_GE(b.nodes.size(), a.nodes.size());
  for (std::size_t n = 0; n < a.nodes.size(); ++n) {
    SCOPED_TRACE("node " + std::to_string(n) + " '" + a.nodes[n].name + "'");
    EXPECT_EQ(a.nodes[n].name, b.nodes[n].name);
    EXPECT_EQ(a.nodes[n].parent, b.nodes[n].parent);
    EXPECT_EQ(a.nodes[n].children, b.nodes[n].children);
    EXPECT_EQ(a.nodes[n].meshes, b.nodes[n].meshes);
    EXPECT_EQ(a.nodes[n].local.translation, b.nodes[n].local.translation);
    // The importer makes rotations unit length again, which may move a last bit.
    const glm::quat& r = a.nodes[n].local.rotation;
    EXPECT_LT(glm::length(glm::vec4(r.x, r.y, r.z, r.w) -
                          glm::vec4(b.nodes[n].local.rotation.x, b.nodes[n].local.rotation.y,
                                    b.nodes[n].local.rotation.z, b.nodes[n].local.rotation.w)),
              1e-6f);
    EXPECT_EQ(a.nodes[n].local.scale, b.nodes[n].local.scale);
  }
}

void expectSameBounds(const Scene& a, const Scene& b, float time) {
  const Bounds boundsA = worldBounds(a, time);
  const Bounds boundsB = worldBounds(b, time);
  EXPECT_LT(glm::length(boundsA.min - boundsB.min), 1e-5f) << "at t = " << time;
  EXPECT_LT(glm::length(boundsA.max - boundsB.max), 1e-5f) << "at t = " << time;
}

std::size_t triangles(const Scene& s) {
  std::size_t count = 0;
  for (const Instance& instance : instancesAt(s, 0.0f))
    count += s.meshes[std::size_t(instance.mesh)].indices.size() / 3;
  return count;
}

// The animated sun room with an edited material: every mesh, material,
// node, the sliding box's animation, the sun and the suggested view come back.
TEST_F(ExportTest, AnEditedBuiltInSceneComesBackFromGltf) {
  Scene original = makeBuiltinScene("sun-room-animated");
  Material& edited = original.materials[1];
  edited.baseColorFactor = glm::vec4(0.125f, 0.5f, 0.75f, 1.0f);
  edited.roughnessFactor = 0.3f;
  edited.metallicFactor = 0.25f;
  edited.emissiveFactor = glm::vec3(0.5f, 0.25f, 1.0f);
  edited.emissiveStrength = 4.0f;
  const fs::path file = folder_ / "sun room.gltf";
  writeGltf(original, file);
  EXPECT_TRUE(fs::exists(folder_ / "sun room.bin"));
  const json document = documentOf(file);
  EXPECT_EQ(document["buffers"][0]["uri"], "sun%20room.bin");
  EXPECT_EQ(document["materials"][1]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"], 4.0);
  EXPECT_FALSE(document["materials"][0].contains("extensions"));

  Scene loaded = load(file);
  expectSameMeshes(original, loaded);
  EXPECT_EQ(triangles(original), triangles(loaded));
  ASSERT_EQ(loaded.materials.size(), original.materials.size());
  for (std::size_t m = 0; m < original.materials.size(); ++m)
    expectSameMaterial(original.materials[m], loaded.materials[m]);
  EXPECT_EQ(loaded.materials[1].emissiveStrength, 4.0f);
  expectSameNodes(original, loaded);
  // The sun and the suggested view, each a root node of their own.
  ASSERT_EQ(loaded.nodes.size(), original.nodes.size() + 2);
  EXPECT_EQ(loaded.roots.size(), original.roots.size() + 2);
  for (float time : {0.0f, 1.3f, 4.7f}) expectSameBounds(original, loaded, time);
  ASSERT_EQ(loaded.animations.size(), original.animations.size());
  for (std::size_t a = 0; a < original.animations.size(); ++a) {
    ASSERT_EQ(loaded.animations[a].channels.size(), original.animations[a].channels.size());
    for (std::size_t c = 0; c < original.animations[a].channels.size(); ++c) {
      const AnimationChannel& before = original.animations[a].channels[c];
      const AnimationChannel& after = loaded.animations[a].channels[c];
      EXPECT_EQ(after.node, before.node);
      EXPECT_EQ(after.property, before.property);
      EXPECT_EQ(after.interpolation, before.interpolation);
      EXPECT_EQ(after.times, before.times);
      ASSERT_EQ(after.values.size(), before.values.size());
      for (std::size_t k = 0; k < before.values.size(); ++k)
        EXPECT_LT(glm::length(after.values[k] - before.values[k]), 1e-6f) << "key value " << k;
    }
  }

  ASSERT_TRUE(adoptDirectionalLightAsSun(loaded));
  EXPECT_TRUE(loaded.hasSun);
  EXPECT_NEAR(loaded.sun.elevationDegrees, original.sun.elevationDegrees, 1e-3f);
  EXPECT_NEAR(loaded.sun.azimuthDegrees, original.sun.azimuthDegrees, 1e-3f);
  EXPECT_EQ(loaded.sun.illuminance, original.sun.illuminance);
  EXPECT_EQ(loaded.sun.color, original.sun.color);

  ASSERT_EQ(loaded.cameras.size(), 1u);
  const CameraPose& view = *original.suggestedCamera;
  EXPECT_NEAR(loaded.cameras[0].yfov, glm::radians(view.fovYDegrees), 1e-6f);
  const glm::mat4 camera = nodeWorldMatrices(loaded, 0.0f).back();
  EXPECT_EQ(loaded.nodes.back().camera, 0);
  EXPECT_LT(glm::length(glm::vec3(camera[3]) - view.position), 1e-5f);
  const glm::vec3 forward = -glm::vec3(camera[2]);
  EXPECT_LT(glm::length(forward - glm::normalize(view.target - view.position)), 1e-5f);
  EXPECT_GT(glm::vec3(camera[1]).y, 0.5f);  // upright
}

// The box without sun: the spot light comes back as it was, and the sun
// node carries intensity 0, so the scene loaded again has no sunlight.
TEST_F(ExportTest, ASceneWithoutSunComesBackDarkWithItsLights) {
  const Scene original = makeBuiltinScene("cornell");
  ASSERT_FALSE(original.hasSun);
  writeGltf(original, folder_ / "cornell.glb");
  Scene loaded = load(folder_ / "cornell.glb");
  expectSameMeshes(original, loaded);
  expectSameNodes(original, loaded);
  ASSERT_EQ(loaded.lights.size(), 2u);
  const Light& spot = loaded.lights[0];
  EXPECT_EQ(spot.type, LightType::Spot);
  EXPECT_EQ(spot.color, original.lights[0].color);
  EXPECT_EQ(spot.intensity, original.lights[0].intensity);
  EXPECT_EQ(spot.outerConeAngle, original.lights[0].outerConeAngle);
  ASSERT_TRUE(adoptDirectionalLightAsSun(loaded));
  EXPECT_EQ(loaded.sun.illuminance, 0.0f);
}

// Textures as PNG files beside a .gltf and inside a .glb, texel for texel;
// emission brighter than glTF's factor range is carried by the strength.
TEST_F(ExportTest, TexturesAndBrightEmissionComeBackExactly) {
  Scene original = makeBuiltinScene("cornell");
  Texture texture;
  texture.name = "checker";
  texture.width = 3;
  texture.height = 2;
  texture.srgb = true;
  for (int i = 0; i < 6; ++i)
    texture.rgba8.insert(texture.rgba8.end(), {std::uint8_t(40 * i), std::uint8_t(255 - i), 7, std::uint8_t(200 + i)});
  Texture roughness = texture;
  roughness.name = "roughness";
  roughness.srgb = false;
  roughness.rgba8[1] = 99;
  original.textures = {texture, roughness};
  original.materials[0].baseColorTexture = 0;
  original.materials[0].metallicRoughnessTexture = 1;
  original.materials[3].emissiveFactor = glm::vec3(40.0f, 20.0f, 10.0f);
  original.materials[3].emissiveStrength = 1.0f;

  for (const char* name : {"textured.gltf", "textured.glb"}) {
    SCOPED_TRACE(name);
    writeGltf(original, folder_ / name);
    const Scene loaded = load(folder_ / name);
    ASSERT_EQ(loaded.textures.size(), 2u);
    for (std::size_t t = 0; t < 2; ++t) {
      EXPECT_EQ(loaded.textures[t].width, 3);
      EXPECT_EQ(loaded.textures[t].height, 2);
      EXPECT_EQ(loaded.textures[t].srgb, original.textures[t].srgb);
      EXPECT_EQ(loaded.textures[t].rgba8, original.textures[t].rgba8);
    }
    expectSameMaterial(original.materials[0], loaded.materials[0]);
    expectSameMaterial(original.materials[3], loaded.materials[3]);
    EXPECT_EQ(loaded.materials[3].emissiveFactor, glm::vec3(1.0f, 0.5f, 0.25f));
    EXPECT_EQ(loaded.materials[3].emissiveStrength, 40.0f);
  }
  EXPECT_TRUE(fs::exists(folder_ / "textured.texture0.png"));
  EXPECT_TRUE(fs::exists(folder_ / "textured.texture1.png"));
  EXPECT_EQ(documentOf(folder_ / "textured.gltf")["images"][1]["uri"], "textured.texture1.png");
}

// A scene loaded from a file may be exported anywhere but onto the files it
// was loaded from (the .gltf, its buffer, its images); an earlier export is
// overwritten.
TEST_F(ExportTest, RefusesToOverwriteTheScenesOwnFiles) {
  writeGltf(makeBuiltinScene("pillars"), folder_ / "pillars.gltf");
  // The buffer renamed, so that another export's buffer would take its name.
  fs::rename(folder_ / "pillars.bin", folder_ / "copy.bin");
  json document = documentOf(folder_ / "pillars.gltf");
  document["buffers"][0]["uri"] = "copy.bin";
  std::ofstream(folder_ / "pillars.gltf") << document.dump();
  const Scene loaded = load(folder_ / "pillars.gltf");

  const std::string own = messageOf([&] { writeGltf(loaded, folder_ / "pillars.gltf"); });
  EXPECT_EQ(own.rfind((folder_ / "pillars.gltf").string() + ": is one of the files the scene was loaded from", 0), 0u)
      << own;
  const std::string buffer = messageOf([&] { writeGltf(loaded, folder_ / "copy.gltf"); });
  EXPECT_EQ(buffer.rfind((folder_ / "copy.bin").string() + ": is one of the files the scene was loaded from", 0), 0u)
      << buffer;
  EXPECT_EQ(load(folder_ / "pillars.gltf").meshes.size(), loaded.meshes.size());  // untouched

  writeGltf(loaded, folder_ / "again.glb");
  writeGltf(loaded, folder_ / "again.glb");
  EXPECT_EQ(load(folder_ / "again.glb").meshes.size(), loaded.meshes.size());
}

TEST_F(ExportTest, NamesTheFileItCannotWrite) {
  const Scene scene = makeBuiltinScene("cornell");
  EXPECT_EQ(messageOf([&] { writeGltf(scene, folder_ / "cornell.obj"); }),
            (folder_ / "cornell.obj").string() + ": a glTF export is named .gltf or .glb (got '.obj')");
  EXPECT_EQ(messageOf([&] { writeGltf(scene, folder_ / "missing" / "cornell.gltf"); }),
            (folder_ / "missing" / "cornell.bin").string() + ": directory " + (folder_ / "missing").string() +
                " does not exist");
  std::ofstream(folder_ / "file") << "not a folder";
  EXPECT_EQ(messageOf([&] { writeGltf(scene, folder_ / "file" / "cornell.glb"); }),
            (folder_ / "file" / "cornell.glb").string() + ": " + (folder_ / "file").string() + " is not a directory");
  // /proc takes no new files, not even root's.
  const std::string unwritable = messageOf([&] { writeGltf(scene, "/proc/cornell.glb"); });
  EXPECT_EQ(unwritable.rfind("/proc/cornell.glb: cannot create /proc/cornell.glb.tmp-", 0), 0u) << unwritable;
}

// ------------------------------------------------------------------ the glTF 2.0 spec's rules

// What an export must satisfy to pass the Khronos glTF Validator with no
// errors, checked on the written file the way the validator checks it:
// numbers as the doubles written in the JSON (pi/2 rounded up through a
// float is out of range), accessor data read from the written buffer. Only
// the rules an exporter could break are here: ranges of factors, lights and
// cameras, indices that resolve, buffer and view sizes, accessor bounds and
// unit vectors (with the validator's tolerances), animation keys. The
// validator itself cannot be installed here.
class SpecCheck {
 public:
  explicit SpecCheck(const fs::path& file) : file_(file) {
    std::ifstream stream(file, std::ios::binary);
    const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
    if (file.extension() == ".glb") {
      readGlb(bytes);
    } else {
      doc_ = json::parse(bytes.begin(), bytes.end());
      if (doc_.contains("buffers")) {
        const fs::path bin = file.parent_path() / doc_["buffers"][0]["uri"].get<std::string>();
        std::ifstream binStream(bin, std::ios::binary);
        bin_.assign(std::istreambuf_iterator<char>(binStream), std::istreambuf_iterator<char>());
        binPadding_ = 0;  // an external file must be exactly byteLength long
      }
    }
  }

  // Every problem found, one line each ("/materials/0/emissiveFactor/1: 2 is not in [0, 1]").
  std::vector<std::string> problems() {
    checkAsset();
    checkBuffers();
    checkAccessors();
    checkMaterials();
    checkMeshes();
    checkNodesAndScenes();
    checkCameras();
    checkLights();
    checkAnimations();
    checkTexturesAndImages();
    return problems_;
  }

  const json& document() const { return doc_; }

 private:
  static constexpr double kUnitVec3 = 0.00674;  // the validator's unitLengthThresholdVec3
  static constexpr double kUnitVec4 = 0.00769;  // and unitLengthThresholdVec4
  static constexpr int kFloat = 5126, kUnsignedByte = 5121, kUnsignedShort = 5123, kUnsignedInt = 5125;

  void problem(const std::string& where, const std::string& what) { problems_.push_back(where + ": " + what); }

  static std::string text(const json& value) { return value.dump(); }

  void readGlb(const std::vector<std::uint8_t>& bytes) {
    const auto u32 = [&](std::size_t at) {
      std::uint32_t value = 0;
      std::memcpy(&value, bytes.data() + at, 4);
      return value;
    };
    ASSERT_GE(bytes.size(), 20u);
    EXPECT_EQ(u32(0), 0x46546C67u) << "GLB magic";
    EXPECT_EQ(u32(4), 2u) << "GLB version";
    EXPECT_EQ(u32(8), bytes.size()) << "GLB length";
    const std::uint32_t jsonLength = u32(12);
    EXPECT_EQ(jsonLength % 4, 0u) << "the JSON chunk is padded to 4 bytes";
    EXPECT_EQ(u32(16), 0x4E4F534Au) << "the first chunk is JSON";
    doc_ = json::parse(bytes.begin() + 20, bytes.begin() + 20 + jsonLength);
    const std::size_t bin = 20 + jsonLength;
    if (bin < bytes.size()) {
      const std::uint32_t binLength = u32(bin);
      EXPECT_EQ(binLength % 4, 0u) << "the BIN chunk is padded to 4 bytes";
      EXPECT_EQ(u32(bin + 4), 0x004E4942u) << "the second chunk is BIN";
      EXPECT_EQ(bin + 8 + binLength, bytes.size());
      bin_.assign(bytes.begin() + long(bin) + 8, bytes.begin() + long(bin) + 8 + binLength);
      binPadding_ = 3;  // byteLength may be up to 3 bytes short of the chunk
    }
  }

  const json& array(const char* name) const {
    static const json empty = json::array();
    return doc_.contains(name) ? doc_[name] : empty;
  }

  // `value` at `where` is an index into the top-level array `of`.
  bool resolves(const json& value, const char* of, const std::string& where) {
    if (!value.is_number_unsigned() || value.get<std::size_t>() >= array(of).size()) {
      problem(where, text(value) + " is not an index into " + of);
      return false;
    }
    return true;
  }

  void inRange(const json& value, double min, double max, const std::string& where) {
    if (!value.is_number() || !(value.get<double>() >= min && value.get<double>() <= max))
      problem(where, text(value) + " is not in [" + text(min) + ", " + text(max) + "]");
  }

  void numbersInRange(const json& values, std::size_t count, double min, double max, const std::string& where) {
    if (!values.is_array() || values.size() != count)
      return problem(where, "must have " + std::to_string(count) + " numbers");
    for (std::size_t i = 0; i < count; ++i) inRange(values[i], min, max, where + "/" + std::to_string(i));
  }

  void usesExtension(const std::string& name, const std::string& where) {
    const json& used = array("extensionsUsed");
    if (std::find(used.begin(), used.end(), name) == used.end()) problem(where, name + " is not in extensionsUsed");
  }

  void checkAsset() {
    if (doc_["asset"]["version"] != "2.0") problem("/asset/version", "must be \"2.0\"");
    for (const json& required : array("extensionsRequired")) usesExtension(required, "/extensionsRequired");
  }

  void checkBuffers() {
    if (array("buffers").size() > 1) problem("/buffers", "the exporter writes one buffer");
    for (std::size_t b = 0; b < array("buffers").size(); ++b) {
      const std::size_t length = doc_["buffers"][b]["byteLength"];
      if (length < 1) problem("/buffers/0/byteLength", "must be at least 1");
      if (!(length <= bin_.size() && bin_.size() - length <= binPadding_))
        problem("/buffers/0/byteLength", std::to_string(length) + " does not match the " + std::to_string(bin_.size()) +
                                             " bytes of the buffer's data");
    }
    const json& views = array("bufferViews");
    for (std::size_t v = 0; v < views.size(); ++v) {
      const std::string where = "/bufferViews/" + std::to_string(v);
      const json& view = views[v];
      if (!resolves(view["buffer"], "buffers", where + "/buffer")) continue;
      const std::size_t length = view["byteLength"], offset = view.value("byteOffset", 0);
      if (length < 1) problem(where + "/byteLength", "must be at least 1");
      if (offset + length > doc_["buffers"][0]["byteLength"].get<std::size_t>())
        problem(where, "runs past the end of its buffer");
      if (view.contains("byteStride")) {
        const std::size_t stride = view["byteStride"];
        if (stride < 4 || stride > 252 || stride % 4 != 0) problem(where + "/byteStride", text(view["byteStride"]));
      }
      if (view.contains("target") && view["target"] != 34962 && view["target"] != 34963)
        problem(where + "/target", text(view["target"]));
    }
  }

  static std::size_t components(const std::string& type) {
    if (type == "SCALAR") return 1;
    if (type == "VEC2") return 2;
    if (type == "VEC3") return 3;
    if (type == "VEC4" || type == "MAT2") return 4;
    if (type == "MAT3") return 9;
    if (type == "MAT4") return 16;
    return 0;
  }

  static std::size_t componentSize(int componentType) {
    switch (componentType) {
      case 5120:
      case kUnsignedByte:
        return 1;
      case 5122:
      case kUnsignedShort:
        return 2;
      case kUnsignedInt:
      case kFloat:
        return 4;
    }
    return 0;
  }

  // Accessor `index`'s components, element after element, as doubles;
  // empty when the accessor could not be read (a problem is recorded).
  std::vector<double> values(const json& index) const {
    return index.get<std::size_t>() < data_.size() ? data_[index.get<std::size_t>()] : std::vector<double>{};
  }

  void checkAccessors() {
    const json& accessors = array("accessors");
    data_.assign(accessors.size(), {});
    for (std::size_t a = 0; a < accessors.size(); ++a) {
      const std::string where = "/accessors/" + std::to_string(a);
      const json& accessor = accessors[a];
      const int componentType = accessor["componentType"];
      const std::size_t size = componentSize(componentType), n = components(accessor["type"]);
      const std::size_t count = accessor["count"];
      if (size == 0 || n == 0) {
        problem(where, "componentType " + std::to_string(componentType) + " or type " + text(accessor["type"]));
        continue;
      }
      if (count < 1) problem(where + "/count", "must be at least 1");
      if (!accessor.contains("bufferView") || !resolves(accessor["bufferView"], "bufferViews", where + "/bufferView"))
        continue;
      const json& view = doc_["bufferViews"][accessor["bufferView"].get<std::size_t>()];
      const std::size_t offset = accessor.value("byteOffset", 0);
      const std::size_t stride = view.value("byteStride", size * n);
      if (offset % size != 0 || (view.value("byteOffset", 0) + offset) % size != 0)
        problem(where + "/byteOffset", "is not a multiple of the component size");
      if (offset + stride * (count - 1) + size * n > view["byteLength"].get<std::size_t>()) {
        problem(where, "does not fit in its bufferView");
        continue;
      }
      const std::size_t start = view.value("byteOffset", 0) + offset;
      if (start + stride * (count - 1) + size * n > bin_.size()) continue;  // reported with the buffer
      std::vector<double>& out = data_[a];
      for (std::size_t e = 0; e < count; ++e)
        for (std::size_t c = 0; c < n; ++c) {
          const std::uint8_t* at = bin_.data() + start + e * stride + c * size;
          if (componentType == kFloat) {
            float f;
            std::memcpy(&f, at, 4);
            if (!std::isfinite(f)) problem(where, "holds a NaN or infinity");
            out.push_back(f);
          } else if (componentType == kUnsignedInt) {
            std::uint32_t u;
            std::memcpy(&u, at, 4);
            out.push_back(u);
          } else if (componentType == kUnsignedShort) {
            std::uint16_t u;
            std::memcpy(&u, at, 2);
            out.push_back(u);
          } else {
            out.push_back(*at);
          }
        }
      // min and max, where given, are exactly the data's.
      for (const char* bound : {"min", "max"}) {
        if (!accessor.contains(bound)) continue;
        const json& declared = accessor[bound];
        if (declared.size() != n) {
          problem(where + "/" + bound, "must have " + std::to_string(n) + " numbers");
          continue;
        }
        for (std::size_t c = 0; c < n; ++c) {
          double actual = out[c];
          for (std::size_t e = 1; e < count; ++e)
            actual = bound[1] == 'i' ? std::min(actual, out[e * n + c]) : std::max(actual, out[e * n + c]);
          if (declared[c].get<double>() != actual)
            problem(where + "/" + bound + "/" + std::to_string(c),
                    text(declared[c]) + " is not the data's " + bound + " " + text(actual));
        }
      }
    }
  }

  // Accessor `index` has the type and one of the component types a use needs.
  bool accessorIs(const json& index, const std::string& type, const std::vector<int>& componentTypes,
                  const std::string& where) {
    if (!resolves(index, "accessors", where)) return false;
    const json& accessor = doc_["accessors"][index.get<std::size_t>()];
    if (accessor["type"] != type || std::find(componentTypes.begin(), componentTypes.end(),
                                              accessor["componentType"].get<int>()) == componentTypes.end()) {
      problem(where,
              "accessor " + text(index) + " is " + text(accessor["type"]) + " of " + text(accessor["componentType"]));
      return false;
    }
    return true;
  }

  // Marks the views an accessor use reads through; a view used two ways
  // (vertex data and indices) or without the target its use needs is an error.
  void viewUsedAs(const json& accessorIndex, const std::string& use, const std::string& where) {
    const json& accessor = doc_["accessors"][accessorIndex.get<std::size_t>()];
    if (!accessor.contains("bufferView")) return;
    const std::size_t v = accessor["bufferView"];
    const json& view = doc_["bufferViews"][v];
    const int wanted = use == "vertices" ? 34962 : use == "indices" ? 34963 : 0;
    if (view.contains("target") && view["target"] != wanted)
      problem(where, "bufferView " + std::to_string(v) + " has target " + text(view["target"]) + " but holds " + use);
    auto [found, added] = viewUse_.try_emplace(v, use);
    if (!added && found->second != use)
      problem(where, "bufferView " + std::to_string(v) + " holds " + found->second + " and " + use);
  }

  void checkMaterials() {
    const json& materials = array("materials");
    for (std::size_t m = 0; m < materials.size(); ++m) {
      const std::string where = "/materials/" + std::to_string(m);
      const json& material = materials[m];
      if (material.contains("pbrMetallicRoughness")) {
        const json& pbr = material["pbrMetallicRoughness"];
        const std::string at = where + "/pbrMetallicRoughness";
        if (pbr.contains("baseColorFactor")) numbersInRange(pbr["baseColorFactor"], 4, 0, 1, at + "/baseColorFactor");
        if (pbr.contains("metallicFactor")) inRange(pbr["metallicFactor"], 0, 1, at + "/metallicFactor");
        if (pbr.contains("roughnessFactor")) inRange(pbr["roughnessFactor"], 0, 1, at + "/roughnessFactor");
        for (const char* texture : {"baseColorTexture", "metallicRoughnessTexture"})
          if (pbr.contains(texture)) resolves(pbr[texture]["index"], "textures", at + "/" + texture + "/index");
      }
      if (material.contains("emissiveFactor"))
        numbersInRange(material["emissiveFactor"], 3, 0, 1, where + "/emissiveFactor");
      if (material.contains("occlusionTexture") && material["occlusionTexture"].contains("strength"))
        inRange(material["occlusionTexture"]["strength"], 0, 1, where + "/occlusionTexture/strength");
      for (const char* texture : {"normalTexture", "occlusionTexture", "emissiveTexture"})
        if (material.contains(texture))
          resolves(material[texture]["index"], "textures", where + "/" + texture + "/index");
      if (material.contains("alphaCutoff")) {
        inRange(material["alphaCutoff"], 0, std::numeric_limits<double>::max(), where + "/alphaCutoff");
        if (material.value("alphaMode", "OPAQUE") != "MASK") problem(where + "/alphaCutoff", "is only for MASK");
      }
      const std::string mode = material.value("alphaMode", "OPAQUE");
      if (mode != "OPAQUE" && mode != "MASK" && mode != "BLEND") problem(where + "/alphaMode", mode);
      if (material.contains("extensions") && material["extensions"].contains("KHR_materials_emissive_strength")) {
        usesExtension("KHR_materials_emissive_strength", where);
        inRange(material["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"], 0,
                std::numeric_limits<double>::max(),
                where + "/extensions/KHR_materials_emissive_strength/emissiveStrength");
      }
    }
  }

  void checkMeshes() {
    const json& meshes = array("meshes");
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      const json& primitives = meshes[m]["primitives"];
      if (primitives.empty()) problem("/meshes/" + std::to_string(m), "has no primitives");
      for (std::size_t p = 0; p < primitives.size(); ++p) {
        const std::string where = "/meshes/" + std::to_string(m) + "/primitives/" + std::to_string(p);
        const json& primitive = primitives[p];
        const json& attributes = primitive["attributes"];
        if (!attributes.contains("POSITION")) {
          problem(where, "has no POSITION");
          continue;
        }
        std::optional<std::size_t> vertices;
        for (const auto& [name, index] : attributes.items()) {
          const std::string at = where + "/attributes/" + name;
          if (!resolves(index, "accessors", at)) continue;
          const std::size_t count = doc_["accessors"][index.get<std::size_t>()]["count"];
          if (vertices && count != *vertices) problem(at, "has another count than POSITION");
          if (!vertices) vertices = count;
          viewUsedAs(index, "vertices", at);
        }
        if (accessorIs(attributes["POSITION"], "VEC3", {kFloat}, where + "/attributes/POSITION")) {
          const json& position = doc_["accessors"][attributes["POSITION"].get<std::size_t>()];
          if (!position.contains("min") || !position.contains("max"))
            problem(where + "/attributes/POSITION", "accessor has no min and max");
        }
        if (attributes.contains("NORMAL") &&
            accessorIs(attributes["NORMAL"], "VEC3", {kFloat}, where + "/attributes/NORMAL")) {
          const std::vector<double> n = values(attributes["NORMAL"]);
          for (std::size_t v = 0; v + 2 < n.size(); v += 3)
            if (std::abs(std::sqrt(n[v] * n[v] + n[v + 1] * n[v + 1] + n[v + 2] * n[v + 2]) - 1.0) > kUnitVec3) {
              problem(where + "/attributes/NORMAL", "vertex " + std::to_string(v / 3) + " is not unit length");
              break;
            }
        }
        if (attributes.contains("TANGENT") &&
            accessorIs(attributes["TANGENT"], "VEC4", {kFloat}, where + "/attributes/TANGENT")) {
          const std::vector<double> t = values(attributes["TANGENT"]);
          for (std::size_t v = 0; v + 3 < t.size(); v += 4)
            if (std::abs(std::sqrt(t[v] * t[v] + t[v + 1] * t[v + 1] + t[v + 2] * t[v + 2]) - 1.0) > kUnitVec3 ||
                (t[v + 3] != 1.0 && t[v + 3] != -1.0)) {
              problem(where + "/attributes/TANGENT",
                      "vertex " + std::to_string(v / 4) + " is not unit length with w +-1");
              break;
            }
        }
        if (attributes.contains("TEXCOORD_0"))
          accessorIs(attributes["TEXCOORD_0"], "VEC2", {kFloat, kUnsignedByte, kUnsignedShort},
                     where + "/attributes/TEXCOORD_0");
        const int mode = primitive.value("mode", 4);
        if (mode < 0 || mode > 6) problem(where + "/mode", std::to_string(mode));
        if (primitive.contains("material")) resolves(primitive["material"], "materials", where + "/material");
        if (!primitive.contains("indices")) continue;
        if (!accessorIs(primitive["indices"], "SCALAR", {kUnsignedByte, kUnsignedShort, kUnsignedInt},
                        where + "/indices"))
          continue;
        viewUsedAs(primitive["indices"], "indices", where + "/indices");
        const json& accessor = doc_["accessors"][primitive["indices"].get<std::size_t>()];
        if (accessor.value("normalized", false)) problem(where + "/indices", "must not be normalized");
        const double restart = std::pow(2.0, 8.0 * double(componentSize(accessor["componentType"]))) - 1.0;
        const std::vector<double> indices = values(primitive["indices"]);
        if (mode == 4 && indices.size() % 3 != 0) problem(where + "/indices", "count is not a multiple of 3");
        for (double index : indices)
          if (index >= double(vertices.value_or(0)) || index == restart) {
            problem(where + "/indices", "index " + text(index) + " is out of range or the restart value");
            break;
          }
      }
    }
  }

  void checkNodesAndScenes() {
    const json& nodes = array("nodes");
    std::vector<int> parents(nodes.size(), 0);
    for (std::size_t n = 0; n < nodes.size(); ++n) {
      const std::string where = "/nodes/" + std::to_string(n);
      const json& node = nodes[n];
      if (node.contains("mesh")) resolves(node["mesh"], "meshes", where + "/mesh");
      if (node.contains("camera")) resolves(node["camera"], "cameras", where + "/camera");
      for (const json& child : node.value("children", json::array()))
        if (resolves(child, "nodes", where + "/children") && ++parents[child.get<std::size_t>()] > 1)
          problem(where + "/children", "node " + text(child) + " has two parents");
      if (node.contains("rotation")) {
        const json& r = node["rotation"];
        double length = 0.0;
        for (const json& c : r) length += c.get<double>() * c.get<double>();
        if (r.size() != 4 || std::abs(std::sqrt(length) - 1.0) > kUnitVec4)
          problem(where + "/rotation", text(r) + " is not a unit quaternion");
      }
      if (node.contains("translation") && node["translation"].size() != 3) problem(where + "/translation", "size");
      if (node.contains("scale") && node["scale"].size() != 3) problem(where + "/scale", "size");
      if (node.contains("extensions") && node["extensions"].contains("KHR_lights_punctual")) {
        usesExtension("KHR_lights_punctual", where);
        const json& light = node["extensions"]["KHR_lights_punctual"]["light"];
        const json& lights = doc_["extensions"]["KHR_lights_punctual"]["lights"];
        if (!light.is_number_unsigned() || light.get<std::size_t>() >= lights.size())
          problem(where + "/extensions/KHR_lights_punctual/light", text(light) + " names no light");
      }
    }
    if (doc_.contains("scene")) resolves(doc_["scene"], "scenes", "/scene");
    const json& scenes = array("scenes");
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      std::vector<bool> listed(nodes.size(), false);
      for (const json& root : scenes[s].value("nodes", json::array())) {
        const std::string where = "/scenes/" + std::to_string(s) + "/nodes";
        if (!resolves(root, "nodes", where)) continue;
        const std::size_t n = root;
        if (listed[n]) problem(where, "lists node " + std::to_string(n) + " twice");
        if (parents[n] > 0) problem(where, "node " + std::to_string(n) + " is not a root");
        listed[n] = true;
      }
    }
  }

  void checkCameras() {
    const json& cameras = array("cameras");
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      const std::string where = "/cameras/" + std::to_string(c);
      if (cameras[c]["type"] != "perspective") {
        problem(where + "/type", "the exporter writes perspective cameras");
        continue;
      }
      const json& p = cameras[c]["perspective"];
      const double yfov = p["yfov"], znear = p["znear"];
      if (!(yfov > 0.0 && yfov < glm::pi<double>())) problem(where + "/perspective/yfov", text(p["yfov"]));
      if (!(znear > 0.0)) problem(where + "/perspective/znear", text(p["znear"]));
      if (p.contains("zfar") && !(p["zfar"].get<double>() > znear))
        problem(where + "/perspective/zfar", "not past znear");
      if (p.contains("aspectRatio") && !(p["aspectRatio"].get<double>() > 0.0))
        problem(where + "/perspective/aspectRatio", text(p["aspectRatio"]));
    }
  }

  void checkLights() {
    if (!doc_.contains("extensions") || !doc_["extensions"].contains("KHR_lights_punctual")) return;
    usesExtension("KHR_lights_punctual", "/extensions");
    const json& lights = doc_["extensions"]["KHR_lights_punctual"]["lights"];
    for (std::size_t l = 0; l < lights.size(); ++l) {
      const std::string where = "/extensions/KHR_lights_punctual/lights/" + std::to_string(l);
      const json& light = lights[l];
      const std::string type = light["type"];
      if (type != "directional" && type != "point" && type != "spot") problem(where + "/type", type);
      if (light.contains("color")) numbersInRange(light["color"], 3, 0, 1, where + "/color");
      if (light.contains("intensity"))
        inRange(light["intensity"], 0, std::numeric_limits<double>::max(), where + "/intensity");
      if (light.contains("range")) {
        if (!(light["range"].get<double>() > 0.0)) problem(where + "/range", text(light["range"]) + " is not above 0");
        if (type == "directional") problem(where + "/range", "a directional light has no range");
      }
      if (type != "spot") {
        if (light.contains("spot")) problem(where + "/spot", "only a spot light has one");
        continue;
      }
      const json& spot = light["spot"];
      const double inner = spot.value("innerConeAngle", 0.0);
      const double outer = spot.value("outerConeAngle", glm::quarter_pi<double>());
      // As the validator compares them: the double written, against pi/2 as a double.
      if (!(inner >= 0.0 && inner < glm::half_pi<double>()))
        problem(where + "/spot/innerConeAngle", text(spot["innerConeAngle"]) + " is out of range");
      if (!(outer > 0.0 && outer <= glm::half_pi<double>()))
        problem(where + "/spot/outerConeAngle", text(spot["outerConeAngle"]) + " is out of range");
      if (!(inner < outer)) problem(where + "/spot", "innerConeAngle is not below outerConeAngle");
    }
  }

  void checkAnimations() {
    const json& animations = array("animations");
    for (std::size_t a = 0; a < animations.size(); ++a) {
      const std::string where = "/animations/" + std::to_string(a);
      const json& samplers = animations[a]["samplers"];
      std::set<std::pair<std::size_t, std::string>> targets;
      for (std::size_t c = 0; c < animations[a]["channels"].size(); ++c) {
        const json& channel = animations[a]["channels"][c];
        const std::string at = where + "/channels/" + std::to_string(c);
        const std::string path = channel["target"]["path"];
        if (!resolves(channel["target"]["node"], "nodes", at + "/target/node")) continue;
        if (!targets.insert({channel["target"]["node"].get<std::size_t>(), path}).second)
          problem(at, "animates a node's " + path + " a second time");
        if (!(channel["sampler"].is_number_unsigned() && channel["sampler"].get<std::size_t>() < samplers.size())) {
          problem(at + "/sampler", "names no sampler");
          continue;
        }
        const json& sampler = samplers[channel["sampler"].get<std::size_t>()];
        const std::string in = where + "/samplers/" + text(channel["sampler"]);
        const bool rotation = path == "rotation";
        if (!rotation && path != "translation" && path != "scale") problem(at + "/target/path", path);
        if (!accessorIs(sampler["input"], "SCALAR", {kFloat}, in + "/input") ||
            !accessorIs(sampler["output"], rotation ? "VEC4" : "VEC3", {kFloat}, in + "/output"))
          continue;
        viewUsedAs(sampler["input"], "animation data", in + "/input");
        viewUsedAs(sampler["output"], "animation data", in + "/output");
        const json& input = doc_["accessors"][sampler["input"].get<std::size_t>()];
        if (!input.contains("min") || !input.contains("max")) problem(in + "/input", "accessor has no min and max");
        const std::vector<double> times = values(sampler["input"]);
        for (std::size_t k = 0; k < times.size(); ++k)
          if (times[k] < 0.0 || (k > 0 && !(times[k] > times[k - 1]))) {
            problem(in + "/input", "key times must be positive and increase");
            break;
          }
        const std::string interpolation = sampler.value("interpolation", "LINEAR");
        const std::size_t perKey = interpolation == "CUBICSPLINE" ? 3 : 1;
        const std::vector<double> outputs = values(sampler["output"]);
        const std::size_t width = rotation ? 4 : 3;
        if (outputs.size() != times.size() * perKey * width) problem(in + "/output", "count does not match input");
        if (rotation)
          for (std::size_t k = perKey / 3; k * width + 3 < outputs.size(); k += perKey) {
            double length = 0.0;
            for (std::size_t i = 0; i < 4; ++i) length += outputs[k * width + i] * outputs[k * width + i];
            if (std::abs(std::sqrt(length) - 1.0) > kUnitVec4) {
              problem(in + "/output", "key " + std::to_string(k / perKey) + " is not a unit quaternion");
              break;
            }
          }
      }
    }
  }

  void checkTexturesAndImages() {
    const json& textures = array("textures");
    for (std::size_t t = 0; t < textures.size(); ++t) {
      if (textures[t].contains("source"))
        resolves(textures[t]["source"], "images", "/textures/" + std::to_string(t) + "/source");
      if (textures[t].contains("sampler"))
        resolves(textures[t]["sampler"], "samplers", "/textures/" + std::to_string(t) + "/sampler");
    }
    const json& images = array("images");
    for (std::size_t i = 0; i < images.size(); ++i) {
      const std::string where = "/images/" + std::to_string(i);
      const json& image = images[i];
      if (image.contains("uri") == image.contains("bufferView")) problem(where, "needs a uri or a bufferView");
      if (image.contains("bufferView")) {
        if (!image.contains("mimeType")) problem(where, "a bufferView image needs a mimeType");
        if (resolves(image["bufferView"], "bufferViews", where + "/bufferView")) {
          const json& view = doc_["bufferViews"][image["bufferView"].get<std::size_t>()];
          if (view.contains("byteStride") || view.contains("target"))
            problem(where, "its bufferView has a stride or target");
        }
      } else if (image.contains("uri") && !fs::exists(file_.parent_path() / image["uri"].get<std::string>())) {
        problem(where + "/uri", "names no file");
      }
    }
  }

  fs::path file_;
  json doc_;
  std::vector<std::uint8_t> bin_;
  std::size_t binPadding_ = 0;
  std::vector<std::vector<double>> data_;  // accessor i's components
  std::map<std::size_t, std::string> viewUse_;
  std::vector<std::string> problems_;
};

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += "\n  " + line;
  return text;
}

// Every built-in scene, as .gltf and .glb: the written file keeps every rule
// of the spec (cornell's spot light, whose outer cone is pi/2 as a float,
// used to be written as 1.5707963705062866, above pi/2).
TEST_F(ExportTest, EveryBuiltInSceneIsWrittenWithinTheSpecsRules) {
  for (const std::string& name : builtinSceneNames())
    for (const char* extension : {".gltf", ".glb"}) {
      SCOPED_TRACE(name + extension);
      const fs::path file = folder_ / (name + extension);
      writeGltf(makeBuiltinScene(name), file);
      SpecCheck check(file);
      const std::vector<std::string> problems = check.problems();
      EXPECT_TRUE(problems.empty()) << joined(problems);
      EXPECT_FALSE(check.document()["meshes"].empty());
    }
}

// A glTF file loaded, edited as the viewer edits (materials and lights
// outside glTF's ranges for their factors: emission and light colour above
// 1, carried by strength and intensity), saved and checked; and the check
// itself finds what it is there to find.
TEST_F(ExportTest, AnEditedGltfIsWrittenWithinTheSpecsRulesAndTheCheckFindsBreaches) {
  writeGltf(makeBuiltinScene("sun-room-animated"), folder_ / "source.gltf");
  Scene edited = load(folder_ / "source.gltf");
  edited.materials[0].emissiveFactor = glm::vec3(8.0f, 2.0f, 0.0f);
  edited.materials[1].roughnessFactor = 0.0f;
  edited.materials[1].metallicFactor = 1.0f;
  Light spot;
  spot.name = "wide spot";
  spot.type = LightType::Spot;
  spot.color = glm::vec3(3.0f, 1.5f, 0.0f);
  spot.intensity = 20.0f;
  spot.range = 5.0f;
  spot.innerConeAngle = glm::half_pi<float>() - 1e-7f;  // the float just below pi/2's
  spot.outerConeAngle = glm::half_pi<float>();
  edited.lights.push_back(spot);
  edited.nodes[0].light = int(edited.lights.size()) - 1;
  const fs::path file = folder_ / "edited.glb";
  writeGltf(edited, file);
  SpecCheck check(file);
  const std::vector<std::string> problems = check.problems();
  EXPECT_TRUE(problems.empty()) << joined(problems);
  const json& lights = check.document()["extensions"]["KHR_lights_punctual"]["lights"];
  const auto written =
      std::find_if(lights.begin(), lights.end(), [](const json& l) { return l["name"] == "wide spot"; });
  ASSERT_NE(written, lights.end());
  EXPECT_EQ((*written)["spot"]["outerConeAngle"].get<double>(), glm::half_pi<double>());
  EXPECT_LT((*written)["spot"]["innerConeAngle"].get<double>(), glm::half_pi<double>());
  EXPECT_EQ((*written)["color"], json({1.0, 0.5, 0.0}));
  EXPECT_EQ((*written)["intensity"].get<double>(), 60.0);

  // What comes back renders the same light.
  Scene loaded = load(file);
  const auto back =
      std::find_if(loaded.lights.begin(), loaded.lights.end(), [](const Light& l) { return l.name == "wide spot"; });
  ASSERT_NE(back, loaded.lights.end());
  EXPECT_EQ(back->color * back->intensity, spot.color * spot.intensity);
  EXPECT_EQ(back->outerConeAngle, spot.outerConeAngle);

  // The check finds each breach it is meant to find, in a copy of the file.
  const auto breached = [&](const std::function<void(json&)>& change) {
    json document = check.document();
    change(document);
    const fs::path copy = folder_ / "breached.gltf";
    std::ofstream(copy) << document.dump();  // beside source.bin, which it names
    return SpecCheck(copy).problems();
  };
  writeGltf(makeBuiltinScene("cornell"), folder_ / "source.gltf");
  check = SpecCheck(folder_ / "source.gltf");
  ASSERT_TRUE(check.problems().empty());
  const std::vector<std::pair<std::string, std::function<void(json&)>>> breaches = {
      {"outerConeAngle",
       [](json& d) {
         d["extensions"]["KHR_lights_punctual"]["lights"][0]["spot"]["outerConeAngle"] = 1.5707963705062866;
       }},
      {"baseColorFactor", [](json& d) { d["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][0] = 5.0; }},
      {"roughnessFactor", [](json& d) { d["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] = -0.5; }},
      {"emissiveFactor",
       [](json& d) {
         d["materials"][0]["emissiveFactor"] = {2, 1, 1};
       }},
      {"range", [](json& d) { d["extensions"]["KHR_lights_punctual"]["lights"][0]["range"] = 0; }},
      {"color",
       [](json& d) {
         d["extensions"]["KHR_lights_punctual"]["lights"][0]["color"] = {2, 1, 1};
       }},
      {"min/0", [](json& d) { d["accessors"][0]["min"][0] = d["accessors"][0]["min"][0].get<double>() - 1.0; }},
      {"byteLength",
       [](json& d) { d["buffers"][0]["byteLength"] = d["buffers"][0]["byteLength"].get<std::size_t>() + 4; }},
      {"byteStride", [](json& d) { d["bufferViews"][0]["byteStride"] = 6; }},
      {"rotation",
       [](json& d) {
         d["nodes"].back()["rotation"] = {0, 0, 0, 2};
       }},
      {"twice", [](json& d) { d["scenes"][0]["nodes"].push_back(0); }},
      {"/indices",
       [](json& d) {
         d["accessors"][d["meshes"][0]["primitives"][0]["indices"].get<std::size_t>()]["componentType"] = 5126;
       }},
  };
  for (const auto& [mentions, change] : breaches) {
    const std::vector<std::string> found = breached(change);
    EXPECT_TRUE(std::any_of(found.begin(), found.end(),
                            [&](const std::string& p) { return p.find(mentions) != std::string::npos; }))
        << mentions << ":" << joined(found);
  }
}

}  // namespace
}  // namespace bounce::scene
