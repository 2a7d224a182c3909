// Tests of src/scene/gltf_import and src/scene/tangents: small glTF files
// written here (each checks one feature against numbers worked out by hand),
// Debian's malformed assimp test models, and the real scenes when present.
#include "scene/gltf_import.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <stb/stb_image_write.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "gltf_builder.h"
#include "scene/camera_path.h"
#include "scene/tangents.h"

namespace bounce::scene {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace bounce::testing::gltf;

// ------------------------------------------------------------------ helpers

// A fresh folder for one test's files, removed afterwards.
class TempFolder {
 public:
  TempFolder() {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("bounce_gltf_" + std::to_string(::getpid()) + "_" + test->test_suite_name() + "_" + test->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

struct Loaded {
  Scene scene;
  std::vector<std::string> warnings;
};

Loaded load(const fs::path& path, GltfImportOptions options = {}) {
  Loaded loaded;
  options.warn = [&](const std::string& line) { loaded.warnings.push_back(line); };
  loaded.scene = loadGltf(path, options);
  return loaded;
}

// The SceneError message of loading `path` (which must fail).
std::string loadError(const fs::path& path, const GltfImportOptions& options = {}) {
  try {
    load(path, options);
  } catch (const SceneError& error) {
    return error.what();
  }
  ADD_FAILURE() << path << " loaded, but should have been refused";
  return {};
}

void expectRefused(const fs::path& path, const std::string& reason, const GltfImportOptions& options = {}) {
  const std::string message = loadError(path, options);
  EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(reason), std::string::npos) << "expected '" << reason << "' in: " << message;
}

void expectNear(const glm::vec3& actual, const glm::vec3& expected, float tolerance = 1e-5f) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

// Everything the renderer relies on beyond validate(): unit normals, unit
// tangents perpendicular to them with w = +-1.
void expectWellFormed(const Scene& scene) {
  for (const Mesh& mesh : scene.meshes)
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      ASSERT_NEAR(glm::length(mesh.normals[v]), 1.0f, 1e-4f) << mesh.name << " vertex " << v;
      ASSERT_NEAR(glm::length(glm::vec3(mesh.tangents[v])), 1.0f, 1e-4f) << mesh.name << " vertex " << v;
      ASSERT_NEAR(glm::dot(mesh.normals[v], glm::vec3(mesh.tangents[v])), 0.0f, 1e-4f) << mesh.name << " vertex " << v;
      ASSERT_EQ(std::abs(mesh.tangents[v].w), 1.0f) << mesh.name << " vertex " << v;
    }
}

glm::vec3 worldPoint(const Instance& instance, const glm::vec3& local) {
  return glm::vec3(instance.objectToWorld * glm::vec4(local, 1.0f));
}

// ------------------------------------------------------------------ hierarchy and transforms

TEST(GltfImport, MatrixAndTrsNodesComposeParentFirst) {
  TempFolder folder;
  GltfBuilder gltf;
  // Parent: translate (1,2,3) * rotate 90 degrees about +Y * scale 2, as a matrix (column-major).
  const int parent = gltf.add("nodes", {{"matrix", {0, 0, -2, 0, 0, 2, 0, 0, 2, 0, 0, 0, 1, 2, 3, 1}}});
  const int child = gltf.addMeshNode(quadPrimitive(gltf), {{"translation", {0, 0, 1}}});
  gltf.doc()["nodes"][parent]["children"] = {child};
  gltf.doc()["scenes"] = {{{"nodes", {parent}}}};
  const Loaded loaded = load(gltf.writeGltf(folder / "hierarchy.gltf"));
  const Scene& scene = loaded.scene;

  EXPECT_TRUE(loaded.warnings.empty());
  ASSERT_EQ(scene.nodes.size(), 2u);
  EXPECT_EQ(scene.roots, std::vector<int>{parent});
  EXPECT_EQ(scene.nodes[std::size_t(child)].parent, parent);
  const Transform& decomposed = scene.nodes[std::size_t(parent)].local;
  expectNear(decomposed.translation, {1, 2, 3});
  expectNear(decomposed.scale, {2, 2, 2});
  expectNear(decomposed.rotation * glm::vec3(1, 0, 0), {0, 0, -1});
  // Quad corner (1,0,0): child (1,0,1) -> scaled (2,0,2) -> rotated (2,0,-2) -> translated (3,2,1).
  const std::vector<Instance> instances = instancesAt(scene, 0.0f);
  ASSERT_EQ(instances.size(), 1u);
  expectNear(worldPoint(instances[0], {1, 0, 0}), {3, 2, 1});
}

TEST(GltfImport, MirroringAndFlattenedMatricesDecomposeExactly) {
  TempFolder folder;
  GltfBuilder gltf;
  const glm::mat4 mirrored = glm::translate(glm::mat4(1.0f), {4, 5, 6}) *
                             glm::rotate(glm::mat4(1.0f), 0.7f, glm::normalize(glm::vec3(1, 2, 3))) *
                             glm::scale(glm::mat4(1.0f), {-1.5f, 0.5f, 2.0f});
  const glm::mat4 flattened =
      glm::rotate(glm::mat4(1.0f), 1.1f, glm::vec3(0, 0, 1)) * glm::scale(glm::mat4(1.0f), {3.0f, 0.0f, 1.0f});
  for (const glm::mat4& matrix : {mirrored, flattened})
    gltf.add("nodes", {{"matrix", std::vector<float>(glm::value_ptr(matrix), glm::value_ptr(matrix) + 16)}});
  const Loaded loaded = load(gltf.writeGltf(folder / "matrices.gltf"));

  EXPECT_TRUE(loaded.warnings.empty());
  const glm::mat4 expected[] = {mirrored, flattened};
  for (int n = 0; n < 2; ++n) {
    const glm::mat4 rebuilt = loaded.scene.nodes[std::size_t(n)].local.matrix();
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(rebuilt[c][r], expected[n][c][r], 1e-5f) << "node " << n;
  }
  EXPECT_LT(
      loaded.scene.nodes[0].local.scale.x * loaded.scene.nodes[0].local.scale.y * loaded.scene.nodes[0].local.scale.z,
      0.0f);
}

TEST(GltfImport, DisplaysTheDefaultSceneOrEveryParentlessNode) {
  TempFolder folder;
  GltfBuilder gltf;
  for (int n = 0; n < 3; ++n) gltf.add("nodes", json::object());
  gltf.doc()["nodes"][0]["children"] = {1};
  const fs::path noScenes = gltf.writeGltf(folder / "no_scenes.gltf");
  EXPECT_EQ(load(noScenes).scene.roots, (std::vector<int>{0, 2}));

  gltf.doc()["scenes"] = {{{"nodes", {0}}}, {{"nodes", {2}}}};
  EXPECT_EQ(load(gltf.writeGltf(folder / "scene0.gltf")).scene.roots, std::vector<int>{0});
  gltf.doc()["scene"] = 1;
  EXPECT_EQ(load(gltf.writeGltf(folder / "scene1.gltf")).scene.roots, std::vector<int>{2});
  gltf.doc()["scene"] = 2;
  expectRefused(gltf.writeGltf(folder / "scene2.gltf"), "default scene 2 does not exist");
}

// ------------------------------------------------------------------ geometry

TEST(GltfImport, ReadsEveryIndexWidthAndNonIndexedPrimitives) {
  TempFolder folder;
  GltfBuilder gltf;
  const int positions = gltf.floats(kQuadPositions, "VEC3");
  const int normals = gltf.floats(kQuadNormals, "VEC3");
  const json attributes = {{"POSITION", positions}, {"NORMAL", normals}};
  const int u8 =
      gltf.addAccessor(std::vector<std::uint8_t>(kQuadIndices.begin(), kQuadIndices.end()), kUnsignedByte, "SCALAR");
  const int u16 =
      gltf.addAccessor(std::vector<std::uint16_t>(kQuadIndices.begin(), kQuadIndices.end()), kUnsignedShort, "SCALAR");
  const int u32 = gltf.addAccessor(kQuadIndices, kUnsignedInt, "SCALAR");
  const std::vector<float> soup = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0};
  gltf.add("meshes", {{"primitives",
                       {{{"attributes", attributes}, {"indices", u8}},
                        {{"attributes", attributes}, {"indices", u16}},
                        {{"attributes", attributes}, {"indices", u32}},
                        {{"attributes", {{"POSITION", gltf.floats(soup, "VEC3")}}}}}}});
  gltf.add("nodes", {{"mesh", 0}});
  const Scene scene = load(gltf.writeGltf(folder / "indices.gltf")).scene;

  ASSERT_EQ(scene.meshes.size(), 4u);
  for (int m = 0; m < 3; ++m) {
    EXPECT_EQ(scene.meshes[std::size_t(m)].indices, kQuadIndices) << "primitive " << m;
    expectNear(scene.meshes[std::size_t(m)].positions[2], {1, 1, 0});
  }
  const Mesh& nonIndexed = scene.meshes[3];
  ASSERT_EQ(nonIndexed.indices.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i)
    expectNear(nonIndexed.positions[nonIndexed.indices[i]], {soup[i * 3], soup[i * 3 + 1], soup[i * 3 + 2]});
  EXPECT_EQ(scene.nodes[0].meshes, (std::vector<int>{0, 1, 2, 3}));
  expectWellFormed(scene);
}

TEST(GltfImport, MissingNormalsBecomeFlatNormalsOfEachTriangle) {
  TempFolder folder;
  GltfBuilder gltf;
  // A quad folded along its diagonal: triangle 0 lies in z = 0, triangle 1 rises to z = 1.
  const std::vector<float> folded = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 1};
  gltf.addMeshNode({{"attributes", {{"POSITION", gltf.floats(folded, "VEC3")}}},
                    {"indices", gltf.addAccessor(kQuadIndices, kUnsignedInt, "SCALAR")}});
  const Scene scene = load(gltf.writeGltf(folder / "flat.gltf")).scene;

