// Tests of src/scene/gltf_export: scenes written as .gltf and .glb and read
// back by the project's importer come back the same (meshes, materials with
// an edit, textures texel for texel, transforms, animation, lights, the sun
// and the suggested view), and the export refuses to overwrite the scene's
// own files and names the file when it cannot write.
#include "scene/gltf_export.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <fstream>
#include <functional>
#include <string>

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

}  // namespace
}  // namespace bounce::scene
