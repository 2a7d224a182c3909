// Writing glTF files in tests: a builder for a document and its one binary
// buffer, written as .gltf (buffer as a data URI or a .bin file) or .glb,
// and the small helpers around it. Shared by the importer's tests and the
// bad-input corpus.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <stb/stb_image_write.h>
#include <nlohmann/json.hpp>

namespace bounce::testing::gltf {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kUnsignedByte = 5121;
constexpr int kUnsignedShort = 5123;
constexpr int kUnsignedInt = 5125;
constexpr int kFloat = 5126;

inline void writeBytes(const fs::path& path, const void* data, std::size_t size) {
  std::ofstream file(path, std::ios::binary);
  file.write(static_cast<const char*>(data), std::streamsize(size));
}

inline void writeText(const fs::path& path, const std::string& text) { writeBytes(path, text.data(), text.size()); }

inline std::string base64(const std::vector<std::uint8_t>& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t chunk = std::uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? bytes[i + 1] << 8 : 0) |
                                (i + 2 < bytes.size() ? bytes[i + 2] : 0);
    out += kAlphabet[chunk >> 18 & 63];
    out += kAlphabet[chunk >> 12 & 63];
    out += i + 1 < bytes.size() ? kAlphabet[chunk >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[chunk & 63] : '=';
  }
  return out;
}

inline std::vector<std::uint8_t> encodePng(int width, int height, const std::vector<std::uint8_t>& rgba) {
  std::vector<std::uint8_t> png;
  stbi_write_png_to_func(
      [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<std::uint8_t>*>(context);
        out->insert(out->end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
      },
      &png, width, height, 4, rgba.data(), width * 4);
  return png;
}

// A GLB container of this JSON text and binary chunk (none when empty).
inline void writeGlbFile(const fs::path& path, std::string text, std::vector<std::uint8_t> bin) {
  while (text.size() % 4 != 0) text += ' ';
  while (bin.size() % 4 != 0) bin.push_back(0);
  std::vector<std::uint8_t> file;
  const auto u32 = [&](std::uint32_t value) {
    for (int b = 0; b < 4; ++b) file.push_back(std::uint8_t(value >> (8 * b)));
  };
  const std::uint32_t length = 12 + 8 + std::uint32_t(text.size()) + (bin.empty() ? 0 : 8 + std::uint32_t(bin.size()));
  file.insert(file.end(), {'g', 'l', 'T', 'F'});
  u32(2);
  u32(length);
  u32(std::uint32_t(text.size()));
  u32(0x4E4F534A);
  file.insert(file.end(), text.begin(), text.end());
  if (!bin.empty()) {
    u32(std::uint32_t(bin.size()));
    u32(0x004E4942);
    file.insert(file.end(), bin.begin(), bin.end());
  }
  writeBytes(path, file.data(), file.size());
}

// Builds a glTF document and its one binary buffer, and writes it as .gltf
// (buffer as a data URI or a .bin file) or as .glb.
class GltfBuilder {
 public:
  GltfBuilder() : doc_({{"asset", {{"version", "2.0"}}}}) {}

  json& doc() { return doc_; }
  const std::vector<std::uint8_t>& bin() const { return bin_; }

  int addBufferView(const void* data, std::size_t size, std::size_t byteStride = 0) {
    while (bin_.size() % 4 != 0) bin_.push_back(0);
    json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", size}};
    if (byteStride) view["byteStride"] = byteStride;
    bin_.insert(bin_.end(), static_cast<const std::uint8_t*>(data), static_cast<const std::uint8_t*>(data) + size);
    doc_["bufferViews"].push_back(view);
    return int(doc_["bufferViews"].size()) - 1;
  }

  template <typename T>
  int addAccessor(const std::vector<T>& values, int componentType, const char* type, bool normalized = false) {
    const std::size_t components = std::string(type) == "SCALAR" ? 1 : std::size_t(type[3] - '0');
    json accessor = {{"bufferView", addBufferView(values.data(), values.size() * sizeof(T))},
                     {"componentType", componentType},
                     {"count", values.size() / components},
                     {"type", type}};
    if (normalized) accessor["normalized"] = true;
    doc_["accessors"].push_back(accessor);
    return int(doc_["accessors"].size()) - 1;
  }

  int floats(const std::vector<float>& values, const char* type) { return addAccessor(values, kFloat, type); }

  int add(const char* array, json item) {
    doc_[array].push_back(std::move(item));
    return int(doc_[array].size()) - 1;
  }

  // A mesh with one primitive, and a node holding it.
  int addMeshNode(json primitive, json node = json::object()) {
    node["mesh"] = add("meshes", {{"primitives", {std::move(primitive)}}});
    return add("nodes", std::move(node));
  }

  fs::path writeGltf(const fs::path& path, bool binFile = false) {
    json doc = doc_;
    if (!bin_.empty()) {
      const std::string uri =
          binFile ? path.stem().string() + ".bin" : "data:application/octet-stream;base64," + base64(bin_);
      if (binFile) writeBytes(path.parent_path() / uri, bin_.data(), bin_.size());
      doc["buffers"] = {{{"byteLength", bin_.size()}, {"uri", uri}}};
    }
    writeText(path, doc.dump(1));
    return path;
  }

  fs::path writeGlb(const fs::path& path) {
    json doc = doc_;
    if (!bin_.empty()) doc["buffers"] = {{{"byteLength", bin_.size()}}};
    writeGlbFile(path, doc.dump(), bin_);
    return path;
  }

 private:
  json doc_;
  std::vector<std::uint8_t> bin_;
};

// The unit square in z = 0 facing +Z, corners counter-clockwise from the origin.
const std::vector<float> kQuadPositions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
const std::vector<float> kQuadNormals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
const std::vector<std::uint32_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

inline json quadPrimitive(GltfBuilder& gltf) {
  return {{"attributes",
           {{"POSITION", gltf.floats(kQuadPositions, "VEC3")}, {"NORMAL", gltf.floats(kQuadNormals, "VEC3")}}},
          {"indices", gltf.addAccessor(kQuadIndices, kUnsignedInt, "SCALAR")}};
}

}  // namespace bounce::testing::gltf