  const Mesh& mesh = scene.meshes.at(0);
  ASSERT_EQ(mesh.positions.size(), 6u);  // un-indexed: no vertex is shared between the two faces
  EXPECT_EQ(mesh.indices, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5}));
  for (int v = 0; v < 3; ++v) expectNear(mesh.normals[std::size_t(v)], {0, 0, 1});
  // (1,1,0) x (0,1,1) = (1,-1,1).
  for (int v = 3; v < 6; ++v) expectNear(mesh.normals[std::size_t(v)], glm::vec3(1, -1, 1) / std::sqrt(3.0f));
  expectNear(mesh.positions[5], {0, 1, 1});
  expectWellFormed(scene);
}

// Quad facing +Z with glTF texcoords (v = 0 at the top of the image). In the
// plain layout u runs along +X; mirrored, u runs along -X. Either way the
// image's up direction is +Y, which is where the bitangent must point.
TEST(GltfImport, GeneratedTangentsFollowUvsWithCorrectHandedness) {
  TempFolder folder;
  GltfBuilder gltf;
  const std::vector<float> plainUvs = {0, 1, 1, 1, 1, 0, 0, 0};
  const std::vector<float> mirroredUvs = {1, 1, 0, 1, 0, 0, 1, 0};
  for (const auto* uvs : {&plainUvs, &mirroredUvs}) {
    json primitive = quadPrimitive(gltf);
    primitive["attributes"]["TEXCOORD_0"] = gltf.floats(*uvs, "VEC2");
    gltf.addMeshNode(primitive);
  }
  const Scene scene = load(gltf.writeGltf(folder / "tangents.gltf")).scene;

  ASSERT_EQ(scene.meshes.size(), 2u);
  const glm::vec3 expectedTangent[] = {{1, 0, 0}, {-1, 0, 0}};
  const float expectedSign[] = {1.0f, -1.0f};
  for (int m = 0; m < 2; ++m) {
    const Mesh& mesh = scene.meshes[std::size_t(m)];
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      expectNear(glm::vec3(mesh.tangents[v]), expectedTangent[m]);
      EXPECT_EQ(mesh.tangents[v].w, expectedSign[m]);
      expectNear(glm::cross(mesh.normals[v], glm::vec3(mesh.tangents[v])) * mesh.tangents[v].w, {0, 1, 0});
    }
  }
  expectWellFormed(scene);
}

TEST(GltfImport, TrianglesStripsAndFansBecomeListsWithTheSameWinding) {
  TempFolder folder;
  GltfBuilder gltf;
  // Strip: four vertices zig-zagging bottom/top; fan: centre plus four rim vertices.
  const std::vector<float> strip = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const std::vector<float> fan = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 1, 0};
  gltf.addMeshNode({{"attributes", {{"POSITION", gltf.floats(strip, "VEC3")}}}, {"mode", 5}});
  gltf.addMeshNode({{"attributes", {{"POSITION", gltf.floats(fan, "VEC3")}}}, {"mode", 6}});
  gltf.addMeshNode({{"attributes", {{"POSITION", gltf.floats(strip, "VEC3")}}}, {"mode", 1}});
  const Loaded loaded = load(gltf.writeGltf(folder / "topology.gltf"));
  const Scene& scene = loaded.scene;

  ASSERT_EQ(scene.meshes.size(), 2u);  // the LINES primitive is skipped
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("line"), std::string::npos) << loaded.warnings[0];
  EXPECT_NE(loaded.warnings[0].find("mesh 2"), std::string::npos) << loaded.warnings[0];
  // The spec's order: strip triangle i = {i, i+1+i%2, i+2-i%2}; fan triangle i = {i+1, i+2, 0}.
  EXPECT_EQ(scene.meshes[0].indices.size(), 6u);
  EXPECT_EQ(scene.meshes[1].indices.size(), 9u);
  for (const Mesh& mesh : scene.meshes)
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
      const glm::vec3& a = mesh.positions[mesh.indices[t]];
      const glm::vec3 normal =
          glm::cross(mesh.positions[mesh.indices[t + 1]] - a, mesh.positions[mesh.indices[t + 2]] - a);
      EXPECT_GT(normal.z, 0.0f) << mesh.name << " triangle " << t / 3 << " is wound clockwise";
    }
}

TEST(GltfImport, NormalizedIntegerTexcoordsMapToZeroOne) {
  TempFolder folder;
  GltfBuilder gltf;
  json withBytes = quadPrimitive(gltf);
  withBytes["attributes"]["TEXCOORD_0"] =
      gltf.addAccessor(std::vector<std::uint8_t>{0, 255, 255, 255, 255, 0, 51, 0}, kUnsignedByte, "VEC2", true);
  gltf.addMeshNode(withBytes);
  json withShorts = quadPrimitive(gltf);
  withShorts["attributes"]["TEXCOORD_0"] = gltf.addAccessor(
      std::vector<std::uint16_t>{0, 65535, 65535, 65535, 65535, 0, 13107, 0}, kUnsignedShort, "VEC2", true);
  gltf.addMeshNode(withShorts);
  const Scene scene = load(gltf.writeGltf(folder / "texcoords.gltf")).scene;

  for (const Mesh& mesh : scene.meshes) {
    EXPECT_EQ(mesh.texcoords[1], glm::vec2(1.0f, 1.0f));
    EXPECT_NEAR(mesh.texcoords[3].x, 0.2f, 1e-6f);
    expectNear(glm::vec3(mesh.tangents[0]), {1, 0, 0});
  }
}

TEST(GltfImport, SparseAccessorsReplaceTheListedElements) {
  TempFolder folder;
  GltfBuilder gltf;
  json primitive = quadPrimitive(gltf);
  const std::vector<std::uint16_t> which = {1, 3};
  const std::vector<float> values = {2, 0, 0, 0, 2, 0};
  json& positions = gltf.doc()["accessors"][primitive["attributes"]["POSITION"].get<int>()];
  positions["sparse"] = {
      {"count", 2},
      {"indices", {{"bufferView", gltf.addBufferView(which.data(), 4)}, {"componentType", kUnsignedShort}}},
      {"values", {{"bufferView", gltf.addBufferView(values.data(), 24)}}}};
  gltf.addMeshNode(primitive);
  const Scene scene = load(gltf.writeGltf(folder / "sparse.gltf")).scene;

  const Mesh& mesh = scene.meshes.at(0);
  expectNear(mesh.positions[0], {0, 0, 0});
  expectNear(mesh.positions[1], {2, 0, 0});
  expectNear(mesh.positions[2], {1, 1, 0});
  expectNear(mesh.positions[3], {0, 2, 0});

  const std::vector<std::uint16_t> outOfRange = {1, 4};
  const json valid = positions["sparse"];
  positions["sparse"]["indices"]["bufferView"] = gltf.addBufferView(outOfRange.data(), 4);
  expectRefused(gltf.writeGltf(folder / "sparse_bad.gltf"), "sparse index 4");

  // tinygltf keeps these in an int: larger ones were wrapped to negative
  // numbers in messages, or cut to a wrong offset that then loaded.
  struct TooLarge {
    const char* pointer;
    std::uint64_t value;
    const char* message;
  };
  for (const TooLarge& c : {TooLarge{"/count", 3000000000u, "accessors[0].sparse.count is 3000000000, over 2147483647"},
                            {"/indices/byteOffset", 4294967296u, "sparse.indices.byteOffset is 4294967296, over"},
                            {"/values/byteOffset", 2147483648u, "sparse.values.byteOffset is 2147483648, over"}}) {
    positions["sparse"] = valid;
    positions["sparse"][json::json_pointer(c.pointer)] = c.value;
    expectRefused(gltf.writeGltf(folder / "sparse_huge.gltf"), c.message);
  }
}

// ------------------------------------------------------------------ materials and textures

TEST(GltfImport, MaterialsKeepFactorsAlphaAndTextureColourSpaces) {
  TempFolder folder;
  // 2x1 image: red, then half-transparent green. The same file serves as
  // base colour and emissive (sRGB) and as metallic-roughness (linear).
  const std::vector<std::uint8_t> pixels = {255, 0, 0, 255, 0, 255, 0, 128};
  const std::vector<std::uint8_t> png = encodePng(2, 1, pixels);
  writeBytes(folder / "colour map.png", png.data(), png.size());
  GltfBuilder gltf;
  gltf.add("images", {{"uri", "colour%20map.png"}});
  gltf.add("textures", {{"source", 0}});
  gltf.add("materials", {{"name", "masked"},
                         {"pbrMetallicRoughness",
                          {{"baseColorFactor", {0.5, 0.25, 1.0, 0.75}},
                           {"baseColorTexture", {{"index", 0}}},
                           {"metallicFactor", 0.2},
                           {"roughnessFactor", 0.7},
                           {"metallicRoughnessTexture", {{"index", 0}}}}},
                         {"emissiveTexture", {{"index", 0}}},
                         {"emissiveFactor", {1.0, 0.5, 0.0}},
                         {"normalTexture", {{"index", 0}, {"scale", 0.5}}},
                         {"occlusionTexture", {{"index", 0}, {"strength", 0.25}}},
                         {"alphaMode", "MASK"},
                         {"alphaCutoff", 0.3},
                         {"doubleSided", true},
                         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 40.0}}}}}});
  gltf.add("materials", {{"alphaMode", "BLEND"}});
  gltf.doc()["extensionsUsed"] = {"KHR_materials_emissive_strength"};
  json textured = quadPrimitive(gltf);
  textured["material"] = 0;
  gltf.addMeshNode(textured);
  json blended = quadPrimitive(gltf);
  blended["material"] = 1;
  gltf.addMeshNode(blended);
  gltf.addMeshNode(quadPrimitive(gltf));  // no material: gets the default one
  const Loaded loaded = load(gltf.writeGltf(folder / "materials.gltf"));
  const Scene& scene = loaded.scene;

  EXPECT_TRUE(loaded.warnings.empty());
  ASSERT_EQ(scene.materials.size(), 3u);
  const Material& masked = scene.materials[0];
  EXPECT_EQ(masked.name, "masked");
  EXPECT_EQ(masked.baseColorFactor, glm::vec4(0.5f, 0.25f, 1.0f, 0.75f));
  EXPECT_FLOAT_EQ(masked.metallicFactor, 0.2f);
  EXPECT_FLOAT_EQ(masked.roughnessFactor, 0.7f);
  EXPECT_EQ(masked.emissiveFactor, glm::vec3(1.0f, 0.5f, 0.0f));
  EXPECT_FLOAT_EQ(masked.emissiveStrength, 40.0f);
  EXPECT_FLOAT_EQ(masked.normalScale, 0.5f);
  EXPECT_FLOAT_EQ(masked.occlusionStrength, 0.25f);
  EXPECT_EQ(masked.alphaMode, AlphaMode::Mask);
  EXPECT_FLOAT_EQ(masked.alphaCutoff, 0.3f);
  EXPECT_TRUE(masked.doubleSided);
  EXPECT_EQ(scene.materials[1].alphaMode, AlphaMode::Blend);
  EXPECT_FALSE(scene.materials[1].doubleSided);
  EXPECT_EQ(scene.materials[2].name, "default");
  EXPECT_EQ(scene.meshes[2].material, 2);

  // One texture per colour space of the one image.
  ASSERT_EQ(scene.textures.size(), 2u);
  EXPECT_EQ(masked.emissiveTexture, masked.baseColorTexture);
  EXPECT_EQ(masked.normalTexture, masked.metallicRoughnessTexture);
  EXPECT_EQ(masked.occlusionTexture, masked.metallicRoughnessTexture);
  EXPECT_NE(masked.baseColorTexture, masked.metallicRoughnessTexture);
  const Texture& srgb = scene.textures[std::size_t(masked.baseColorTexture)];
  const Texture& linear = scene.textures[std::size_t(masked.metallicRoughnessTexture)];
  EXPECT_TRUE(srgb.srgb);
  EXPECT_FALSE(linear.srgb);
  for (const Texture* texture : {&srgb, &linear}) {
    EXPECT_EQ(texture->name, "colour map.png");
    EXPECT_EQ(texture->width, 2);
    EXPECT_EQ(texture->height, 1);
    EXPECT_EQ(texture->rgba8, pixels);
  }
}

TEST(GltfImport, UsesTheCoreSourceOfDdsTexturesAndDecodesOnlyUsedImages) {
  TempFolder folder;
  const std::vector<std::uint8_t> pixels = {10, 20, 30, 255};
  const std::vector<std::uint8_t> png = encodePng(1, 1, pixels);
  GltfBuilder gltf;
  gltf.add("images", {{"uri", "data:image/png;base64," + base64(png)}});
  gltf.add("images", {{"uri", "never_written.dds"}});
  gltf.add("images", {{"uri", "also_missing_but_unused.png"}});
  gltf.add("textures", {{"source", 0}, {"extensions", {{"MSFT_texture_dds", {{"source", 1}}}}}});
  gltf.add("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  gltf.doc()["extensionsUsed"] = {"MSFT_texture_dds"};
  json primitive = quadPrimitive(gltf);
  primitive["material"] = 0;
  gltf.addMeshNode(primitive);
  const Loaded loaded = load(gltf.writeGltf(folder / "dds.gltf"));

  ASSERT_EQ(loaded.scene.textures.size(), 1u);
  EXPECT_EQ(loaded.scene.textures[0].rgba8, pixels);
  EXPECT_EQ(loaded.scene.textures[0].name, "image 0 of dds.gltf");
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("MSFT_texture_dds"), std::string::npos);
}

TEST(GltfImport, RefusesMissingAndUndecodableTextureFiles) {
  TempFolder folder;
  GltfBuilder gltf;
  gltf.add("images", {{"uri", "bricks_missing.png"}});
  gltf.add("textures", {{"source", 0}});
  gltf.add("materials", {{"normalTexture", {{"index", 0}}}});
  json primitive = quadPrimitive(gltf);
  primitive["material"] = 0;
  gltf.addMeshNode(primitive);
  expectRefused(gltf.writeGltf(folder / "missing_texture.gltf"), "bricks_missing.png");

  writeText(folder / "bricks_missing.png", "this is not a PNG file at all");
  expectRefused(gltf.writeGltf(folder / "bad_texture.gltf"), "'bricks_missing.png' is not a PNG or JPEG");
}

// One PNG named by URIs that resolve to the same file ("t.png", "./t.png",
// "t%2Epng") is one texture, decoded and held once (issue 46, M3: three
// names of a 16384 x 16384 PNG were decoded three times, 4.2 GB), and so are
// the same bytes under another name; other bytes are another texture, and
// an image used as sRGB and as linear data is two (converted differently).
TEST(GltfImport, AnImageUnderSeveralUrisOrNamesIsOneTexture) {
  TempFolder folder;
  const std::vector<std::uint8_t> pixels = {10, 20, 30, 255, 40, 50, 60, 255};
  const std::vector<std::uint8_t> otherPixels = {90, 80, 70, 255, 60, 50, 40, 255};
  writeBytes(folder / "t.png", encodePng(2, 1, pixels).data(), encodePng(2, 1, pixels).size());
  writeBytes(folder / "copy.png", encodePng(2, 1, pixels).data(), encodePng(2, 1, pixels).size());
  writeBytes(folder / "other.png", encodePng(2, 1, otherPixels).data(), encodePng(2, 1, otherPixels).size());
  GltfBuilder gltf;
  const std::vector<std::string> uris = {"t.png", "./t.png", "t%2Epng", "copy.png", "other.png"};
  for (std::size_t i = 0; i < uris.size(); ++i) {
    gltf.add("images", {{"uri", uris[i]}});
    gltf.add("textures", {{"source", i}});
    gltf.add("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", i}}}}}});
  }
  gltf.add("materials", {{"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 1}}}}}});
  json primitive = quadPrimitive(gltf);
  primitive["material"] = 0;
  gltf.addMeshNode(primitive);
  const Loaded loaded = load(gltf.writeGltf(folder / "shared.gltf"));
  const Scene& scene = loaded.scene;

  ASSERT_EQ(scene.textures.size(), 3u) << "t.png as sRGB and as linear data, other.png";
  const int shared = scene.materials[0].baseColorTexture;
  for (std::size_t i = 1; i < 4; ++i) EXPECT_EQ(scene.materials[i].baseColorTexture, shared) << uris[i];
  EXPECT_NE(scene.materials[4].baseColorTexture, shared);
  EXPECT_NE(scene.materials[5].metallicRoughnessTexture, shared);
  EXPECT_EQ(scene.textures[std::size_t(shared)].name, "t.png");
  EXPECT_EQ(scene.textures[std::size_t(shared)].rgba8, pixels);
  EXPECT_EQ(scene.textures[std::size_t(scene.materials[4].baseColorTexture)].rgba8, otherPixels);
  EXPECT_EQ(scene.textures[std::size_t(scene.materials[5].metallicRoughnessTexture)].rgba8, pixels);
  EXPECT_FALSE(scene.textures[std::size_t(scene.materials[5].metallicRoughnessTexture)].srgb);
}

// A texture of 20000 x 20000 pixels is refused from its header, naming both
// sizes (it used to be called truncated or corrupt).
TEST(GltfImport, TexturesOverTheSizeLimitAreRefusedWithBothSizes) {
  TempFolder folder;
  // Signature and an IHDR chunk (CRCs left 0) are all the header there is.
  std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
  for (const std::uint32_t side : {20000u, 20000u})
    for (int shift = 24; shift >= 0; shift -= 8) png.push_back(std::uint8_t(side >> shift));
  png.insert(png.end(), {8, 6, 0, 0, 0, 0, 0, 0, 0});
  GltfBuilder gltf;
  gltf.add("images", {{"uri", "data:image/png;base64," + base64(png)}});
  gltf.add("textures", {{"source", 0}});
  gltf.add("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  json primitive = quadPrimitive(gltf);
  primitive["material"] = 0;
  gltf.addMeshNode(primitive);
  expectRefused(gltf.writeGltf(folder / "huge_texture.gltf"),
                "texture image 'image 0 of huge_texture.gltf': image size 20000x20000 is over the limit of 16384 "
                "pixels a side");
}

// ------------------------------------------------------------------ lights, cameras, animation

TEST(GltfImport, PunctualLightsShineDownTheirNodesMinusZ) {
  TempFolder folder;
  GltfBuilder gltf;
  gltf.doc()["extensionsUsed"] = {"KHR_lights_punctual"};
  gltf.doc()["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "directional"}, {"name", "sun"}, {"color", {1.0, 0.9, 0.8}}, {"intensity", 3.0}},
      {{"type", "point"}, {"intensity", 20.0}, {"range", 5.0}},
      {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.6}}}}};
  // Rotating -Z by -90 degrees about +X points it straight down.
  const float s = std::sqrt(0.5f);
  for (int light = 0; light < 3; ++light)
    gltf.add("nodes", {{"rotation", {-s, 0, 0, s}},
                       {"translation", {0, 3, 0}},
                       {"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}});
  const Loaded loaded = load(gltf.writeGltf(folder / "lights.gltf"));
  const Scene& scene = loaded.scene;

  EXPECT_TRUE(loaded.warnings.empty());
  ASSERT_EQ(scene.lights.size(), 3u);
  EXPECT_EQ(scene.lights[0].type, LightType::Directional);
  EXPECT_EQ(scene.lights[0].name, "sun");
  EXPECT_EQ(scene.lights[0].color, glm::vec3(1.0f, 0.9f, 0.8f));
  EXPECT_FLOAT_EQ(scene.lights[0].intensity, 3.0f);
  EXPECT_EQ(scene.lights[1].type, LightType::Point);
  EXPECT_FLOAT_EQ(scene.lights[1].range, 5.0f);
  EXPECT_EQ(scene.lights[2].type, LightType::Spot);
  EXPECT_FLOAT_EQ(scene.lights[2].innerConeAngle, 0.2f);
  EXPECT_FLOAT_EQ(scene.lights[2].outerConeAngle, 0.6f);
  const std::vector<glm::mat4> world = nodeWorldMatrices(scene, 0.0f);
  for (int n = 0; n < 3; ++n) {
    EXPECT_EQ(scene.nodes[std::size_t(n)].light, n);
    expectNear(glm::vec3(world[std::size_t(n)] * glm::vec4(0, 0, -1, 0)), {0, -1, 0});
  }

  gltf.doc()["extensions"]["KHR_lights_punctual"]["lights"][2]["spot"]["innerConeAngle"] = 0.7;
  expectRefused(gltf.writeGltf(folder / "bad_spot.gltf"), "cone angles");
}

// glTF: a range, when given, is above 0. tinygltf keeps an absent range as
// 0 too, and 0 was taken for "no limit" without a word; the file's 0 (or a
// negative range) is refused, naming the light.
TEST(GltfImport, LightRangeZeroIsRefusedNamingTheLight) {
  TempFolder folder;
  GltfBuilder gltf;
  gltf.doc()["extensionsUsed"] = {"KHR_lights_punctual"};
  gltf.doc()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"name", "lamp"}, {"range", 0}}};
  gltf.add("nodes", {{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  expectRefused(gltf.writeGltf(folder / "zero.gltf"), "light 0 'lamp': range 0 must be above 0");
  gltf.doc()["extensions"]["KHR_lights_punctual"]["lights"][0]["range"] = -2.5;
  expectRefused(gltf.writeGltf(folder / "negative.gltf"), "light 0 'lamp': range -2.5 must be above 0");
  gltf.doc()["extensions"]["KHR_lights_punctual"]["lights"][0].erase("range");
  EXPECT_EQ(load(gltf.writeGltf(folder / "none.gltf")).scene.lights.at(0).range, 0.0f);  // none: no limit
}

// Material factors outside glTF's [0, 1] (which --material refuses) are
// clamped into it, and each field is named in a warning with the materials
// it concerns: emission of 2 was rendered twice as bright, and a base
// colour of 5 clamped, without a word. Ten thousand such materials still
// give one line a field.
TEST(GltfImport, FactorsOutsideZeroToOneAreClampedWithAWarningPerField) {
  TempFolder folder;
  GltfBuilder gltf;
  gltf.add("materials", {{"name", "bright"},
                         {"pbrMetallicRoughness", {{"baseColorFactor", {5, 5, 5, 1}}, {"metallicFactor", 2}}},
                         {"emissiveFactor", {2, 1, 1}}});
  gltf.add("materials", {{"name", "negative"},
                         {"pbrMetallicRoughness", {{"baseColorFactor", {-1, 0.5, 0.5, 1}}, {"roughnessFactor", -0.5}}},
                         {"emissiveFactor", {-1, 0, 0}},
                         {"occlusionTexture", {{"index", 0}, {"strength", 1.5}}}});
  gltf.add("materials", {{"name", "fine"},
                         {"pbrMetallicRoughness", {{"baseColorFactor", {0, 1, 0.5, 1}}, {"roughnessFactor", 1}}},
                         {"emissiveFactor", {1, 0, 0}}});
  const std::vector<std::uint8_t> png = encodePng(1, 1, {10, 20, 30, 255});
  gltf.add("images", {{"uri", "data:image/png;base64," + base64(png)}});
  gltf.add("textures", {{"source", 0}});
  for (int material = 0; material < 3; ++material) {
    json primitive = quadPrimitive(gltf);
    primitive["material"] = material;
    gltf.addMeshNode(primitive);
  }
  const fs::path path = gltf.writeGltf(folder / "factors.gltf");
  const Loaded loaded = load(path);

  const std::vector<std::string> expected = {
      "pbrMetallicRoughness.baseColorFactor outside [0, 1] was clamped into it: material 0 'bright', material 1 "
      "'negative'",
      "pbrMetallicRoughness.metallicFactor outside [0, 1] was clamped into it: material 0 'bright'",
      "emissiveFactor outside [0, 1] was clamped into it (KHR_materials_emissive_strength makes emission brighter): "
      "material 0 'bright', material 1 'negative'",
      "pbrMetallicRoughness.roughnessFactor outside [0, 1] was clamped into it: material 1 'negative'",
      "occlusionTexture.strength outside [0, 1] was clamped into it: material 1 'negative'"};
  std::vector<std::string> warnings = loaded.warnings;
  std::vector<std::string> lines;
  for (const std::string& warning : expected) lines.push_back(path.string() + ": " + warning);
  std::sort(warnings.begin(), warnings.end());
  std::sort(lines.begin(), lines.end());
  EXPECT_EQ(warnings, lines);
  const std::vector<Material>& materials = loaded.scene.materials;
  EXPECT_EQ(materials[0].baseColorFactor, glm::vec4(1.0f));
  EXPECT_EQ(materials[0].metallicFactor, 1.0f);
  EXPECT_EQ(materials[0].emissiveFactor, glm::vec3(1.0f));
  EXPECT_EQ(materials[1].baseColorFactor, glm::vec4(0.0f, 0.5f, 0.5f, 1.0f));
  EXPECT_EQ(materials[1].roughnessFactor, 0.0f);
  EXPECT_EQ(materials[1].emissiveFactor, glm::vec3(0.0f));
  EXPECT_EQ(materials[1].occlusionStrength, 1.0f);
  EXPECT_EQ(materials[2].baseColorFactor, glm::vec4(0.0f, 1.0f, 0.5f, 1.0f));
  EXPECT_EQ(materials[2].emissiveFactor, glm::vec3(1.0f, 0.0f, 0.0f));

  // Ten thousand: still one line a field, naming eight and counting the rest.
  GltfBuilder many;
  json primitive = quadPrimitive(many);
  for (int m = 0; m < 10000; ++m) many.add("materials", {{"emissiveFactor", {3, 0, 0}}});
  primitive["material"] = 9999;
  many.addMeshNode(primitive);
  const Loaded manyLoaded = load(many.writeGltf(folder / "many.gltf"));
  ASSERT_EQ(manyLoaded.warnings.size(), 1u);
  EXPECT_NE(manyLoaded.warnings[0].find("emissiveFactor outside [0, 1] was clamped into it"), std::string::npos);
  EXPECT_NE(manyLoaded.warnings[0].find("material 7 and 9992 more"), std::string::npos) << manyLoaded.warnings[0];
}

// Values of the wrong JSON type that tinygltf silently replaces by their
// defaults: each is named in a warning, and the rest is still read.
TEST(GltfImport, LightAndMaterialValuesThatFallBackToDefaultsAreNamed) {
  TempFolder folder;
  GltfBuilder gltf;
  gltf.doc()["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_emissive_strength"};
  gltf.doc()["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"name", "lamp"}, {"intensity", "bright"}, {"color", "red"}, {"range", "far"}},
      {{"type", "spot"}, {"spot", {{"innerConeAngle", "narrow"}, {"outerConeAngle", "wide"}}}}};
  for (int light = 0; light < 2; ++light)
    gltf.add("nodes", {{"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}});
  const std::vector<std::uint8_t> png = encodePng(1, 1, {10, 20, 30, 255});
  gltf.add("images", {{"uri", "data:image/png;base64," + base64(png)}});
  gltf.add("textures", {{"source", 0}});
  // Three numbers: tinygltf dropped the whole block, texture and metallic factor too.
  gltf.add("materials",
           {{"name", "rgb"},
            {"pbrMetallicRoughness",
             {{"baseColorFactor", {0.5, 0.5, 0.5}}, {"metallicFactor", 0.25}, {"baseColorTexture", {{"index", 0}}}}}});
  gltf.add("materials", {{"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", "strong"}}}}}});
  for (int material = 0; material < 2; ++material) {
    json primitive = quadPrimitive(gltf);
    primitive["material"] = material;
    gltf.addMeshNode(primitive);
  }
  const fs::path path = gltf.writeGltf(folder / "defaults.gltf");
  const Loaded loaded = load(path);

  const std::vector<std::string> expected = {
      "light color must be an array of 3 numbers; using (1, 1, 1): light 0 'lamp'",
      "light intensity must be a number; using 1: light 0 'lamp'",
      "light range must be a number; using none (the light reaches everywhere): light 0 'lamp'",
      "spot light innerConeAngle must be a number; using 0: light 1",
      "spot light outerConeAngle must be a number; using pi/4: light 1",
      "pbrMetallicRoughness.baseColorFactor must have 4 numbers; using (1, 1, 1, 1): material 0 'rgb'",
      "KHR_materials_emissive_strength emissiveStrength must be a number; using 1: material 1"};
  ASSERT_EQ(loaded.warnings.size(), expected.size());
  for (const std::string& warning : expected)
    EXPECT_NE(std::find(loaded.warnings.begin(), loaded.warnings.end(), path.string() + ": " + warning),
              loaded.warnings.end())
        << warning;
  const Scene& scene = loaded.scene;
  EXPECT_EQ(scene.lights[0].intensity, 1.0f);
  EXPECT_EQ(scene.lights[0].color, glm::vec3(1.0f));
  EXPECT_EQ(scene.materials[0].baseColorFactor, glm::vec4(1.0f));
  EXPECT_FLOAT_EQ(scene.materials[0].metallicFactor, 0.25f);
  ASSERT_GE(scene.materials[0].baseColorTexture, 0);
  EXPECT_EQ(scene.textures[std::size_t(scene.materials[0].baseColorTexture)].rgba8,
            (std::vector<std::uint8_t>{10, 20, 30, 255}));
  EXPECT_EQ(scene.materials[1].emissiveStrength, 1.0f);

  // Where no default exists, the light is refused by name.
  json& lights = gltf.doc()["extensions"]["KHR_lights_punctual"]["lights"];
  lights[0]["type"] = 5;
  expectRefused(gltf.writeGltf(folder / "typeless.gltf"), "light 0 'lamp': type must be a string");
  lights[0]["type"] = "spot";
  expectRefused(gltf.writeGltf(folder / "spotless.gltf"), "light 0 'lamp': a spot light needs a \"spot\" object");
  lights = "lamp";
  expectRefused(gltf.writeGltf(folder / "lightless.gltf"),
                "extensions.KHR_lights_punctual.lights must be an array of objects");
}

TEST(GltfImport, PerspectiveCamerasAreKeptOrthographicOnesSkipped) {
  TempFolder folder;
  GltfBuilder gltf;
  gltf.add("cameras", {{"type", "orthographic"},
                       {"name", "plan"},
                       {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}});
  gltf.add("cameras", {{"type", "perspective"}, {"name", "eye"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.02}}}});
  gltf.add("nodes", {{"camera", 0}});
  gltf.add("nodes", {{"camera", 1}, {"translation", {0, 1.7, 4}}});
  const Loaded loaded = load(gltf.writeGltf(folder / "cameras.gltf"));
  const Scene& scene = loaded.scene;

  ASSERT_EQ(scene.cameras.size(), 1u);
  EXPECT_EQ(scene.cameras[0].name, "eye");
  EXPECT_FLOAT_EQ(scene.cameras[0].yfov, 0.9f);
  EXPECT_FLOAT_EQ(scene.cameras[0].znear, 0.02f);
  EXPECT_EQ(scene.nodes[0].camera, -1);
  EXPECT_EQ(scene.nodes[1].camera, 0);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("orthographic"), std::string::npos);
  EXPECT_NE(loaded.warnings[0].find("plan"), std::string::npos);
}

// 100,000 nodes in one chain, each a step up from its parent, the quad and a
// camera at its end (validation used to take minutes on such a file).
TEST(GltfImport, AHundredThousandNodeChainLoadsWithItsLeafInPlace) {
  constexpr int kNodes = 100000;
  TempFolder folder;
  GltfBuilder gltf;
  gltf.add("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}});
  for (int i = 0; i + 1 < kNodes; ++i) gltf.add("nodes", {{"translation", {0, 1, 0}}, {"children", {i + 1}}});
  gltf.addMeshNode(quadPrimitive(gltf), {{"translation", {0, 1, 0}}, {"camera", 0}});
  gltf.doc()["scenes"] = {{{"nodes", {0}}}};
  const Scene scene = load(gltf.writeGltf(folder / "chain.gltf")).scene;

  ASSERT_EQ(scene.nodes.size(), std::size_t(kNodes));
  validate(scene);
  // Sums of whole numbers below 2^24 are exact in float.
  const std::vector<Instance> instances = instancesAt(scene, 0.0f);
  ASSERT_EQ(instances.size(), 1u);
  EXPECT_EQ(worldPoint(instances[0], {1, 1, 0}), glm::vec3(1, kNodes + 1, 0));
  EXPECT_EQ(makeCameraPath("gltf", scene)->pose(0.0f).position, glm::vec3(0, kNodes, 0));
}

// 100,000 nodes side by side, every one a root of the scene and every one
// warned about: neither the roots nor the warnings may be collected by
// searching what was collected before (that took 9 s on this file, growing
// with the square of its size).
TEST(GltfImport, AHundredThousandRootsAndWarningsLoadInLinearTime) {
  constexpr int kNodes = 100000;
  TempFolder folder;
  GltfBuilder gltf;
  json roots = json::array();
  for (int i = 0; i < kNodes; ++i) {
    gltf.add("nodes", {{"translation", {i, 0, 0}}, {"weights", {0.5}}});
    roots.push_back(i);
  }
  gltf.doc()["scenes"] = {{{"nodes", roots}}};
  const Loaded loaded = load(gltf.writeGltf(folder / "wide.gltf"));

  ASSERT_EQ(loaded.scene.roots.size(), std::size_t(kNodes));
  EXPECT_EQ(loaded.scene.roots.back(), kNodes - 1);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("morph targets are ignored: node 0, node 1,"), std::string::npos);
  EXPECT_NE(loaded.warnings[0].find("and " + std::to_string(kNodes - 8) + " more"), std::string::npos)
      << loaded.warnings[0];
}

// glTF's scene.nodes lists each root once: a node listed twice is refused,
// at its second listing, however long the list (a root listed 200,000
// times was displayed once, without a word).
TEST(GltfImport, ARootListedTwiceIsRefused) {
  TempFolder folder;
  GltfBuilder gltf;
  gltf.addMeshNode(quadPrimitive(gltf));
  gltf.add("nodes", {{"translation", {1, 0, 0}}});
  gltf.doc()["scenes"] = {{{"nodes", {0, 1, 0}}}};
  expectRefused(gltf.writeGltf(folder / "twice.gltf"), "scene 0: lists node 0 more than once");
  gltf.doc()["scenes"] = {{{"nodes", json(std::vector<int>(200000, 1))}}};
  expectRefused(gltf.writeGltf(folder / "many.gltf"), "scene 0: lists node 1 more than once");
}

// 3.14159265 is below pi, but as the float the camera keeps it is pi: 180
// degrees, which the renderer then refused with a message about everything.
TEST(GltfImport, CameraYfovIsCheckedAsTheFloatItBecomes) {
  TempFolder folder;
  GltfBuilder gltf;
  gltf.add("cameras", {{"type", "perspective"}, {"perspective", {{"yfov", 3.14159265}, {"znear", 0.1}}}});
  gltf.add("nodes", {{"camera", 0}});
  expectRefused(gltf.writeGltf(folder / "wide.gltf"),
                "camera 0: yfov 3.14159265 must be between 0 and pi (exclusive, as a 32-bit float)");
  gltf.doc()["cameras"][0]["perspective"]["yfov"] = 3.1415925;
  EXPECT_LT(load(gltf.writeGltf(folder / "almost.gltf")).scene.cameras.at(0).yfov, glm::pi<float>());
}

TEST(GltfImport, NodeAnimationsMoveInstancesOverTime) {
  TempFolder folder;
  GltfBuilder gltf;
  const int node = gltf.addMeshNode(quadPrimitive(gltf));
  const int times = gltf.floats({0, 2}, "SCALAR");
  const int translations = gltf.floats({0, 0, 0, 4, 0, 0}, "VEC3");
  // Rotation steps from identity to 90 degrees about +Z at t = 1.
  const float s = std::sqrt(0.5f);
  const int stepTimes = gltf.floats({0, 1}, "SCALAR");
  const int rotations = gltf.floats({0, 0, 0, 1, 0, 0, s, s}, "VEC4");
  // Cubic spline scale with zero tangents: (in, value, out) per key.
  const int scales = gltf.floats({0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0, 3, 3, 3, 0, 0, 0}, "VEC3");
  gltf.add("animations", {{"name", "move"},
                          {"samplers",
                           {{{"input", times}, {"output", translations}},
                            {{"input", stepTimes}, {"output", rotations}, {"interpolation", "STEP"}},
                            {{"input", times}, {"output", scales}, {"interpolation", "CUBICSPLINE"}},
                            {{"input", times}, {"output", gltf.floats({0, 1}, "SCALAR")}}}},
                          {"channels",
                           {{{"sampler", 0}, {"target", {{"node", node}, {"path", "translation"}}}},
                            {{"sampler", 1}, {"target", {{"node", node}, {"path", "rotation"}}}},
                            {{"sampler", 2}, {"target", {{"node", node}, {"path", "scale"}}}},
                            {{"sampler", 3}, {"target", {{"node", node}, {"path", "weights"}}}}}}});
  const Loaded loaded = load(gltf.writeGltf(folder / "animation.gltf"));
  const Scene& scene = loaded.scene;

  ASSERT_EQ(scene.animations.size(), 1u);
  ASSERT_EQ(scene.animations[0].channels.size(), 3u);  // the morph-weight channel is dropped
  EXPECT_EQ(scene.animations[0].channels[2].values.size(), 6u);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("weights"), std::string::npos) << loaded.warnings[0];
  // t = 0.5: translation 1/4 of the way to (4,0,0), rotation still identity,
  // scale by the Hermite basis (3t^2 - 2t^3 at t = 1/4: 5/32) from 1 to 3.
  const float scale = 1.0f + 2.0f * (5.0f / 32.0f);
  expectNear(worldPoint(instancesAt(scene, 0.5f).at(0), {1, 0, 0}), {1.0f + scale, 0, 0});
  // t = 1.5: translation (3,0,0), rotated by 90 degrees about +Z: (1,0,0) -> (0,1,0).
  const float laterScale = 1.0f + 2.0f * (27.0f / 32.0f);
  expectNear(worldPoint(instancesAt(scene, 1.5f).at(0), {1, 0, 0}), {3, laterScale, 0});
}

// ------------------------------------------------------------------ containers and extensions

TEST(GltfImport, GlbAndGltfWithBinFileGiveTheSameScene) {
  TempFolder folder;
  GltfBuilder gltf;
  json primitive = quadPrimitive(gltf);
  primitive["attributes"]["TEXCOORD_0"] = gltf.floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2");
  gltf.addMeshNode(primitive, {{"translation", {1, 2, 3}}});
  const Scene fromGlb = load(gltf.writeGlb(folder / "box.glb")).scene;
  const Scene fromBin = load(gltf.writeGltf(folder / "box.gltf", true)).scene;

  ASSERT_EQ(fromGlb.meshes.size(), 1u);
  ASSERT_EQ(fromBin.meshes.size(), 1u);
  EXPECT_EQ(fromGlb.meshes[0].positions, fromBin.meshes[0].positions);
  EXPECT_EQ(fromGlb.meshes[0].texcoords, fromBin.meshes[0].texcoords);
  EXPECT_EQ(fromGlb.meshes[0].indices, kQuadIndices);
  EXPECT_EQ(fromGlb.meshes[0].indices, fromBin.meshes[0].indices);
  expectNear(fromGlb.nodes[0].local.translation, {1, 2, 3});
  EXPECT_EQ(fromGlb.name, "box.glb");

  // The same GLB cut short, and with a BIN chunk header that claims too much.
  std::ifstream in(folder / "box.glb", std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  writeBytes(folder / "cut.glb", bytes.data(), bytes.size() - 16);
  expectRefused(folder / "cut.glb", "truncated GLB");
  std::uint32_t jsonLength;
  std::memcpy(&jsonLength, bytes.data() + 12, 4);
  const std::uint32_t hugeChunk = 1u << 30;
  std::memcpy(bytes.data() + 20 + jsonLength, &hugeChunk, 4);
  writeBytes(folder / "lying.glb", bytes.data(), bytes.size());
  expectRefused(folder / "lying.glb", "BIN chunk runs past the end");
}

TEST(GltfImport, UnsupportedOptionalExtensionsGiveOneWarningNamingThemAll) {
  TempFolder folder;
  GltfBuilder gltf;
  gltf.addMeshNode(quadPrimitive(gltf));
  gltf.doc()["extensionsUsed"] = {"EXT_made_up_one", "KHR_lights_punctual", "EXT_made_up_two"};
  const Loaded loaded = load(gltf.writeGltf(folder / "optional.gltf"));

  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("EXT_made_up_one"), std::string::npos) << loaded.warnings[0];
  EXPECT_NE(loaded.warnings[0].find("EXT_made_up_two"), std::string::npos) << loaded.warnings[0];
  EXPECT_EQ(loaded.warnings[0].find("KHR_lights_punctual"), std::string::npos) << loaded.warnings[0];
}

TEST(GltfImport, RefusesUnsupportedRequiredExtensions) {
  TempFolder folder;
  GltfBuilder gltf;
  gltf.addMeshNode(quadPrimitive(gltf));
  gltf.doc()["extensionsUsed"] = {"KHR_lights_punctual", "KHR_draco_mesh_compression"};
  gltf.doc()["extensionsRequired"] = {"KHR_lights_punctual", "KHR_draco_mesh_compression"};
  expectRefused(gltf.writeGltf(folder / "required.gltf"), "KHR_draco_mesh_compression");
}

// ------------------------------------------------------------------ where files may come from

TEST(GltfImport, BufferAndImageUrisMustStayInsideTheGltfFilesFolder) {
  TempFolder folder;
  const fs::path scene = folder / "scene";
  fs::create_directories(scene / "sub");
  GltfBuilder gltf;
  gltf.addMeshNode(quadPrimitive(gltf));
  gltf.writeGltf(scene / "quad.gltf", true);  // and scene/quad.bin
  fs::copy_file(scene / "quad.bin", folder / "outside.bin");
  std::ifstream in(scene / "quad.gltf");
  const json original = json::parse(in);
  // The quad with its buffer at `uri`, and optionally an image no material uses.
  const auto withUri = [&](const std::string& uri, const std::string& imageUri = "") {
    json doc = original;
    doc["buffers"][0]["uri"] = uri;
    if (!imageUri.empty()) doc["images"] = {{{"uri", imageUri}}};
    writeText(scene / "uri.gltf", doc.dump());
    return scene / "uri.gltf";
  };
  const std::string outside =
      "lies outside the glTF file's folder; files there are read only with "
      "--allow-outside-assets";

  // Inside the folder, however it is spelt, loads.
  fs::create_symlink("quad.bin", scene / "alias.bin");
  fs::create_symlink("..", scene / "sub" / "up");
  for (const char* uri : {"quad.bin", "./quad.bin", "sub/../quad.bin", "%71uad.bin", "alias.bin", "sub/up/quad.bin"})
    EXPECT_EQ(load(withUri(uri)).scene.meshes.size(), 1u) << uri;

  // Out of it, by any road, is refused, for images as for buffers.
  fs::create_symlink("../outside.bin", scene / "relative-link.bin");
  fs::create_symlink(folder / "outside.bin", scene / "absolute-link.bin");
  const std::vector<std::string> escapes = {"../outside.bin",
                                            "%2e%2e/outside.bin",
                                            "%2E%2E%2Foutside.bin",
                                            "sub/../../outside.bin",
                                            "sub/up/../outside.bin",
                                            (folder / "outside.bin").string(),
                                            (scene / "quad.bin").string(),  // absolute, even when inside
                                            "relative-link.bin",
                                            "absolute-link.bin"};
  for (const std::string& uri : escapes) {
    SCOPED_TRACE(uri);
    expectRefused(withUri(uri), outside);
    expectRefused(withUri("quad.bin", uri), outside);
  }
  expectRefused(withUri("%2e%2e/outside.bin"), "the buffer or image file '../outside.bin' " + outside);
  // A NUL would end the path early in the C library: refused, and shown as %00.
  expectRefused(withUri("quad.bin%00.png"),
                "the buffer or image file 'quad.bin%00.png' has a NUL byte (%00) in its URI");

  // Whether the outside file exists changes nothing in the message, which
  // holds none of its bytes.
  const std::string secret(120, 'S');
  writeText(folder / "secret.bin", secret);
  fs::create_symlink("../secret.bin", scene / "secret-link.bin");
  const std::vector<std::string> secretUris = {"../secret.bin", "secret-link.bin"};
  std::vector<std::string> whenPresent;
  for (const std::string& uri : secretUris) whenPresent.push_back(loadError(withUri(uri)));
  fs::remove(folder / "secret.bin");
  for (std::size_t i = 0; i < secretUris.size(); ++i) {
    EXPECT_EQ(loadError(withUri(secretUris[i])), whenPresent[i]);
    EXPECT_NE(whenPresent[i].find(outside), std::string::npos) << whenPresent[i];
    EXPECT_EQ(whenPresent[i].find("SSSS"), std::string::npos) << whenPresent[i];
  }

  // allowOutsideAssets reads them; a NUL stays refused.
  GltfImportOptions allowed;
  allowed.allowOutsideAssets = true;
  for (const std::string& uri : escapes) EXPECT_EQ(load(withUri(uri), allowed).scene.meshes.size(), 1u) << uri;
  expectRefused(withUri("quad.bin%00.png"), "has a NUL byte", allowed);
}

// ------------------------------------------------------------------ malformed data

// A glTF document `levels` containers deep in all (the document itself is
// the first): nested arrays in the root's extras, or nested objects in a
// node's extensions.
std::string nestedExtras(int levels) {
  const std::size_t arrays = std::size_t(levels - 1);
  return R"({"asset": {"version": "2.0"}, "extras": )" + std::string(arrays, '[') + std::string(arrays, ']') + "}";
}
std::string nestedNodeExtensions(int levels) {
  std::string objects;
  for (int level = 4; level <= levels; ++level) objects += R"({"a": )";
  objects += "0";
  for (int level = 4; level <= levels; ++level) objects += "}";
  return R"({"asset": {"version": "2.0"}, "nodes": [{"extensions": )" + objects + "}]}";
}

TEST(GltfImport, JsonNestedDeeperThan64LevelsIsRefusedWithoutRecursing) {
  TempFolder folder;
  // 15,000 levels in 30 KB overflowed the stack in tinygltf's recursive parser.
  writeText(folder / "deep.gltf", nestedExtras(15000));
  expectRefused(folder / "deep.gltf", "JSON nested deeper than 64 levels");
  writeGlbFile(folder / "deep.glb", nestedNodeExtensions(15000), {});
  expectRefused(folder / "deep.glb", "JSON nested deeper than 64 levels");

  // The limit is exact: 64 levels load, 65 do not.
  writeText(folder / "64.gltf", nestedExtras(64));
  EXPECT_NO_THROW(load(folder / "64.gltf"));
  writeGlbFile(folder / "64.glb", nestedNodeExtensions(64), {});
  EXPECT_EQ(load(folder / "64.glb").scene.nodes.size(), 1u);
  writeText(folder / "65.gltf", nestedExtras(65));
  expectRefused(folder / "65.gltf", "JSON nested deeper than 64 levels");
  writeGlbFile(folder / "65.glb", nestedNodeExtensions(65), {});
  expectRefused(folder / "65.glb", "JSON nested deeper than 64 levels");
}

TEST(GltfImport, RefusesNanAndInfinitePositions) {
  TempFolder folder;
  GltfBuilder gltf;
  std::vector<float> positions = kQuadPositions;
  positions[7] = std::numeric_limits<float>::quiet_NaN();
  gltf.addMeshNode({{"attributes", {{"POSITION", gltf.floats(positions, "VEC3")}}},
                    {"indices", gltf.addAccessor(kQuadIndices, kUnsignedInt, "SCALAR")}});
  expectRefused(gltf.writeGltf(folder / "nan.gltf"), "vertex 2 is NaN or infinite");
}

// Each case corrupts one property of a valid file; each must be refused with
// a message that says what is wrong.
TEST(GltfImport, RefusesBrokenAccessorsBufferViewsAndIndices) {
  struct Corruption {
    const char* name;
    std::function<void(json&)> apply;
    const char* reason;
  };
  // Accessors 0..2 are POSITION, NORMAL, indices; bufferViews likewise.
  const std::vector<Corruption> corruptions = {
      {"offset_past_view", [](json& d) { d["accessors"][0]["byteOffset"] = 8; }, "do not fit in bufferView"},
      {"count_past_view", [](json& d) { d["accessors"][2]["count"] = 7; }, "do not fit in bufferView"},
      {"view_past_buffer", [](json& d) { d["bufferViews"][1]["byteLength"] = 4000; },
       "runs past the end of its buffer"},
      {"missing_view", [](json& d) { d["accessors"][0]["bufferView"] = 17; }, "bufferView 17 does not exist"},
      {"missing_accessor", [](json& d) { d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 9; },
       "accessor 9 does not exist"},
      {"small_stride", [](json& d) { d["bufferViews"][0]["byteStride"] = 8; }, "byteStride 8 is invalid"},
      {"wrong_type", [](json& d) { d["accessors"][1]["type"] = "VEC2"; }, "is VEC2, expected VEC3"},
      {"wrong_component", [](json& d) { d["accessors"][0]["componentType"] = kUnsignedShort; }, "UNSIGNED_SHORT"},
      {"float_indices", [](json& d) { d["accessors"][2]["componentType"] = kFloat; }, "expected UNSIGNED_BYTE"},
      {"count_mismatch", [](json& d) { d["accessors"][1]["count"] = 3; }, "NORMAL has 3 elements but POSITION has 4"},
      {"indices_offset", [](json& d) { d["accessors"][2]["byteOffset"] = 4; }, "do not fit in bufferView"},
      {"buffer_too_short", [](json& d) { d["buffers"][0]["byteLength"] = 1000; },
       "buffer 0: its file 'valid.bin' is 120 bytes, but its byteLength says 1000 bytes"},
      {"virtual_accessors_over_the_limit_together",
       [](json& d) {
         d["accessors"].push_back({{"componentType", kFloat}, {"count", 700000}, {"type", "VEC3"}});
         d["accessors"].push_back({{"componentType", kFloat}, {"count", 700000}, {"type", "VEC3"}});
         d["meshes"][0]["primitives"][0]["attributes"] = {{"POSITION", 3}, {"NORMAL", 4}};
         d["meshes"][0]["primitives"][0].erase("indices");
       },
       "NORMAL (accessor 4) has too many elements without a bufferView: 700000 after 700000 read before"},
      {"missing_material", [](json& d) { d["meshes"][0]["primitives"][0]["material"] = 3; }, "material 3"},
      {"bad_mode", [](json& d) { d["meshes"][0]["primitives"][0]["mode"] = 9; }, "unknown primitive mode 9"},
      {"negative_index", [](json& d) { d["nodes"][0]["mesh"] = -1; }, "must be a non-negative integer"},
      {"string_count", [](json& d) { d["accessors"][0]["count"] = "4"; }, "accessors[0].count"},
      {"huge_translation",
       [](json& d) {
         d["nodes"][0]["translation"] = {1e300, 0, 0};
       },
       "translation is out of range"},
      {"zero_rotation",
       [](json& d) {
         d["nodes"][0]["rotation"] = {0, 0, 0, 0};
       },
       "not a unit quaternion"},
      {"two_parents",
       [](json& d) {
         d["nodes"].push_back({{"children", {0}}});
         d["nodes"].push_back({{"children", {0}}});
       },
       "more than one parent"},
      {"self_child", [](json& d) { d["nodes"][0]["children"] = {0}; }, "cycle"},
      {"not_json", [](json& d) { d = "just a string"; }, "not a glTF file"},
  };
  TempFolder folder;
  GltfBuilder gltf;
  gltf.addMeshNode(quadPrimitive(gltf));
  const fs::path valid = gltf.writeGltf(folder / "valid.gltf", true);
  std::ifstream in(valid);
  const json original = json::parse(in);
  EXPECT_NO_THROW(load(valid));
  for (const Corruption& corruption : corruptions) {
    SCOPED_TRACE(corruption.name);
    json broken = original;
    corruption.apply(broken);
    const fs::path path = folder / (std::string(corruption.name) + ".gltf");
    writeText(path, broken.dump());
    expectRefused(path, corruption.reason);
  }
  writeText(folder / "truncated.gltf", original.dump().substr(0, 40));
  expectRefused(folder / "truncated.gltf", "not valid JSON");
  expectRefused(folder / "does_not_exist.gltf", "file not found");
}

// Every byte of a small GLB (JSON, geometry, an embedded PNG) set to 0, to
// 255 and with its low bit flipped, one at a time: each variant must be
// refused with a SceneError or load well-formed; none may crash.
TEST(GltfImport, SurvivesEverySingleByteCorruptionOfAGlb) {
  TempFolder folder;
  GltfBuilder gltf;
  const std::vector<std::uint8_t> png = encodePng(2, 2, std::vector<std::uint8_t>(16, 200));
  gltf.add("images", {{"bufferView", gltf.addBufferView(png.data(), png.size())}, {"mimeType", "image/png"}});
  gltf.add("textures", {{"source", 0}});
  gltf.add("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  json primitive = quadPrimitive(gltf);
  primitive["attributes"]["TEXCOORD_0"] = gltf.floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2");
  primitive["material"] = 0;
  primitive["indices"] =
      gltf.addAccessor(std::vector<std::uint16_t>(kQuadIndices.begin(), kQuadIndices.end()), kUnsignedShort, "SCALAR");
  gltf.addMeshNode(primitive);
  const fs::path original = gltf.writeGlb(folder / "original.glb");
  ASSERT_EQ(load(original).scene.textures.size(), 1u);
  std::ifstream in(original, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());

  const fs::path corrupted = folder / "corrupted.glb";
  int refused = 0;
  for (std::size_t at = 0; at < bytes.size(); ++at)
    for (int variant = 0; variant < 3; ++variant) {
      std::vector<std::uint8_t> copy = bytes;
      copy[at] = variant == 0 ? 0 : variant == 1 ? 255 : std::uint8_t(copy[at] ^ 1);
      writeBytes(corrupted, copy.data(), copy.size());
      try {
        expectWellFormed(load(corrupted).scene);
      } catch (const SceneError& error) {
        ++refused;
        ASSERT_EQ(std::string(error.what()).rfind(corrupted.string() + ": ", 0), 0u) << error.what();
      }
      if (::testing::Test::HasFatalFailure()) FAIL() << "byte " << at << " variant " << variant;
    }
  EXPECT_GT(refused, 0);
}

TEST(GltfImport, RepairsBadNormalsAndTangentsWithAWarning) {
  TempFolder folder;
  GltfBuilder gltf;
  // Vertex 0's normal is zero, vertex 1's is too short; vertex 2's tangent lies along its normal.
  const std::vector<float> normals = {0, 0, 0, 0, 0, 0.5f, 0, 0, 1, 0, 0, 1};
  const std::vector<float> tangents = {1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 2, -1, 1, 0, 0, 1};
  gltf.addMeshNode({{"attributes",
                     {{"POSITION", gltf.floats(kQuadPositions, "VEC3")},
                      {"NORMAL", gltf.floats(normals, "VEC3")},
                      {"TANGENT", gltf.floats(tangents, "VEC4")}}},
                    {"indices", gltf.addAccessor(kQuadIndices, kUnsignedInt, "SCALAR")}});
  const Loaded loaded = load(gltf.writeGltf(folder / "repair.gltf"));

  const Mesh& mesh = loaded.scene.meshes.at(0);
  for (const glm::vec3& normal : mesh.normals) expectNear(normal, {0, 0, 1});
  EXPECT_EQ(mesh.tangents[2].w, -1.0f);
  expectWellFormed(loaded.scene);
  ASSERT_EQ(loaded.warnings.size(), 2u);
  EXPECT_NE(loaded.warnings[0].find("normals"), std::string::npos) << loaded.warnings[0];
  EXPECT_NE(loaded.warnings[1].find("tangents"), std::string::npos) << loaded.warnings[1];
}

// ------------------------------------------------------------------ tangents.h directly

// Two quads sharing the edge x = 0; u = |x| mirrors the left one, as on a
// symmetric model whose halves share one UV island.
TEST(Tangents, MirroredSeamVerticesAreSplitSoBothSidesAreRight) {
  Mesh mesh;
  mesh.name = "seam";
  mesh.positions = {{-1, 0, 0}, {0, 0, 0}, {1, 0, 0}, {-1, 1, 0}, {0, 1, 0}, {1, 1, 0}};
  for (const glm::vec3& p : mesh.positions) mesh.texcoords.push_back({std::abs(p.x), 1.0f - p.y});
  mesh.normals.assign(6, {0, 0, 1});
  mesh.indices = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4};
  generateTangents(mesh);

  EXPECT_EQ(mesh.positions.size(), 8u);  // the two seam vertices, once per side
  ASSERT_EQ(mesh.tangents.size(), 8u);
  for (std::size_t t = 0; t < 4; ++t) {
    const bool left = t < 2;
    for (std::size_t k = 0; k < 3; ++k) {
      const glm::vec4& tangent = mesh.tangents[mesh.indices[t * 3 + k]];
      expectNear(glm::vec3(tangent), {left ? -1.0f : 1.0f, 0, 0});
      EXPECT_EQ(tangent.w, left ? -1.0f : 1.0f);
    }
  }
}

TEST(Tangents, DegenerateInputStillGivesFiniteUnitTangents) {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 0, 0}, {0, 1, 0}, {std::nanf(""), 0, 0}};
  mesh.normals = {{0, 0, 1}, {0, 0, -1}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, 1}};
  mesh.texcoords.assign(6, {0.5f, 0.5f});  // all equal: no usable derivative
  mesh.indices = {0, 1, 2, 3, 4, 5};
  generateTangents(mesh);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3 tangent(mesh.tangents[v]);
    EXPECT_NEAR(glm::length(tangent), 1.0f, 1e-5f) << v;
    EXPECT_NEAR(glm::dot(tangent, mesh.normals[v]), 0.0f, 1e-5f) << v;
  }

  Mesh flat = mesh;
  generateFlatNormals(flat);
  for (const glm::vec3& normal : flat.normals) EXPECT_NEAR(glm::length(normal), 1.0f, 1e-5f);
  Mesh withoutNormals;
  withoutNormals.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  withoutNormals.indices = {0, 1, 2};
  EXPECT_THROW(generateTangents(withoutNormals), std::invalid_argument);
}

// ------------------------------------------------------------------ assimp's malformed models

const fs::path kAssimpModels = "/usr/share/assimp/models/glTF2";

TEST(GltfImportAssimpModels, MalformedFilesAreRefusedOrLoadCorrectly) {
  if (!fs::is_directory(kAssimpModels)) GTEST_SKIP() << kAssimpModels << " absent (Debian package assimp-testmodels)";
  struct Case {
    const char* file;
    const char* refusal;  // nullptr: the file is usable and must load
  };
  const Case cases[] = {
      {"IndexOutOfRange/IndexOutOfRange.gltf", "index 255 (at position 0) is out of range for 24 vertices"},
      {"IndexOutOfRange/AllIndicesOutOfRange.gltf", "out of range for 24 vertices"},
      {"MissingBin/BoxTextured.gltf", "BoxTextured0.bin"},
      {"SchemaFailures/sceneWrongType.gltf", "scene must be a non-negative integer"},
      {"wrongTypes/badArray.gltf", "meshes[0].primitives must be an array"},
      {"wrongTypes/badExtension.gltf", "KHR_texture_transform must be an object"},
      {"wrongTypes/badNumber.gltf", "materials[0].normalTexture.index is missing"},
      {"wrongTypes/badObject.gltf", "pbrMetallicRoughness must be an object"},
      {"wrongTypes/badString.gltf", "scenes[0].name must be a string"},
      {"wrongTypes/badUint.gltf", "baseColorTexture.index must be a non-negative integer"},
      {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "NaN or infinite"},
      {"RecursiveNodes/RecursiveNodes.gltf", "cycle"},
      {"TestNoRootNode/NoScene.gltf", "default scene 0 does not exist"},
      {"draco/2CylinderEngine.gltf", "KHR_draco_mesh_compression"},
      {"BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf", "KHR_technique_webgl"},
      // Valid, if empty: a scene without nodes.
      {"TestNoRootNode/SceneWithoutNodes.gltf", nullptr},
      // Zero and short normals: repaired (with a warning), as checked below.
      {"BoxBadNormals-glTF-Binary/BoxBadNormals.glb", nullptr},
      // Triangle lists of 35 vertices: the incomplete last triangle is dropped,
      // as a GPU would; the line primitives are skipped.
      {"IncorrectVertexArrays/Cube.gltf", nullptr},
      {"issue_3269/texcoord_crash.gltf", nullptr},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    if (c.refusal) {
      expectRefused(kAssimpModels / c.file, c.refusal);
    } else {
      ASSERT_NO_THROW(expectWellFormed(load(kAssimpModels / c.file).scene));
    }
  }

  const Loaded badNormals = load(kAssimpModels / "BoxBadNormals-glTF-Binary/BoxBadNormals.glb");
  ASSERT_EQ(badNormals.warnings.size(), 1u);
  EXPECT_NE(badNormals.warnings[0].find("normals"), std::string::npos);
  const Loaded cube = load(kAssimpModels / "IncorrectVertexArrays/Cube.gltf");
  std::size_t triangles = 0;
  for (const Mesh& mesh : cube.scene.meshes) triangles += mesh.indices.size() / 3;
  EXPECT_EQ(cube.scene.meshes.size(), 4u);
  EXPECT_EQ(triangles, 12u + 11u + 12u + 11u);
  EXPECT_EQ(cube.warnings.size(), 2u);
}

// Every glTF file in the collection: refused with a message naming it, or
// loaded with well-formed data. Nothing may crash or hang.
TEST(GltfImportAssimpModels, EveryFileIsRefusedCleanlyOrLoadsWellFormed) {
  if (!fs::is_directory(kAssimpModels)) GTEST_SKIP() << kAssimpModels << " absent (Debian package assimp-testmodels)";
  int files = 0;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(kAssimpModels)) {
    const std::string extension = entry.path().extension().string();
    if (extension != ".gltf" && extension != ".glb") continue;
    SCOPED_TRACE(entry.path().string());
    ++files;
    try {
      expectWellFormed(load(entry.path()).scene);
    } catch (const SceneError& error) {
      EXPECT_EQ(std::string(error.what()).rfind(entry.path().string() + ": ", 0), 0u) << error.what();
    }
  }
  EXPECT_GT(files, 20);
}

// ------------------------------------------------------------------ real scenes

const fs::path kScenes = fs::path(BOUNCE_SOURCE_DIR) / "../shared/scenes";

std::size_t uniqueMeshTriangles(const Scene& scene) {
  std::size_t triangles = 0;
  for (const Mesh& mesh : scene.meshes) triangles += mesh.indices.size() / 3;
  return triangles;
}

std::size_t instancedTriangles(const Scene& scene) {
  std::size_t triangles = 0;
  for (const Instance& instance : instancesAt(scene, 0.0f))
    triangles += scene.meshes[std::size_t(instance.mesh)].indices.size() / 3;
  return triangles;
}

// The triangle counts in ../shared/scenes/README.md count each mesh once;
// nodes place many meshes several times, so the drawn count is higher (the
// instanced numbers were counted from the files' JSON independently).
TEST(GltfImportRealScenes, SponzaLoadsCompletely) {
  const fs::path path = kScenes / "sponza/Sponza.gltf";
  if (!fs::exists(path)) GTEST_SKIP() << path << " absent";
  const Loaded loaded = load(path);
  const Scene& scene = loaded.scene;

  EXPECT_TRUE(loaded.warnings.empty());
  EXPECT_EQ(uniqueMeshTriangles(scene), 115580u);
  EXPECT_EQ(instancedTriangles(scene), 262087u);
  EXPECT_TRUE(std::any_of(scene.materials.begin(), scene.materials.end(),
                          [](const Material& m) { return m.alphaMode == AlphaMode::Mask; }));
  EXPECT_EQ(scene.textures.size(), 49u);
  for (const Texture& texture : scene.textures) {
    EXPECT_GT(texture.width, 0) << texture.name;
    EXPECT_EQ(texture.rgba8.size(), std::size_t(texture.width) * std::size_t(texture.height) * 4) << texture.name;
  }
  EXPECT_EQ(scene.cameras.size(), 4u);
  expectWellFormed(scene);
}

TEST(GltfImportRealScenes, BreakfastRoomUsesFallbacksAndWarnsOnce) {
  const fs::path path = kScenes / "breakfast_room/BreakfastRoom.gltf";
  if (!fs::exists(path)) GTEST_SKIP() << path << " absent";
  const Loaded loaded = load(path);
  const Scene& scene = loaded.scene;

  EXPECT_EQ(uniqueMeshTriangles(scene), 82291u);
  EXPECT_EQ(instancedTriangles(scene), 262687u);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("MSFT_texture_dds"), std::string::npos) << loaded.warnings[0];
  EXPECT_NE(loaded.warnings[0].find("KHR_materials_specular"), std::string::npos) << loaded.warnings[0];
  ASSERT_EQ(scene.cameras.size(), 3u);
  EXPECT_EQ(scene.cameras[0].name, "CameraMain");
  EXPECT_EQ(std::count_if(scene.nodes.begin(), scene.nodes.end(), [](const Node& n) { return n.camera >= 0; }), 3);
  // Each of the three cameras can be chosen, by number or by name.
  const auto position = [&](const std::string& spec) { return makeCameraPath(spec, scene)->pose(0.0f).position; };
  EXPECT_EQ(position("gltf"), position("gltf:CameraMain"));
  EXPECT_EQ(position("gltf:1"), position("gltf:CameraTableTop"));
  EXPECT_EQ(position("gltf:2"), position("gltf:CameraTopDown"));
  EXPECT_GT(glm::length(position("gltf:0") - position("gltf:1")), 0.1f);
  EXPECT_GT(glm::length(position("gltf:1") - position("gltf:2")), 0.1f);
  EXPECT_EQ(scene.textures.size(), 3u);
  for (const Texture& texture : scene.textures) EXPECT_EQ(texture.name.find(".dds"), std::string::npos);
  expectWellFormed(scene);
}

}  // namespace
}  // namespace bounce::scene
