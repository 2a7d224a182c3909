// glTF 2.0 import. tinygltf parses the file; everything it hands over is
// treated as untrusted: every index, accessor range and value is checked here
// before use, because tinygltf itself checks little (it does not range-check
// accessors, and barely checks JSON types). Before tinygltf sees the file, a
// small schema check refuses values of the wrong JSON type, which tinygltf
// would otherwise silently replace by defaults.
#include "scene/gltf_import.h"

#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string_view>
#include <thread>
#include <unordered_set>
#include <utility>
#include <vector>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "io/image_io.h"
#include "scene/tangents.h"
#include "scene/uri.h"
#include "util/json_error.h"
#include "util/json_parse.h"
#include "util/printable.h"

namespace bounce::scene {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// ---------------------------------------------------------------- JSON schema

// The JSON type a glTF property must have. Index: a non-negative integer that
// fits an int (an index into an array, an enum, or a count or offset that
// tinygltf keeps in an int, as it does those of sparse accessors); Size: any
// non-negative integer (byte lengths and offsets, counts).
enum class Kind {
  Index,
  Size,
  Number,
  Bool,
  String,
  Object,
  IndexArray,
  NumberArray,
  StringArray,
  ObjectArray,
  IndexMap
};

struct Property {
  std::string_view name;
  Kind kind;
  bool required = false;
  std::span<const Property> members = {};  // for Object and ObjectArray
};

// The glTF 2.0 core schema, reduced to the properties this importer or
// tinygltf reads. "name", "extensions" and "extras" are checked on every object.
constexpr Property kTextureInfo[] = {
    {"index", Kind::Index, true}, {"texCoord", Kind::Index}, {"scale", Kind::Number}, {"strength", Kind::Number}};
constexpr Property kPbrMetallicRoughness[] = {{"baseColorFactor", Kind::NumberArray},
                                              {"baseColorTexture", Kind::Object, false, kTextureInfo},
                                              {"metallicFactor", Kind::Number},
                                              {"roughnessFactor", Kind::Number},
                                              {"metallicRoughnessTexture", Kind::Object, false, kTextureInfo}};
constexpr Property kMaterial[] = {{"pbrMetallicRoughness", Kind::Object, false, kPbrMetallicRoughness},
                                  {"normalTexture", Kind::Object, false, kTextureInfo},
                                  {"occlusionTexture", Kind::Object, false, kTextureInfo},
                                  {"emissiveTexture", Kind::Object, false, kTextureInfo},
                                  {"emissiveFactor", Kind::NumberArray},
                                  {"alphaMode", Kind::String},
                                  {"alphaCutoff", Kind::Number},
                                  {"doubleSided", Kind::Bool}};
constexpr Property kSparseIndices[] = {
    {"bufferView", Kind::Index, true}, {"byteOffset", Kind::Index}, {"componentType", Kind::Index, true}};
constexpr Property kSparseValues[] = {{"bufferView", Kind::Index, true}, {"byteOffset", Kind::Index}};
constexpr Property kSparse[] = {{"count", Kind::Index, true},
                                {"indices", Kind::Object, true, kSparseIndices},
                                {"values", Kind::Object, true, kSparseValues}};
constexpr Property kAccessor[] = {
    {"bufferView", Kind::Index}, {"byteOffset", Kind::Size},  {"componentType", Kind::Index, true},
    {"normalized", Kind::Bool},  {"count", Kind::Size, true}, {"type", Kind::String, true},
    {"max", Kind::NumberArray},  {"min", Kind::NumberArray},  {"sparse", Kind::Object, false, kSparse}};
constexpr Property kChannelTarget[] = {{"node", Kind::Index}, {"path", Kind::String, true}};
constexpr Property kChannel[] = {{"sampler", Kind::Index, true}, {"target", Kind::Object, true, kChannelTarget}};
constexpr Property kAnimationSampler[] = {
    {"input", Kind::Index, true}, {"interpolation", Kind::String}, {"output", Kind::Index, true}};
constexpr Property kAnimation[] = {{"channels", Kind::ObjectArray, true, kChannel},
                                   {"samplers", Kind::ObjectArray, true, kAnimationSampler}};
constexpr Property kAsset[] = {{"version", Kind::String, true},
                               {"minVersion", Kind::String},
                               {"generator", Kind::String},
                               {"copyright", Kind::String}};
constexpr Property kBuffer[] = {{"uri", Kind::String}, {"byteLength", Kind::Size, true}};
constexpr Property kBufferView[] = {{"buffer", Kind::Index, true},
                                    {"byteOffset", Kind::Size},
                                    {"byteLength", Kind::Size, true},
                                    {"byteStride", Kind::Size},
                                    {"target", Kind::Index}};
constexpr Property kPerspective[] = {
    {"aspectRatio", Kind::Number}, {"yfov", Kind::Number, true}, {"zfar", Kind::Number}, {"znear", Kind::Number, true}};
constexpr Property kOrthographic[] = {{"xmag", Kind::Number, true},
                                      {"ymag", Kind::Number, true},
                                      {"zfar", Kind::Number, true},
                                      {"znear", Kind::Number, true}};
constexpr Property kCamera[] = {{"type", Kind::String, true},
                                {"perspective", Kind::Object, false, kPerspective},
                                {"orthographic", Kind::Object, false, kOrthographic}};
constexpr Property kImage[] = {{"uri", Kind::String}, {"mimeType", Kind::String}, {"bufferView", Kind::Index}};
constexpr Property kPrimitive[] = {{"attributes", Kind::IndexMap, true},
                                   {"indices", Kind::Index},
                                   {"material", Kind::Index},
                                   {"mode", Kind::Index},
                                   {"targets", Kind::ObjectArray}};
constexpr Property kMesh[] = {{"primitives", Kind::ObjectArray, true, kPrimitive}, {"weights", Kind::NumberArray}};
constexpr Property kNode[] = {{"camera", Kind::Index},       {"children", Kind::IndexArray},
                              {"skin", Kind::Index},         {"matrix", Kind::NumberArray},
                              {"mesh", Kind::Index},         {"rotation", Kind::NumberArray},
                              {"scale", Kind::NumberArray},  {"translation", Kind::NumberArray},
                              {"weights", Kind::NumberArray}};
constexpr Property kSampler[] = {
    {"magFilter", Kind::Index}, {"minFilter", Kind::Index}, {"wrapS", Kind::Index}, {"wrapT", Kind::Index}};
constexpr Property kScene[] = {{"nodes", Kind::IndexArray}};
constexpr Property kSkin[] = {
    {"inverseBindMatrices", Kind::Index}, {"skeleton", Kind::Index}, {"joints", Kind::IndexArray, true}};
constexpr Property kTexture[] = {{"sampler", Kind::Index}, {"source", Kind::Index}};
constexpr Property kRoot[] = {{"extensionsUsed", Kind::StringArray},
                              {"extensionsRequired", Kind::StringArray},
                              {"accessors", Kind::ObjectArray, false, kAccessor},
                              {"animations", Kind::ObjectArray, false, kAnimation},
                              {"asset", Kind::Object, true, kAsset},
                              {"buffers", Kind::ObjectArray, false, kBuffer},
                              {"bufferViews", Kind::ObjectArray, false, kBufferView},
                              {"cameras", Kind::ObjectArray, false, kCamera},
                              {"images", Kind::ObjectArray, false, kImage},
                              {"materials", Kind::ObjectArray, false, kMaterial},
                              {"meshes", Kind::ObjectArray, false, kMesh},
                              {"nodes", Kind::ObjectArray, false, kNode},
                              {"samplers", Kind::ObjectArray, false, kSampler},
                              {"scene", Kind::Index},
                              {"scenes", Kind::ObjectArray, false, kScene},
                              {"skins", Kind::ObjectArray, false, kSkin},
                              {"textures", Kind::ObjectArray, false, kTexture}};

const char* describe(Kind kind) {
  switch (kind) {
    case Kind::Index:
    case Kind::Size:
      return "a non-negative integer";
    case Kind::Number:
      return "a number";
    case Kind::Bool:
      return "true or false";
    case Kind::String:
      return "a string";
    case Kind::Object:
      return "an object";
    case Kind::IndexArray:
      return "an array of non-negative integers";
    case Kind::NumberArray:
      return "an array of numbers";
    case Kind::StringArray:
      return "an array of strings";
    case Kind::ObjectArray:
      return "an array of objects";
    case Kind::IndexMap:
      return "an object whose values are non-negative integers";
  }
  return "?";
}

bool isSize(const json& value) {
  return value.is_number_unsigned() || (value.is_number_integer() && value.get<std::int64_t>() >= 0);
}
bool isIndex(const json& value) {
  return isSize(value) && value.get<std::uint64_t>() <= std::uint64_t(std::numeric_limits<int>::max());
}

// Returns the first schema violation below `object` ("meshes[0].primitives
// must be an array of objects"), or an empty string.
std::string schemaViolation(const json& object, std::span<const Property> properties, const std::string& where);

std::string kindViolation(const json& value, const Property& property, const std::string& where) {
  const auto all = [&](auto&& predicate) {
    return value.is_array() && std::all_of(value.begin(), value.end(), predicate);
  };
  bool ok = false;
  switch (property.kind) {
    case Kind::Index:
      ok = isIndex(value);
      break;
    case Kind::Size:
      ok = isSize(value);
      break;
    case Kind::Number:
      ok = value.is_number();
      break;
    case Kind::Bool:
      ok = value.is_boolean();
      break;
    case Kind::String:
      ok = value.is_string();
      break;
    case Kind::Object:
      ok = value.is_object();
      break;
    case Kind::IndexArray:
      ok = all([](const json& v) { return isIndex(v); });
      break;
    case Kind::NumberArray:
      ok = all([](const json& v) { return v.is_number(); });
      break;
    case Kind::StringArray:
      ok = all([](const json& v) { return v.is_string(); });
      break;
    case Kind::ObjectArray:
      ok = all([](const json& v) { return v.is_object(); });
      break;
    case Kind::IndexMap:
      ok = value.is_object() && std::all_of(value.begin(), value.end(), [](const json& v) { return isIndex(v); });
      break;
  }
  // tinygltf would wrap a larger index or count around, or cut it short.
  if (property.kind == Kind::Index && isSize(value) && !ok)
    return where + " is " + value.dump() + ", over " + std::to_string(std::numeric_limits<int>::max()) +
           ", the most this importer reads there";
  if (!ok) return where + " must be " + describe(property.kind);
  if (property.kind == Kind::Object) return schemaViolation(value, property.members, where);
  if (property.kind == Kind::ObjectArray)
    for (std::size_t i = 0; i < value.size(); ++i) {
      std::string violation = schemaViolation(value[i], property.members, where + "[" + std::to_string(i) + "]");
      if (!violation.empty()) return violation;
    }
  return {};
}

std::string schemaViolation(const json& object, std::span<const Property> properties, const std::string& where) {
  const std::string prefix = where.empty() ? "" : where + ".";
  for (const Property& property : properties) {
    const auto found = object.find(std::string(property.name));
    if (found == object.end()) {
      if (property.required) return prefix + std::string(property.name) + " is missing";
      continue;
    }
    std::string violation = kindViolation(*found, property, prefix + std::string(property.name));
    if (!violation.empty()) return violation;
  }
  if (const auto name = object.find("name"); name != object.end() && !name->is_string())
    return prefix + "name must be a string";
  if (const auto extensions = object.find("extensions"); extensions != object.end()) {
    if (!extensions->is_object()) return prefix + "extensions must be an object";
    for (const auto& [extension, value] : extensions->items())
      if (!value.is_object()) return prefix + "extensions." + extension + " must be an object";
  }
  return {};
}

// ---------------------------------------------------------------- nesting depth

// tinygltf turns extras and extensions into its own values recursively, one
// stack frame per level, so a small file nested thousands of levels deep
// overflows the stack. No glTF needs more than a dozen levels; JSON nested
// deeper than this is refused while it is parsed here (util::parseJson:
// iterative, stopping at the first container past the limit without
// building the rest), before tinygltf sees it.
constexpr int kMaxJsonDepth = 64;

// ---------------------------------------------------------------- file access

// Buffer and image files come from the glTF file's folder only (unless the
// user allows others): a scene from the internet must not make Bounce read
// ../../etc/passwd into a buffer, or tell whether such a file exists.
struct AssetFolder {
  std::string baseDir;  // the folder as handed to tinygltf, which appends "/" and the decoded URI
  fs::path folder;      // the same folder, with symlinks resolved
  bool allowOutside = false;
  std::string refusal;         // why the first refused URI (or file) was refused
  std::vector<fs::path> read;  // every buffer and image file read, in order
  // The largest file any buffer or image of this glTF may be: a file larger
  // than this is refused by its size, before a byte of it is read.
  std::uint64_t maxFileBytes = 0;
};

// Symlinks followed while resolving one URI before it counts as a loop (Linux's limit).
constexpr int kMaxSymlinksPerUri = 40;

// The file a relative path names inside `folder`, with every symlink on the
// way resolved (dangling ones too), or nothing when getting there leaves the
// folder at any step: ".." above it, or a symlink pointing elsewhere. The
// answer depends only on what lies inside the folder, never on what exists
// outside it, so a refusal reveals nothing about other files.
std::optional<fs::path> insideFolder(const fs::path& folder, const fs::path& relative) {
  if (relative.has_root_path()) return std::nullopt;
  std::vector<fs::path> pending(relative.begin(), relative.end());  // the next part last
  std::reverse(pending.begin(), pending.end());
  fs::path resolved = folder;
  int symlinks = 0;
  while (!pending.empty()) {
    const fs::path part = std::move(pending.back());
    pending.pop_back();
    if (part.empty() || part == ".") continue;
    if (part == "..") {
      if (resolved == folder) return std::nullopt;
      resolved = resolved.parent_path();
      continue;
    }
    const fs::path next = resolved / part;
    std::error_code error;
    if (!fs::is_symlink(fs::symlink_status(next, error))) {
      resolved = next;
      continue;
    }
    fs::path target = fs::read_symlink(next, error);
    if (error || ++symlinks > kMaxSymlinksPerUri) return std::nullopt;
    if (target.has_root_path()) {
      // An absolute target is followed only when it lies inside the folder as written.
      const fs::path rest = target.lexically_normal().lexically_relative(folder);
      if (rest.empty() || *rest.begin() == "..") return std::nullopt;
      resolved = folder;
      target = rest;
    }
    for (auto it = target.end(); it != target.begin();) pending.push_back(*--it);
  }
  return resolved;
}

// A URI for a message: control bytes (a decoded %00 among them) written as
// %XX again, and at most a line's worth of it.
std::string printableUri(const std::string& uri) {
  constexpr std::size_t kMaxLength = 200;
  std::string text;
  for (const char c : uri.substr(0, kMaxLength)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      const char* hex = "0123456789ABCDEF";
      text += {'%', hex[byte >> 4], hex[byte & 15]};
    } else {
      text += c;
    }
  }
  return uri.size() > kMaxLength ? text + "..." : text;
}

// tinygltf's ExpandFilePath callback, through which every file it opens
// passes: the path to open for base directory + "/" + decoded URI, or ""
// (which tinygltf reports as a missing file) for a refused URI.
std::string resolveAssetPath(const std::string& joined, void* userData) {
  AssetFolder& assets = *static_cast<AssetFolder*>(userData);
  const std::string prefix = assets.baseDir.ends_with('/') ? assets.baseDir : assets.baseDir + "/";
  // tinygltf also tries each URI relative to the current directory, which
  // would make a broken scene load or not depending on where the program runs.
  if (!joined.starts_with(prefix)) return {};
  const std::string uri = joined.substr(prefix.size());
  const auto refuse = [&](const std::string& why) {
    if (assets.refusal.empty()) assets.refusal = "the buffer or image file '" + printableUri(uri) + "' " + why;
    return std::string();
  };
  // The C library would end the path at the NUL and open another file.
  if (uri.find('\0') != std::string::npos) return refuse("has a NUL byte (%00) in its URI");
  // As tinygltf joined it (not normalised: "link/.." must mean what the file
  // system makes of it), except that an absolute URI stays absolute.
  const std::optional<fs::path> resolved =
      assets.allowOutside ? std::optional(fs::path(fs::path(uri).is_absolute() ? uri : joined))
                          : insideFolder(assets.folder, uri);
  if (!resolved)
    return refuse("lies outside the glTF file's folder; files there are read only with --allow-outside-assets");
  // tinygltf would call a folder or a FIFO "not found" (and reading a FIFO
  // would wait for a writer forever).
  std::error_code error;
  const fs::file_status status = fs::status(*resolved, error);
  if (fs::exists(status) && !fs::is_regular_file(status))
    return refuse(std::string("is not a regular file (") +
                  (fs::is_directory(status) ? "a folder" : fs::is_fifo(status) ? "a FIFO" : "a device or socket") + ")");
  return resolved->string();
}

// tinygltf file callbacks that only ever open the absolute paths
// resolveAssetPath returns.
bool absoluteFileExists(const std::string& path, void*) {
  std::error_code error;
  return fs::path(path).is_absolute() && fs::is_regular_file(path, error);
}
bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* userData) {
  AssetFolder& assets = *static_cast<AssetFolder*>(userData);
  assets.read.push_back(path);
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  const std::streamoff size = file ? std::streamoff(file.tellg()) : -1;
  // The importer sized every file the glTF names before tinygltf ran; this
  // catches one that grew since, still before it is read.
  if (size >= 0 && std::uint64_t(size) > assets.maxFileBytes) {
    if (assets.refusal.empty())
      assets.refusal = "the file '" + printableUri(path) + "' is " + io::memoryText(std::uint64_t(size)) +
                       ", larger than any buffer or image of this glTF may be";
    if (err) *err = assets.refusal;
    return false;
  }
  if (size >= 0) {
    out->resize(std::size_t(size));
    file.seekg(0);
    if (file.read(reinterpret_cast<char*>(out->data()), size)) return true;
  }
  if (err) *err = "cannot read " + path;
  return false;
}
bool refuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err = "the importer never writes files";
  return false;
}

// tinygltf hands every image's encoded bytes to this callback. Keeping them
// encoded (instead of letting tinygltf decode everything) means only images
// that materials use get decoded, in parallel, and formats such as DDS that
// are only referenced by extensions are never touched.
bool keepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  // For images stored in a bufferView tinygltf passes a pointer it has not
  // range-checked; those are read later through the checked bufferView path.
  if (image->bufferView >= 0) return true;
  image->image.assign(bytes, bytes + std::max(size, 0));
  image->as_is = true;
  return true;
}

// How messages name the i-th object of a kind: "light 0 'lamp'", or "light 0" when it has no name.
std::string named(const char* kind, std::size_t index, const std::string& name) {
  return kind + (" " + std::to_string(index)) + (name.empty() ? "" : " '" + name + "'");
}

// A number from the file for a message, with the digits that tell it from its neighbours.
std::string numberText(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", value);
  return text;
}

// tinygltf's messages end lines with '\n'; a SceneError is one line.
std::string oneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  for (std::size_t at = text.find('\n'); at != std::string::npos; at = text.find('\n', at)) text.replace(at, 1, "; ");
  return text;
}

std::uint32_t readU32(const std::vector<unsigned char>& bytes, std::size_t offset) {
  std::uint32_t value;
  std::memcpy(&value, bytes.data() + offset, 4);
  return value;  // GLB is little-endian, as is every machine this runs on
}

// ---------------------------------------------------------------- accessors

const char* componentTypeName(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT:
      return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return "FLOAT";
    case TINYGLTF_COMPONENT_TYPE_DOUBLE:
      return "DOUBLE";
  }
  return "an unknown component type";
}

std::size_t componentSize(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
  }
  return 0;
}

const char* typeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
  }
  return "an unknown type";
}

std::size_t componentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
  }
  return 0;
}

// One component as a number; normalized integers map to [0,1] or [-1,1] as the
// glTF spec says (signed: max(c / MAX, -1)).
double componentValue(const unsigned char* bytes, int componentType, bool normalized) {
  const auto load = [bytes](auto value) {
    std::memcpy(&value, bytes, sizeof(value));
    return value;
  };
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const double value = load(std::int8_t());
      return normalized ? std::max(value / 127.0, -1.0) : value;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const double value = load(std::uint8_t());
      return normalized ? value / 255.0 : value;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const double value = load(std::int16_t());
      return normalized ? std::max(value / 32767.0, -1.0) : value;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const double value = load(std::uint16_t());
      return normalized ? value / 65535.0 : value;
    }
    case TINYGLTF_COMPONENT_TYPE_INT:
      return load(std::int32_t());
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return load(std::uint32_t());
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return load(float());
  }
  return 0.0;
}

// What an accessor must hold for one use (a vertex attribute, indices, keys).
struct AccessorFormat {
  int type;                         // TINYGLTF_TYPE_*
  std::vector<int> componentTypes;  // allowed TINYGLTF_COMPONENT_TYPE_*
  bool integersNormalized;          // integer components must be normalized (true) or must not be (false)
};

const AccessorFormat kVec3Floats{TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT}, false};
const AccessorFormat kVec4Floats{TINYGLTF_TYPE_VEC4, {TINYGLTF_COMPONENT_TYPE_FLOAT}, false};
const AccessorFormat kScalarFloats{TINYGLTF_TYPE_SCALAR, {TINYGLTF_COMPONENT_TYPE_FLOAT}, false};
const AccessorFormat kTexcoords{
    TINYGLTF_TYPE_VEC2,
    {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
    true};
const AccessorFormat kIndices{TINYGLTF_TYPE_SCALAR,
                              {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                               TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                              false};
const AccessorFormat kRotationKeys{
    TINYGLTF_TYPE_VEC4,
    {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
     TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
    true};

// An accessor without a bufferView is all zeros (plus sparse values), so a
// 2 KB file can ask for any number of elements: two of 2^24 took 2.2 GB
// before the renderer refused the vertex buffer they made. The elements of
// every such accessor read (each time it is read) are counted against this,
// before any is allocated; real data comes with a bufferView, whose bytes
// bound its count.
constexpr std::size_t kMaxVirtualElements = std::size_t(1) << 20;
// glTF images are at most this many pixels a side here (as in io/image_io).
constexpr int kMaxTextureSide = 16384;

// The image files a glTF names are held, encoded, while their pixels are
// decoded, which takes at least as many bytes again: together they may be
// at most half of the memory a command may plan for its images (the rest
// of that limit then bounds the decoded textures; docs/reliability.md).
constexpr std::uint64_t kMaxImageFileBytes = io::kImageMemoryLimit / 2;

// The renderer draws a texture at most this many pixels a side (a larger
// one is shrunk into its atlas), said when a texture is refused for memory.
constexpr int kDrawnTextureSide = 2048;

// A URI's %XX escapes decoded as tinygltf decodes them before it opens the
// file (its dlib::urldecode, which is not part of its interface): '+' is a
// space, and a '%' with two characters after it always takes them, a
// character that is not a hex digit counting as 0. The importer sizes the
// file tinygltf will open, so it must name the same file.
std::string decodedAsTinygltfDoes(const std::string& uri) {
  const auto hex = [](char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return 0;
  };
  std::string decoded;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      decoded += ' ';
    } else if (uri[i] == '%' && uri.size() > i + 2) {
      decoded += char(hex(uri[i + 1]) << 4 | hex(uri[i + 2]));
      i += 2;
    } else {
      decoded += uri[i];
    }
  }
  return decoded;
}

// ---------------------------------------------------------------- the importer

enum class Topology { Triangles, Strip, Fan };

struct DecodeJob {
  int image = -1;
  std::string name;
  std::vector<int> textures;  // Scene::textures filled from this image (sRGB and/or linear)
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba8;
  std::string error;
};

class Importer {
 public:
  Importer(const fs::path& path, const GltfImportOptions& options) : path_(path), options_(options) {
    scene_.name = path.filename().string();
    scene_.source = path;
    scene_.files = {path};
  }

  Scene run() {
    const std::vector<unsigned char> bytes = readFile();
    load(bytes);
    checkVersion();
    convertMaterials();
    convertMeshes();
    convertCameras();
    convertLights();
    convertNodes();
    convertAnimations();
    chooseRoots();
    decodeTextures();
    validate(scene_);
    emitWarnings();
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const std::string& reason) const { throw SceneError(path_.string() + ": " + reason); }

  // A JSON number as a float: values a float cannot hold are refused rather
  // than turned into infinity.
  float toFloat(double value, const std::string& what) const {
    if (!(std::abs(value) <= double(std::numeric_limits<float>::max()))) fail(what + " is out of range");
    return float(value);
  }

  // Collects one warning line per kind of problem, naming what it concerns.
  void warn(const std::string& kind, const std::string& subject) {
    auto found = std::find_if(warnings_.begin(), warnings_.end(), [&](const Warning& w) { return w.kind == kind; });
    if (found == warnings_.end()) found = warnings_.insert(warnings_.end(), {kind, {}, {}});
    if (found->named.insert(subject).second) found->subjects.push_back(subject);
  }

  void emitWarnings() const {
    constexpr std::size_t kNamedSubjects = 8;
    const auto emit = [&](const std::string& line) {
      if (options_.warn)
        options_.warn(line);
      else
        std::cerr << "bounce: warning: " << util::printable(line) << "\n";
    };
    if (!ignoredExtensions_.empty()) {
      std::string line = path_.string() + ": ignoring unsupported optional glTF extensions: ";
      for (std::size_t i = 0; i < ignoredExtensions_.size(); ++i) line += (i ? ", " : "") + ignoredExtensions_[i];
      emit(line);
    }
    for (const auto& [kind, subjects, named] : warnings_) {
      std::string line = path_.string() + ": " + kind + ": ";
      for (std::size_t i = 0; i < subjects.size() && i < kNamedSubjects; ++i) line += (i ? ", " : "") + subjects[i];
      if (subjects.size() > kNamedSubjects)
        line += " and " + std::to_string(subjects.size() - kNamedSubjects) + " more";
      emit(line);
    }
  }

  // ------------------------------------------------------------ loading

  std::vector<unsigned char> readFile() const {
    std::error_code error;
    if (!fs::exists(path_, error)) fail("file not found");
    if (!fs::is_regular_file(path_, error)) fail("not a regular file");
    const std::uintmax_t size = fs::file_size(path_, error);
    // tinygltf takes sizes as unsigned int.
    if (error || size > std::uintmax_t(std::numeric_limits<std::int32_t>::max())) fail("file too large or unreadable");
    std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
    std::ifstream file(path_, std::ios::binary);
    if (!file.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()))) fail("cannot read file");
    return bytes;
  }

  void load(const std::vector<unsigned char>& bytes) {
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    std::size_t glbLength = 0;
    if (binary) {
      // tinygltf checks the GLB layout only partly (it can read past the end
      // of a BIN chunk whose header lies), so the whole layout is checked here.
      if (bytes.size() < 20) fail("truncated GLB header");
      if (readU32(bytes, 4) != 2) fail("GLB container version " + std::to_string(readU32(bytes, 4)) + " is not 2");
      glbLength = readU32(bytes, 8);
      if (glbLength > bytes.size())
        fail("truncated GLB: header says " + std::to_string(glbLength) + " bytes, file has " +
             std::to_string(bytes.size()));
      const std::uint64_t jsonLength = readU32(bytes, 12);
      if (readU32(bytes, 16) != 0x4E4F534Au) fail("the first GLB chunk is not JSON");
      if (jsonLength == 0) fail("the GLB JSON chunk is empty");
      if (20 + jsonLength > glbLength) fail("the GLB JSON chunk runs past the end of the file");
      const std::uint64_t binStart = 20 + jsonLength;
      if (binStart < glbLength) {
        if (binStart + 8 > glbLength) fail("truncated GLB chunk header");
        if (binStart + 8 + readU32(bytes, binStart) > glbLength)
          fail("the GLB BIN chunk runs past the end of the file");
        if (readU32(bytes, binStart + 4) != 0x004E4942u) fail("the second GLB chunk is not BIN");
      }
      text = text.substr(20, jsonLength);
    }

    json document;
    try {
      document = util::parseJson(text.begin(), text.end(), kMaxJsonDepth);
    } catch (const util::JsonTooDeep& e) {
      fail(e.what());
    } catch (const json::exception& e) {
      fail("not valid JSON (" + util::withoutJsonExceptionTag(e.what()) + ")");
    }
    if (!document.is_object()) fail("not a glTF file (the JSON is not an object)");
    if (const std::string violation = schemaViolation(document, kRoot, ""); !violation.empty())
      fail("invalid glTF: " + violation);
    checkExtensions(document);
    checkLightValues(document);

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&keepEncodedImage, nullptr);
    const fs::path folder = fs::absolute(path_).parent_path();
    std::error_code error;
    AssetFolder assets{folder.string(), fs::weakly_canonical(folder, error), options_.allowOutsideAssets, {}};
    if (error) fail("cannot resolve the folder of the file (" + error.message() + ")");
    sizeAssetFiles(document, assets);
    loader.SetFsCallbacks({&absoluteFileExists, &resolveAssetPath, &readWholeFile, &refuseWrite, &assets});
    std::string loadError;
    // tinygltf's warnings only concern images it could not read; whether that
    // matters depends on whether a material uses the image, checked later.
    std::string ignoredWarnings;
    bool loaded = false;
    try {
      loaded = binary ? loader.LoadBinaryFromMemory(&model_, &loadError, &ignoredWarnings, bytes.data(),
                                                    unsigned(glbLength), assets.baseDir)
                      : loader.LoadASCIIFromString(&model_, &loadError, &ignoredWarnings, text.data(),
                                                   unsigned(text.size()), assets.baseDir);
    } catch (const std::exception& e) {
      // tinygltf's JSON library throws on some inputs the schema check lets through.
      loadError = e.what();
    }
    // A refused URI is an error even for an image no material uses, and
    // tinygltf's own message would call the file missing.
    if (!assets.refusal.empty()) fail(assets.refusal);
    scene_.files.insert(scene_.files.end(), assets.read.begin(), assets.read.end());
    if (!loaded)
      fail("cannot load glTF: " + (loadError.empty() ? std::string("tinygltf gave no reason") : oneLine(loadError)));
    restoreDroppedPbrBlocks(document);
  }

  // Every buffer and image a URI names, sized before tinygltf reads any:
  // tinygltf reads a whole file and only then compares a buffer's size with
  // its byteLength (a 2 GB sparse scene.bin was read, 8 s and 2.1 GB, to be
  // refused), reads every image whether a material uses it or not, and
  // calls a file it did not read "missing". A buffer must be exactly its
  // byteLength (data: URIs too, decoded); the image files together at most
  // kMaxImageFileBytes. Missing or empty image files are noted for the
  // message, should a material use one.
  void sizeAssetFiles(const json& document, AssetFolder& assets) {
    const std::string prefix = assets.baseDir.ends_with('/') ? assets.baseDir : assets.baseDir + "/";
    // The file tinygltf will open for a URI (resolveAssetPath's answer), or
    // nothing for a data: URI or none; a refused URI is refused here.
    const auto fileOf = [&](const std::string& uri) -> std::optional<fs::path> {
      if (uri.empty() || tinygltf::IsDataURI(uri)) return std::nullopt;
      const std::string resolved = resolveAssetPath(prefix + decodedAsTinygltfDoes(uri), &assets);
      if (!assets.refusal.empty()) fail(assets.refusal);
      return fs::path(resolved);
    };
    // A regular file's size; nothing for one that is missing (tinygltf and
    // the messages below say so) or cannot be sized.
    const auto sizeOf = [](const fs::path& file) -> std::optional<std::uint64_t> {
      std::error_code error;
      const std::uintmax_t size = fs::file_size(file, error);
      if (error) return std::nullopt;
      return std::uint64_t(size);
    };
    const auto text = [](std::uint64_t bytes) {
      return std::to_string(bytes) + (bytes == 1 ? " byte" : " bytes") +
             (bytes >= 1024 ? " (" + io::memoryText(bytes) + ")" : "");
    };
    const json* buffers = document.contains("buffers") ? &document["buffers"] : nullptr;
    for (std::size_t i = 0; buffers && i < buffers->size(); ++i) {
      const json& buffer = (*buffers)[i];
      const std::string uri = buffer.value("uri", "");
      const std::uint64_t byteLength = buffer["byteLength"].get<std::uint64_t>();
      const std::string what = named("buffer", i, buffer.value("name", ""));
      assets.maxFileBytes = std::max(assets.maxFileBytes, byteLength);
      if (tinygltf::IsDataURI(uri)) {
        // tinygltf's own message for a size that differs, "Failed to decode
        // 'uri'", blames the encoding and repeats the whole URI.
        std::vector<unsigned char> decoded;
        std::string mimeType;
        tinygltf::DecodeDataURI(&decoded, mimeType, uri, 0, false);
        if (decoded.empty()) fail(what + ": its data: URI holds no base64 data");
        if (decoded.size() != byteLength)
          fail(what + ": its data: URI decodes to " + text(decoded.size()) + ", but its byteLength says " +
               text(byteLength));
        continue;
      }
      const std::optional<fs::path> file = fileOf(uri);
      if (!file) continue;
      std::error_code missing;
      if (!fs::exists(*file, missing))
        fail(what + ": its file '" + printableUri(percentDecoded(uri)) + "' does not exist");
      const std::optional<std::uint64_t> size = sizeOf(*file);
      if (size && *size != byteLength)
        fail(what + ": its file '" + printableUri(percentDecoded(uri)) + "' is " + text(*size) +
             ", but its byteLength says " + text(byteLength));
    }
    const json* images = document.contains("images") ? &document["images"] : nullptr;
    std::uint64_t imageFileBytes = 0;
    for (std::size_t i = 0; images && i < images->size(); ++i) {
      const std::string uri = (*images)[i].value("uri", "");
      const std::optional<fs::path> file = fileOf(uri);
      if (!file) continue;
      assets.maxFileBytes = std::max(assets.maxFileBytes, kMaxImageFileBytes);
      const std::string name = printableUri(percentDecoded(uri));
      std::error_code missing;
      if (!fs::exists(*file, missing)) {
        imageFileProblems_[int(i)] = "the file does not exist";
        continue;
      }
      const std::optional<std::uint64_t> size = sizeOf(*file);
      if (!size) continue;
      if (*size == 0) imageFileProblems_[int(i)] = "the file is empty";
      imageFileBytes += *size;
      if (imageFileBytes > kMaxImageFileBytes)
        fail("the image file '" + name + "' is too large: " + text(*size) +
             (imageFileBytes > *size ? ", " + io::memoryText(imageFileBytes) + " with the image files before it" : "") +
             "; a glTF's image files may hold at most " + io::memoryText(kMaxImageFileBytes) + " in all (half the " +
             io::memoryText(io::kImageMemoryLimit) +
             " image memory limit: they are held while their pixels are decoded; docs/reliability.md)");
    }
  }

  // tinygltf replaces a KHR_lights_punctual value of the wrong JSON type by
  // its default without a word (and a light without a type string by an
  // error naming no light). The file's values are checked here first: each
  // one that falls back to its default is named in a warning; a light with
  // no type to fall back on is refused.
  void checkLightValues(const json& document) {
    const auto extensions = document.find("extensions");
    if (extensions == document.end()) return;
    const auto punctual = extensions->find("KHR_lights_punctual");
    if (punctual == extensions->end()) return;
    const auto lights = punctual->find("lights");
    if (lights == punctual->end()) return;
    if (!lights->is_array() ||
        !std::all_of(lights->begin(), lights->end(), [](const json& l) { return l.is_object(); }))
      fail("extensions.KHR_lights_punctual.lights must be an array of objects");
    for (std::size_t i = 0; i < lights->size(); ++i) {
      const json& light = (*lights)[i];
      const auto name = light.find("name");
      const std::string what =
          named("light", i, name != light.end() && name->is_string() ? name->get<std::string>() : "");
      const auto type = light.find("type");
      if (type == light.end() || !type->is_string())
        fail(what + ": type must be a string (directional, point or spot)");
      // Present but not a number: tinygltf uses the default.
      const auto warnUnlessNumber = [&](const json& object, const char* key, const std::string& kind) {
        if (const auto found = object.find(key); found != object.end() && !found->is_number()) warn(kind, what);
      };
      if (const auto color = light.find("color");
          color != light.end() && !(color->is_array() && std::all_of(color->begin(), color->end(),
                                                                     [](const json& c) { return c.is_number(); })))
        warn("light color must be an array of 3 numbers; using (1, 1, 1)", what);
      warnUnlessNumber(light, "intensity", "light intensity must be a number; using 1");
      warnUnlessNumber(light, "range", "light range must be a number; using none (the light reaches everywhere)");
      // tinygltf keeps an absent range as 0, so only the file tells them
      // apart. A range of 0 is refused, not read as "none": glTF says a given
      // range is above 0, and the two readings a broken exporter might mean
      // (reaches nowhere, reaches everywhere) give opposite pictures.
      if (const auto range = light.find("range"); range != light.end() && range->is_number() && !(*range > 0.0))
        fail(what + ": range " + numberText(range->get<double>()) + " must be above 0 (or left out for no limit)");
      if (*type != "spot") continue;
      const auto spot = light.find("spot");
      if (spot == light.end() || !spot->is_object()) fail(what + ": a spot light needs a \"spot\" object");
      warnUnlessNumber(*spot, "innerConeAngle", "spot light innerConeAngle must be a number; using 0");
      warnUnlessNumber(*spot, "outerConeAngle", "spot light outerConeAngle must be a number; using pi/4");
    }
  }

  // tinygltf drops a whole pbrMetallicRoughness whose baseColorFactor does
  // not have 4 numbers, textures and factors with it, and says nothing. The
  // rest of the block is read here instead, with the default base colour,
  // and the fallback is named in a warning.
  void restoreDroppedPbrBlocks(const json& document) {
    const auto materials = document.find("materials");
    if (materials == document.end()) return;
    for (std::size_t i = 0; i < materials->size() && i < model_.materials.size(); ++i) {
      const json& material = (*materials)[i];
      const auto pbr = material.find("pbrMetallicRoughness");
      if (pbr == material.end()) continue;
      const auto factor = pbr->find("baseColorFactor");
      if (factor == pbr->end() || factor->size() == 4) continue;
      warn("pbrMetallicRoughness.baseColorFactor must have 4 numbers; using (1, 1, 1, 1)",
           named("material", i, model_.materials[i].name));
      tinygltf::PbrMetallicRoughness& restored = model_.materials[i].pbrMetallicRoughness;
      restored.metallicFactor = pbr->value("metallicFactor", 1.0);
      restored.roughnessFactor = pbr->value("roughnessFactor", 1.0);
      const auto textureInfo = [&](const char* key, tinygltf::TextureInfo& info) {
        if (const auto found = pbr->find(key); found != pbr->end()) {
          info.index = found->value("index", -1);
          info.texCoord = found->value("texCoord", 0);
        }
      };
      textureInfo("baseColorTexture", restored.baseColorTexture);
      textureInfo("metallicRoughnessTexture", restored.metallicRoughnessTexture);
    }
  }

  void checkExtensions(const json& document) {
    static const std::vector<std::string> kSupported = {"KHR_lights_punctual", "KHR_materials_emissive_strength"};
    const auto names = [&](const char* key) {
      std::vector<std::string> list;
      if (const auto found = document.find(key); found != document.end())
        for (const json& name : *found) list.push_back(name.get<std::string>());
      return list;
    };
    const auto supported = [&](const std::string& name) {
      return std::find(kSupported.begin(), kSupported.end(), name) != kSupported.end();
    };
    std::string missing;
    for (const std::string& name : names("extensionsRequired"))
      if (!supported(name)) missing += (missing.empty() ? "" : ", ") + name;
    if (!missing.empty()) fail("requires glTF extensions this importer does not support: " + missing);
    for (const std::string& name : names("extensionsUsed"))
      if (!supported(name) &&
          std::find(ignoredExtensions_.begin(), ignoredExtensions_.end(), name) == ignoredExtensions_.end())
        ignoredExtensions_.push_back(name);
  }

  void checkVersion() const {
    const auto major = [](const std::string& version) { return version.substr(0, version.find('.')); };
    if (major(model_.asset.version) != "2")
      fail("glTF version " + model_.asset.version + " is not supported (only 2.x)");
    if (!model_.asset.minVersion.empty() && model_.asset.minVersion != "2.0")
      fail("the file needs glTF " + model_.asset.minVersion + "; this importer reads 2.0");
  }

  // ------------------------------------------------------------ buffers and accessors

  struct ByteRange {
    const unsigned char* data;
    std::size_t size;
  };

  ByteRange bufferView(int index, const std::string& what) const {
    if (index < 0 || std::size_t(index) >= model_.bufferViews.size())
      fail(what + ": bufferView " + std::to_string(index) + " does not exist");
    const tinygltf::BufferView& view = model_.bufferViews[std::size_t(index)];
    if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size())
      fail(what + ": bufferView " + std::to_string(index) + " names buffer " + std::to_string(view.buffer) +
           ", which does not exist");
    const std::vector<unsigned char>& data = model_.buffers[std::size_t(view.buffer)].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
      fail(what + ": bufferView " + std::to_string(index) + " (bytes " + std::to_string(view.byteOffset) + " to " +
           std::to_string(view.byteOffset + view.byteLength) + ") runs past the end of its buffer (" +
           std::to_string(data.size()) + " bytes)");
    return {data.data() + view.byteOffset, view.byteLength};
  }

  // Every component of accessor `index` (count * components values, sparse
  // substitution applied), after checking that the accessor has `format` and
  // that every byte it reads lies inside its bufferView.
  template <typename T>
  std::vector<T> readAccessor(int index, const AccessorFormat& format, const std::string& what) const {
    if (index < 0 || std::size_t(index) >= model_.accessors.size())
      fail(what + ": accessor " + std::to_string(index) + " does not exist");
    const tinygltf::Accessor& accessor = model_.accessors[std::size_t(index)];
    const std::string name = what + " (accessor " + std::to_string(index) + ")";
    if (accessor.type != format.type)
      fail(name + " is " + typeName(accessor.type) + ", expected " + typeName(format.type));
    if (std::find(format.componentTypes.begin(), format.componentTypes.end(), accessor.componentType) ==
        format.componentTypes.end()) {
      std::string allowed;
      for (int type : format.componentTypes)
        allowed += std::string(allowed.empty() ? "" : " or ") + componentTypeName(type);
      fail(name + " has components of type " + componentTypeName(accessor.componentType) + ", expected " + allowed);
    }
    const bool integer = accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT;
    if (integer && accessor.normalized != format.integersNormalized)
      fail(name + (format.integersNormalized ? " must be normalized" : " must not be normalized"));
    const bool normalized = integer && accessor.normalized;
    if (accessor.count == 0) fail(name + " has no elements");

    const std::size_t components = componentCount(accessor.type);
    const std::size_t bytesPerComponent = componentSize(accessor.componentType);
    const std::size_t elementSize = components * bytesPerComponent;
    std::vector<T> values;
    if (accessor.bufferView < 0) {
      if (accessor.count > kMaxVirtualElements - std::min(virtualElements_, kMaxVirtualElements))
        fail(name + " has too many elements without a bufferView: " + std::to_string(accessor.count) +
             (virtualElements_ ? " after " + std::to_string(virtualElements_) + " read before" : "") +
             ", more than the " + std::to_string(kMaxVirtualElements) +
             " that accessors without a bufferView (zeros but for their sparse values) may have in one file");
      virtualElements_ += accessor.count;
      values.assign(accessor.count * components, T(0));
    } else {
      const ByteRange view = bufferView(accessor.bufferView, name);
      const std::size_t declaredStride = model_.bufferViews[std::size_t(accessor.bufferView)].byteStride;
      if (declaredStride != 0 && (declaredStride < elementSize || declaredStride > 252))
        fail(name + ": byteStride " + std::to_string(declaredStride) + " is invalid for elements of " +
             std::to_string(elementSize) + " bytes");
      const std::size_t stride = declaredStride ? declaredStride : elementSize;
      // count <= view.size bounds the products below well inside 64 bits.
      if (accessor.count > view.size || accessor.byteOffset > view.size ||
          (accessor.count - 1) * stride + elementSize > view.size - accessor.byteOffset)
        fail(name + ": " + std::to_string(accessor.count) + " elements from byte offset " +
             std::to_string(accessor.byteOffset) + " do not fit in bufferView " + std::to_string(accessor.bufferView) +
             " (" + std::to_string(view.size) + " bytes)");
      values.resize(accessor.count * components);
      for (std::size_t element = 0; element < accessor.count; ++element) {
        const unsigned char* at = view.data + accessor.byteOffset + element * stride;
        for (std::size_t c = 0; c < components; ++c)
          values[element * components + c] =
              T(componentValue(at + c * bytesPerComponent, accessor.componentType, normalized));
      }
    }
    if (accessor.sparse.isSparse) applySparse(accessor, components, elementSize, normalized, values, name);
    return values;
  }

  template <typename T>
  void applySparse(const tinygltf::Accessor& accessor, std::size_t components, std::size_t elementSize, bool normalized,
                   std::vector<T>& values, const std::string& name) const {
    const auto& sparse = accessor.sparse;
    const std::size_t count = std::size_t(std::max(sparse.count, 0));
    if (count == 0 || count > accessor.count)
      fail(name + ": sparse count " + std::to_string(sparse.count) + " is not between 1 and the accessor's count");
    const int indexType = sparse.indices.componentType;
    if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(name + ": sparse indices have component type " + componentTypeName(indexType));
    const ByteRange indexView = bufferView(sparse.indices.bufferView, name + " sparse indices");
    const ByteRange valueView = bufferView(sparse.values.bufferView, name + " sparse values");
    const std::size_t indexOffset = std::size_t(std::max(sparse.indices.byteOffset, 0));
    const std::size_t valueOffset = std::size_t(std::max(sparse.values.byteOffset, 0));
    const std::size_t indexSize = componentSize(indexType);
    if (indexOffset > indexView.size || count > (indexView.size - indexOffset) / indexSize)
      fail(name + ": sparse indices do not fit in their bufferView");
    if (valueOffset > valueView.size || count > (valueView.size - valueOffset) / elementSize)
      fail(name + ": sparse values do not fit in their bufferView");
    const std::size_t bytesPerComponent = elementSize / components;
    std::size_t previous = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t target =
          std::size_t(componentValue(indexView.data + indexOffset + i * indexSize, indexType, false));
      if (target >= accessor.count || (i > 0 && target <= previous))
        fail(name + ": sparse index " + std::to_string(target) + " is out of range or not increasing");
      previous = target;
      const unsigned char* at = valueView.data + valueOffset + i * elementSize;
      for (std::size_t c = 0; c < components; ++c)
        values[target * components + c] =
            T(componentValue(at + c * bytesPerComponent, accessor.componentType, normalized));
    }
  }

  template <int N>
  std::vector<glm::vec<N, float>> readVectors(int index, const AccessorFormat& format, const std::string& what) const {
    const std::vector<float> flat = readAccessor<float>(index, format, what);
    std::vector<glm::vec<N, float>> vectors(flat.size() / N);
    std::memcpy(vectors.data(), flat.data(), vectors.size() * sizeof(vectors[0]));
    return vectors;
  }

  // ------------------------------------------------------------ materials and textures

  // The Scene::textures index for glTF texture `index` used as sRGB or linear
  // data, creating the texture (and a decode job for its image) on first use.
  int textureFor(int index, bool srgb, int texCoord, const std::string& what) {
    if (index < 0) return -1;
    if (std::size_t(index) >= model_.textures.size())
      fail(what + ": texture " + std::to_string(index) + " does not exist");
    if (texCoord != 0) warn("textures that use a texture coordinate set other than 0 are read with set 0", what);
    const tinygltf::Texture& gltfTexture = model_.textures[std::size_t(index)];
    // Samplers are not used (every texture repeats and filters trilinearly),
    // but an index to nothing is a broken file all the same.
    if (gltfTexture.sampler >= 0 && std::size_t(gltfTexture.sampler) >= model_.samplers.size())
      fail(what + ": texture " + std::to_string(index) + " uses sampler " + std::to_string(gltfTexture.sampler) +
           ", which does not exist");
    const int image = gltfTexture.source;
    if (image < 0) {
      warn("textures without a PNG or JPEG image are ignored", "texture " + std::to_string(index));
      return -1;
    }
    if (std::size_t(image) >= model_.images.size())
      fail(what + ": texture " + std::to_string(index) + " uses image " + std::to_string(image) +
           ", which does not exist");
    const int source = firstImageWithSameBytes(image);
    const auto key = std::make_pair(source, srgb);
    if (const auto found = textureIndex_.find(key); found != textureIndex_.end()) return found->second;

    const auto [jobIndex, isNew] = decodeJobOfImage_.try_emplace(source, decodeJobs_.size());
    if (isNew) decodeJobs_.push_back({.image = source, .name = imageName(source)});
    DecodeJob& job = decodeJobs_[jobIndex->second];
    const int textureIndex = int(scene_.textures.size());
    Texture texture;
    texture.name = job.name;
    texture.srgb = srgb;
    scene_.textures.push_back(std::move(texture));
    job.textures.push_back(textureIndex);
    textureIndex_[key] = textureIndex;
    return textureIndex;
  }

  // An image's encoded bytes: its file's or data: URI's, or its bufferView's
  // (checked); empty when its file could not be read.
  ByteRange encodedImage(int index) const {
    const tinygltf::Image& image = model_.images[std::size_t(index)];
    if (image.bufferView >= 0) return bufferView(image.bufferView, "texture image '" + imageName(index) + "'");
    return {image.image.data(), image.image.size()};
  }

  // The first image whose encoded bytes are this one's: a file named by
  // several URIs ("t.png", "./t.png", "t%2Epng") or stored twice becomes
  // one texture, decoded and held once (it was decoded once a URI: three
  // names of a 16384 x 16384 PNG took 4.2 GB). Compared by content rather
  // than by resolved path, which also catches the same bytes under two
  // names or in two bufferViews; the hash only narrows the candidates.
  int firstImageWithSameBytes(int index) {
    if (const auto found = firstWithSameBytes_.find(index); found != firstWithSameBytes_.end()) return found->second;
    const ByteRange bytes = encodedImage(index);
    int first = index;
    if (bytes.size > 0) {
      const std::size_t hash =
          std::hash<std::string_view>{}(std::string_view(reinterpret_cast<const char*>(bytes.data), bytes.size));
      std::vector<int>& candidates = imagesByHash_[hash];
      const auto same = std::find_if(candidates.begin(), candidates.end(), [&](int other) {
        const ByteRange otherBytes = encodedImage(other);
        return otherBytes.size == bytes.size && std::memcmp(otherBytes.data, bytes.data, bytes.size) == 0;
      });
      if (same != candidates.end())
        first = *same;
      else
        candidates.push_back(index);
    }
    firstWithSameBytes_[index] = first;
    return first;
  }

  std::string imageName(int index) const {
    const tinygltf::Image& image = model_.images[std::size_t(index)];
    if (image.bufferView < 0 && !image.uri.empty() && image.uri.rfind("data:", 0) != 0)
      return percentDecoded(image.uri);
    return "image " + std::to_string(index) + " of " + path_.filename().string();
  }

  void convertMaterials() {
    for (std::size_t i = 0; i < model_.materials.size(); ++i) {
      const tinygltf::Material& source = model_.materials[i];
      const std::string what = named("material", i, source.name);
      const auto vector = [&](const std::vector<double>& values, std::size_t size, const char* property) {
        if (values.size() != size) fail(what + ": " + property + " must have " + std::to_string(size) + " numbers");
        glm::vec4 result(0.0f);
        for (std::size_t c = 0; c < size; ++c) result[int(c)] = toFloat(values[c], what + ": " + property);
        return result;
      };
      // glTF gives these factors the range [0, 1] (and --material refuses
      // values outside it): a value outside is clamped, with a warning naming
      // the material and the field, rather than drawn as a surface that
      // reflects or emits more than glTF allows.
      const auto clamped = [&](auto value, const char* property, const char* note = "") {
        const auto inside = glm::clamp(value, decltype(value)(0.0f), decltype(value)(1.0f));
        if (inside != value) warn(std::string(property) + " outside [0, 1] was clamped into it" + note, what);
        return inside;
      };
      const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
      Material material;
      material.name = source.name;
      material.baseColorFactor =
          clamped(vector(pbr.baseColorFactor, 4, "baseColorFactor"), "pbrMetallicRoughness.baseColorFactor");
      material.metallicFactor = clamped(float(pbr.metallicFactor), "pbrMetallicRoughness.metallicFactor");
      material.roughnessFactor = clamped(float(pbr.roughnessFactor), "pbrMetallicRoughness.roughnessFactor");
      material.emissiveFactor = clamped(glm::vec3(vector(source.emissiveFactor, 3, "emissiveFactor")), "emissiveFactor",
                                        " (KHR_materials_emissive_strength makes emission brighter)");
      material.normalScale = toFloat(source.normalTexture.scale, what + ": normal texture scale");
      material.occlusionStrength = clamped(float(source.occlusionTexture.strength), "occlusionTexture.strength");
      if (source.alphaMode == "OPAQUE")
        material.alphaMode = AlphaMode::Opaque;
      else if (source.alphaMode == "MASK")
        material.alphaMode = AlphaMode::Mask;
      else if (source.alphaMode == "BLEND")
        material.alphaMode = AlphaMode::Blend;
      else
        fail(what + ": unknown alphaMode '" + source.alphaMode + "'");
      if (!(source.alphaCutoff >= 0.0)) fail(what + ": alphaCutoff must not be negative");
      material.alphaCutoff = toFloat(source.alphaCutoff, what + ": alphaCutoff");
      material.doubleSided = source.doubleSided;
      if (const auto found = source.extensions.find("KHR_materials_emissive_strength");
          found != source.extensions.end() && found->second.Has("emissiveStrength")) {
        const tinygltf::Value& strength = found->second.Get("emissiveStrength");
        if (!strength.IsNumber()) {
          warn("KHR_materials_emissive_strength emissiveStrength must be a number; using 1", what);
        } else {
          if (!(strength.GetNumberAsDouble() >= 0.0))
            fail(what + ": KHR_materials_emissive_strength needs a non-negative emissiveStrength");
          material.emissiveStrength = toFloat(strength.GetNumberAsDouble(), what + ": emissiveStrength");
        }
      }
      material.baseColorTexture = textureFor(pbr.baseColorTexture.index, true, pbr.baseColorTexture.texCoord, what);
      material.metallicRoughnessTexture =
          textureFor(pbr.metallicRoughnessTexture.index, false, pbr.metallicRoughnessTexture.texCoord, what);
      material.normalTexture = textureFor(source.normalTexture.index, false, source.normalTexture.texCoord, what);
      material.emissiveTexture = textureFor(source.emissiveTexture.index, true, source.emissiveTexture.texCoord, what);
      material.occlusionTexture =
          textureFor(source.occlusionTexture.index, false, source.occlusionTexture.texCoord, what);
      scene_.materials.push_back(std::move(material));
    }
  }

  // Decodes every image a material uses, a few at a time in parallel (on a
  // large scene this is most of the load time), once their headers have
  // shown that the memory this takes is within the limit for images.
  void decodeTextures() {
    for (DecodeJob& job : decodeJobs_) {
      const tinygltf::Image& image = model_.images[std::size_t(job.image)];
      if (image.bufferView < 0 && image.image.empty()) {
        const auto problem = imageFileProblems_.find(job.image);
        fail("cannot read texture image '" + job.name + "' (" +
             (problem != imageFileProblems_.end() ? problem->second : "file missing, empty or unreadable") + ")");
      }
    }
    std::vector<ByteRange> encoded;
    for (const DecodeJob& job : decodeJobs_) encoded.push_back(encodedImage(job.image));
    const unsigned threads =
        std::min<unsigned>({std::max(1u, std::thread::hardware_concurrency()), 8u, unsigned(decodeJobs_.size())});
    checkTextureMemory(encoded, threads);
    std::atomic<std::size_t> next{0};
    const auto work = [&] {
      for (std::size_t j = next++; j < decodeJobs_.size(); j = next++) decode(decodeJobs_[j], encoded[j]);
    };
    {
      std::vector<std::jthread> helpers;
      for (unsigned t = 1; t < threads; ++t) helpers.emplace_back(work);
      work();
    }
    for (DecodeJob& job : decodeJobs_) {
      if (!job.error.empty()) fail(job.error);
      for (std::size_t k = 0; k < job.textures.size(); ++k) {
        Texture& texture = scene_.textures[std::size_t(job.textures[k])];
        texture.width = job.width;
        texture.height = job.height;
        texture.rgba8 = k + 1 < job.textures.size() ? job.rgba8 : std::move(job.rgba8);
      }
    }
    // The encoded files are not needed once decoded.
    for (tinygltf::Image& image : model_.images) std::vector<unsigned char>().swap(image.image);
  }

  // The memory decoding the textures takes, from the images' headers, before
  // a pixel is decoded: a 261 KB PNG declares 16384 x 16384 pixels, 1 GiB as
  // RGBA8 (it took 2.1 GB). Counted: the encoded files tinygltf holds, every
  // texture's RGBA8 pixels (an image used as sRGB and as linear data is two
  // textures), and the decoder's buffers (io::rgba8Info) for as many of the
  // largest images as decode at once. Over io::kImageMemoryLimit is refused,
  // naming the largest texture.
  void checkTextureMemory(const std::vector<ByteRange>& encoded, unsigned threads) const {
    std::uint64_t held = 0;
    for (const tinygltf::Image& image : model_.images) held += image.image.size();
    std::vector<std::uint64_t> decoders;
    std::size_t largest = 0;
    std::vector<io::Rgba8Info> infos;
    for (std::size_t j = 0; j < decodeJobs_.size(); ++j) {
      const DecodeJob& job = decodeJobs_[j];
      const std::string what = "texture image '" + job.name + "'";
      if (const std::string problem = notPngOrJpeg(encoded[j], what); !problem.empty()) fail(problem);
      try {
        infos.push_back(io::rgba8Info(std::span(encoded[j].data, encoded[j].size), what, kMaxTextureSide));
      } catch (const io::ImageIoError& e) {
        fail(e.what());
      }
      held += infos.back().imageBytes() * job.textures.size();
      decoders.push_back(infos.back().decoderBytes);
      if (infos.back().imageBytes() > infos[largest].imageBytes()) largest = j;
    }
    std::sort(decoders.rbegin(), decoders.rend());
    for (std::size_t j = 0; j < decoders.size() && j < threads; ++j) held += decoders[j];
    if (held <= io::kImageMemoryLimit) return;
    const io::Rgba8Info& big = infos[largest];
    const std::size_t others = decodeJobs_.size() - 1;
    fail("decoding the texture image '" + decodeJobs_[largest].name + "' (" + std::to_string(big.width) + "x" +
         std::to_string(big.height) + ", " + io::memoryText(big.imageBytes()) + " as RGBA8)" +
         (others ? " and " + std::to_string(others) + (others == 1 ? " other" : " others") : "") + " needs about " +
         io::memoryText(held) + " of memory, more than the limit of " + io::memoryText(io::kImageMemoryLimit) +
         " for images (docs/reliability.md); the renderer draws a texture at most " +
         std::to_string(kDrawnTextureSide) + " pixels a side, so a copy shrunk to that draws the same");
  }

  // Why bytes that should be a texture cannot be one, or "".
  static std::string notPngOrJpeg(ByteRange bytes, const std::string& what) {
    const auto isPrefix = [&](std::string_view magic) {
      return bytes.size >= magic.size() && std::memcmp(bytes.data, magic.data(), magic.size()) == 0;
    };
    return isPrefix("\x89PNG") || isPrefix("\xFF\xD8\xFF") ? "" : what + " is not a PNG or JPEG file";
  }

  // Runs on worker threads: touches only its own job.
  static void decode(DecodeJob& job, ByteRange bytes) {
    const std::string what = "texture image '" + job.name + "'";
    try {
      io::Rgba8Image image = io::decodeRgba8(std::span(bytes.data, bytes.size), what, kMaxTextureSide);
      job.width = image.width;
      job.height = image.height;
      job.rgba8 = std::move(image.rgba8);
    } catch (const io::ImageIoError& e) {
      job.error = e.what();
    }
  }

  // ------------------------------------------------------------ meshes

  void convertMeshes() {
    bool needsDefaultMaterial = false;
    meshPrimitives_.resize(model_.meshes.size());
    for (std::size_t m = 0; m < model_.meshes.size(); ++m) {
      const tinygltf::Mesh& source = model_.meshes[m];
      const std::string meshName = named("mesh", m, source.name);
      const bool morphed = !source.weights.empty() || std::any_of(source.primitives.begin(), source.primitives.end(),
                                                                  [](const auto& p) { return !p.targets.empty(); });
      if (morphed) warn("morph targets are ignored", meshName);
      for (std::size_t p = 0; p < source.primitives.size(); ++p) {
        const tinygltf::Primitive& primitive = source.primitives[p];
        const std::string what = meshName + " primitive " + std::to_string(p);
        std::optional<Mesh> mesh = convertPrimitive(primitive, what);
        if (!mesh) continue;
        mesh->name = source.name;
        if (source.primitives.size() > 1) mesh->name.append("#").append(std::to_string(p));
        if (primitive.material >= 0 && std::size_t(primitive.material) >= model_.materials.size())
          fail(what + ": material " + std::to_string(primitive.material) + " does not exist");
        needsDefaultMaterial |= primitive.material < 0;
        mesh->material = primitive.material >= 0 ? primitive.material : int(model_.materials.size());
        meshPrimitives_[m].push_back(int(scene_.meshes.size()));
        scene_.meshes.push_back(std::move(*mesh));
      }
    }
    if (needsDefaultMaterial) {
      Material fallback;
      fallback.name = "default";
      scene_.materials.push_back(fallback);
    }
  }

  std::optional<Mesh> convertPrimitive(const tinygltf::Primitive& primitive, const std::string& what) {
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    Topology topology = Topology::Triangles;
    switch (mode) {
      case TINYGLTF_MODE_POINTS:
      case TINYGLTF_MODE_LINE:
      case TINYGLTF_MODE_LINE_LOOP:
      case TINYGLTF_MODE_LINE_STRIP:
        warn("point and line primitives are skipped (only triangles are drawn)", what);
        return std::nullopt;
      case TINYGLTF_MODE_TRIANGLES:
        break;
      case TINYGLTF_MODE_TRIANGLE_STRIP:
        topology = Topology::Strip;
        break;
      case TINYGLTF_MODE_TRIANGLE_FAN:
        topology = Topology::Fan;
        break;
      default:
        fail(what + ": unknown primitive mode " + std::to_string(mode));
    }
    const auto attribute = [&](const char* name) {
      const auto found = primitive.attributes.find(name);
      return found == primitive.attributes.end() ? -1 : found->second;
    };
    if (attribute("POSITION") < 0) {
      warn("primitives without POSITION are skipped", what);
      return std::nullopt;
    }
    if (attribute("COLOR_0") >= 0) warn("vertex colours are ignored", what);

    Mesh mesh;
    mesh.positions = readVectors<3>(attribute("POSITION"), kVec3Floats, what + " POSITION");
    const std::size_t vertexCount = mesh.positions.size();
    const auto requireVertexCount = [&](std::size_t count, const char* name) {
      if (count != vertexCount)
        fail(what + ": " + name + " has " + std::to_string(count) + " elements but POSITION has " +
             std::to_string(vertexCount));
    };
    for (std::size_t v = 0; v < vertexCount; ++v)
      if (!std::isfinite(mesh.positions[v].x) || !std::isfinite(mesh.positions[v].y) ||
          !std::isfinite(mesh.positions[v].z))
        fail(what + ": POSITION of vertex " + std::to_string(v) + " is NaN or infinite");
    const bool hasNormals = attribute("NORMAL") >= 0;
    if (hasNormals) {
      mesh.normals = readVectors<3>(attribute("NORMAL"), kVec3Floats, what + " NORMAL");
      requireVertexCount(mesh.normals.size(), "NORMAL");
      // glTF ignores tangents of a primitive without normals.
      if (attribute("TANGENT") >= 0) {
        mesh.tangents = readVectors<4>(attribute("TANGENT"), kVec4Floats, what + " TANGENT");
        requireVertexCount(mesh.tangents.size(), "TANGENT");
      }
    }
    if (attribute("TEXCOORD_0") >= 0) {
      mesh.texcoords = readVectors<2>(attribute("TEXCOORD_0"), kTexcoords, what + " TEXCOORD_0");
      requireVertexCount(mesh.texcoords.size(), "TEXCOORD_0");
      for (glm::vec2& uv : mesh.texcoords)
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) fail(what + ": TEXCOORD_0 has a NaN or infinite value");
    } else {
      mesh.texcoords.assign(vertexCount, glm::vec2(0.0f));
    }

    std::vector<std::uint32_t> vertices;
    if (primitive.indices >= 0) {
      vertices = readAccessor<std::uint32_t>(primitive.indices, kIndices, what + " indices");
      for (std::size_t i = 0; i < vertices.size(); ++i)
        if (vertices[i] >= vertexCount)
          fail(what + ": index " + std::to_string(vertices[i]) + " (at position " + std::to_string(i) +
               ") is out of range for " + std::to_string(vertexCount) + " vertices");
    } else {
      vertices.resize(vertexCount);
      for (std::size_t v = 0; v < vertexCount; ++v) vertices[v] = std::uint32_t(v);
    }
    mesh.indices = triangleList(vertices, topology, what);
    if (mesh.indices.empty()) {
      warn("primitives without a single triangle are skipped", what);
      return std::nullopt;
    }

    if (!hasNormals) {
      generateFlatNormals(mesh);
    } else if (normalizeNormals(mesh) > 0) {
      warn("normals that were zero, not finite or not unit length were repaired", what);
    }
    if (mesh.tangents.empty())
      generateTangents(mesh);
    else if (orthonormalizeTangents(mesh) > 0)
      warn("degenerate tangents were replaced", what);
    return mesh;
  }

  // glTF vertex order for each topology (spec 3.7.2.1); strips and fans drop
  // degenerate triangles, which there only stitch runs together.
  std::vector<std::uint32_t> triangleList(const std::vector<std::uint32_t>& v, Topology topology,
                                          const std::string& what) {
    std::vector<std::uint32_t> list;
    const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, bool dropDegenerate) {
      if (dropDegenerate && (a == b || b == c || a == c)) return;
      list.insert(list.end(), {a, b, c});
    };
    switch (topology) {
      case Topology::Triangles:
        if (v.size() % 3 != 0) warn("an incomplete last triangle was dropped (vertex count not a multiple of 3)", what);
        for (std::size_t i = 0; i + 2 < v.size(); i += 3) add(v[i], v[i + 1], v[i + 2], false);
        break;
      case Topology::Strip:
        for (std::size_t i = 0; i + 2 < v.size(); ++i)
          if (i % 2 == 0)
            add(v[i], v[i + 1], v[i + 2], true);
          else
            add(v[i], v[i + 2], v[i + 1], true);
        break;
      case Topology::Fan:
        for (std::size_t i = 0; i + 2 < v.size(); ++i) add(v[i + 1], v[i + 2], v[0], true);
        break;
    }
    return list;
  }

  // ------------------------------------------------------------ cameras and lights

  void convertCameras() {
    cameraIndex_.assign(model_.cameras.size(), -1);
    for (std::size_t i = 0; i < model_.cameras.size(); ++i) {
      const tinygltf::Camera& camera = model_.cameras[i];
      const std::string what = named("camera", i, camera.name);
      if (camera.type == "orthographic") {
        warn("orthographic cameras are skipped", what);
        continue;
      }
      if (camera.type != "perspective") fail(what + ": unknown camera type '" + camera.type + "'");
      const double yfov = camera.perspective.yfov;
      const double znear = camera.perspective.znear;
      // Checked as the float it is kept as: 3.14159265 is below pi, but its float is not.
      if (!(yfov > 0.0 && float(yfov) < glm::pi<float>()))
        fail(what + ": yfov " + numberText(yfov) + " must be between 0 and pi (exclusive, as a 32-bit float)");
      if (!(znear > 0.0)) fail(what + ": znear must be positive");
      cameraIndex_[i] = int(scene_.cameras.size());
      scene_.cameras.push_back({camera.name, float(yfov), toFloat(znear, what + ": znear")});
    }
  }

  void convertLights() {
    for (std::size_t i = 0; i < model_.lights.size(); ++i) {
      const tinygltf::Light& source = model_.lights[i];
      const std::string what = named("light", i, source.name);
      Light light;
      light.name = source.name;
      if (source.type == "directional")
        light.type = LightType::Directional;
      else if (source.type == "point")
        light.type = LightType::Point;
      else if (source.type == "spot")
        light.type = LightType::Spot;
      else
        fail(what + ": unknown light type '" + source.type + "'");
      if (!source.color.empty()) {
        if (source.color.size() != 3) fail(what + ": color must have 3 numbers");
        for (int c = 0; c < 3; ++c) {
          if (!(source.color[std::size_t(c)] >= 0.0)) fail(what + ": color must not be negative");
          light.color[c] = toFloat(source.color[std::size_t(c)], what + ": color");
        }
      }
      if (!(source.intensity >= 0.0)) fail(what + ": intensity must not be negative");
      if (!(source.range >= 0.0)) fail(what + ": range must be positive");
      light.intensity = toFloat(source.intensity, what + ": intensity");
      light.range = toFloat(source.range, what + ": range");
      if (light.type == LightType::Spot) {
        const double inner = source.spot.innerConeAngle;
        const double outer = source.spot.outerConeAngle;
        if (!(inner >= 0.0 && inner < outer && outer <= glm::half_pi<double>() + 1e-6))
          fail(what + ": spot cone angles must satisfy 0 <= inner < outer <= pi/2");
        light.innerConeAngle = float(inner);
        light.outerConeAngle = float(outer);
      }
      scene_.lights.push_back(light);
    }
  }

  // ------------------------------------------------------------ nodes

  void convertNodes() {
    scene_.nodes.resize(model_.nodes.size());
    for (std::size_t i = 0; i < model_.nodes.size(); ++i) {
      const tinygltf::Node& source = model_.nodes[i];
      const std::string what = named("node", i, source.name);
      Node& node = scene_.nodes[i];
      node.name = source.name;
      node.local = localTransform(source, what);
      for (int child : source.children) {
        if (child < 0 || std::size_t(child) >= model_.nodes.size())
          fail(what + ": child " + std::to_string(child) + " does not exist");
        int& parent = scene_.nodes[std::size_t(child)].parent;
        if (parent == int(i)) fail(what + ": lists child " + std::to_string(child) + " twice");
        if (parent >= 0) fail("node " + std::to_string(child) + " has more than one parent");
        parent = int(i);
        node.children.push_back(child);
      }
      if (source.mesh >= 0) {
        if (std::size_t(source.mesh) >= model_.meshes.size())
          fail(what + ": mesh " + std::to_string(source.mesh) + " does not exist");
        node.meshes = meshPrimitives_[std::size_t(source.mesh)];
      }
      if (source.camera >= 0) {
        if (std::size_t(source.camera) >= model_.cameras.size())
          fail(what + ": camera " + std::to_string(source.camera) + " does not exist");
        node.camera = cameraIndex_[std::size_t(source.camera)];
      }
      if (const auto found = source.extensions.find("KHR_lights_punctual"); found != source.extensions.end()) {
        const tinygltf::Value& light = found->second.Get("light");
        if (!light.IsInt() || light.GetNumberAsInt() < 0 || std::size_t(light.GetNumberAsInt()) >= scene_.lights.size())
          fail(what + ": KHR_lights_punctual names a light that does not exist");
        node.light = light.GetNumberAsInt();
      }
      if (source.skin >= 0) {
        // Unused, but an index to nothing is a broken file all the same.
        if (std::size_t(source.skin) >= model_.skins.size())
          fail(what + ": skin " + std::to_string(source.skin) + " does not exist");
        warn("skins are ignored (skinned meshes are drawn in their bind pose)", what);
      }
      if (!source.weights.empty()) warn("morph targets are ignored", what);
    }
  }

  Transform localTransform(const tinygltf::Node& source, const std::string& what) {
    Transform local;
    if (!source.matrix.empty()) {
      if (source.matrix.size() != 16) fail(what + ": matrix must have 16 numbers");
      glm::mat4 matrix;
      for (int i = 0; i < 16; ++i)
        glm::value_ptr(matrix)[i] = toFloat(source.matrix[std::size_t(i)], what + ": matrix");
      return decomposed(matrix, what);
    }
    if (!source.translation.empty()) {
      if (source.translation.size() != 3) fail(what + ": translation must have 3 numbers");
      for (int c = 0; c < 3; ++c)
        local.translation[c] = toFloat(source.translation[std::size_t(c)], what + ": translation");
    }
    if (!source.scale.empty()) {
      if (source.scale.size() != 3) fail(what + ": scale must have 3 numbers");
      for (int c = 0; c < 3; ++c) local.scale[c] = toFloat(source.scale[std::size_t(c)], what + ": scale");
    }
    if (!source.rotation.empty()) {
      if (source.rotation.size() != 4) fail(what + ": rotation must have 4 numbers");
      const glm::vec4 xyzw(source.rotation[0], source.rotation[1], source.rotation[2], source.rotation[3]);
      local.rotation = unitQuaternion(xyzw, what + ": rotation");
    }
    return local;
  }

  glm::quat unitQuaternion(const glm::vec4& xyzw, const std::string& what) const {
    const float length = glm::length(xyzw);
    if (!std::isfinite(length) || length < 1e-6f) fail(what + " is not a unit quaternion");
    const glm::vec4 unit = xyzw / length;
    return glm::quat(unit.w, unit.x, unit.y, unit.z);
  }

  // Splits a node matrix into translation * rotation * scale. A mirroring
  // matrix gets a negative x scale; an axis scaled to zero gets its rotation
  // from the other two. Shear cannot be represented: it is dropped, warned about.
  Transform decomposed(const glm::mat4& matrix, const std::string& what) {
    Transform transform;
    transform.translation = glm::vec3(matrix[3]);
    glm::vec3 axes[3] = {glm::vec3(matrix[0]), glm::vec3(matrix[1]), glm::vec3(matrix[2])};
    const float largest = std::max({glm::length(axes[0]), glm::length(axes[1]), glm::length(axes[2])});
    int degenerate = 0;
    for (int a = 0; a < 3; ++a) {
      transform.scale[a] = glm::length(axes[a]);
      if (!(transform.scale[a] > 1e-7f * largest)) {
        transform.scale[a] = 0.0f;
        ++degenerate;
      } else {
        axes[a] /= transform.scale[a];
      }
    }
    if (glm::determinant(glm::mat3(axes[0], axes[1], axes[2])) < 0.0f) {
      transform.scale.x = -transform.scale.x;
      axes[0] = -axes[0];
    }
    if (!std::isfinite(largest)) fail(what + ": matrix is too large to decompose");
    if (degenerate == 1) {
      const int zero = transform.scale.x == 0.0f ? 0 : transform.scale.y == 0.0f ? 1 : 2;
      const glm::vec3 normal = glm::cross(axes[(zero + 1) % 3], axes[(zero + 2) % 3]);
      const float length = glm::length(normal);
      if (length > 1e-6f)
        axes[zero] = normal / length;
      else
        degenerate = 2;
    }
    // With two or three axes scaled to zero the rotation does not matter.
    if (degenerate <= 1) transform.rotation = glm::normalize(glm::quat_cast(glm::mat3(axes[0], axes[1], axes[2])));
    const glm::mat4 rebuilt = transform.matrix();
    float error = 0.0f;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) error = std::max(error, std::abs(rebuilt[c][r] - matrix[c][r]));
    if (!(error <= 1e-3f * std::max(1.0f, largest)))
      warn("node matrices with shear or projection were approximated by translation, rotation and scale", what);
    return transform;
  }

  // ------------------------------------------------------------ animations

  void convertAnimations() {
    for (std::size_t a = 0; a < model_.animations.size(); ++a) {
      const tinygltf::Animation& source = model_.animations[a];
      Animation animation;
      animation.name = source.name.empty() ? "animation " + std::to_string(a) : source.name;
      for (std::size_t c = 0; c < source.channels.size(); ++c) {
        const tinygltf::AnimationChannel& channel = source.channels[c];
        const std::string what = "animation '" + animation.name + "' channel " + std::to_string(c);
        if (channel.target_node < 0) {
          warn("animation channels without a target node are ignored", what);
          continue;
        }
        if (std::size_t(channel.target_node) >= model_.nodes.size())
          fail(what + ": node " + std::to_string(channel.target_node) + " does not exist");
        if (channel.sampler < 0 || std::size_t(channel.sampler) >= source.samplers.size())
          fail(what + ": sampler " + std::to_string(channel.sampler) + " does not exist");
        AnimationChannel out;
        out.node = channel.target_node;
        if (channel.target_path == "translation")
          out.property = AnimatedProperty::Translation;
        else if (channel.target_path == "rotation")
          out.property = AnimatedProperty::Rotation;
        else if (channel.target_path == "scale")
          out.property = AnimatedProperty::Scale;
        else {
          warn("animations of morph target weights and other properties are ignored", what);
          continue;
        }
        const tinygltf::AnimationSampler& sampler = source.samplers[std::size_t(channel.sampler)];
        if (sampler.interpolation == "LINEAR")
          out.interpolation = Interpolation::Linear;
        else if (sampler.interpolation == "STEP")
          out.interpolation = Interpolation::Step;
        else if (sampler.interpolation == "CUBICSPLINE")
          out.interpolation = Interpolation::CubicSpline;
        else
          fail(what + ": unknown interpolation '" + sampler.interpolation + "'");
        out.times = readAccessor<float>(sampler.input, kScalarFloats, what + " input");
        const bool rotation = out.property == AnimatedProperty::Rotation;
        if (rotation) {
          for (const glm::vec4& v : readVectors<4>(sampler.output, kRotationKeys, what + " output"))
            out.values.push_back(v);
        } else {
          for (const glm::vec3& v : readVectors<3>(sampler.output, kVec3Floats, what + " output"))
            out.values.push_back(glm::vec4(v, 0.0f));
        }
        const std::size_t perKey = out.interpolation == Interpolation::CubicSpline ? 3 : 1;
        if (out.values.size() != out.times.size() * perKey)
          fail(what + ": " + std::to_string(out.times.size()) + " key times but " + std::to_string(out.values.size()) +
               " values (expected " + std::to_string(out.times.size() * perKey) + ")");
        if (rotation)
          // Key values (not cubic-spline tangents) must be unit quaternions.
          for (std::size_t k = perKey / 3; k < out.values.size(); k += perKey) {
            const glm::quat q = unitQuaternion(out.values[k], what + ": key " + std::to_string(k / perKey));
            out.values[k] = glm::vec4(q.x, q.y, q.z, q.w);
          }
        animation.channels.push_back(std::move(out));
      }
      if (!animation.channels.empty()) scene_.animations.push_back(std::move(animation));
    }
  }

  // ------------------------------------------------------------ the displayed scene

  void chooseRoots() {
    int chosen = -1;
    if (model_.defaultScene >= 0) {
      if (std::size_t(model_.defaultScene) >= model_.scenes.size())
        fail("the default scene " + std::to_string(model_.defaultScene) + " does not exist");
      chosen = model_.defaultScene;
    } else if (!model_.scenes.empty()) {
      chosen = 0;
    }
    if (chosen < 0) {
      for (std::size_t i = 0; i < scene_.nodes.size(); ++i)
        if (scene_.nodes[i].parent < 0) scene_.roots.push_back(int(i));
      return;
    }
    // glTF's scene.nodes holds unique items; a node drawn twice over itself
    // is a broken file, refused (in one pass, however long the list).
    std::vector<bool> listed(scene_.nodes.size(), false);
    for (int node : model_.scenes[std::size_t(chosen)].nodes) {
      if (node < 0 || std::size_t(node) >= scene_.nodes.size())
        fail("scene " + std::to_string(chosen) + ": node " + std::to_string(node) + " does not exist");
      if (listed[std::size_t(node)])
        fail("scene " + std::to_string(chosen) + ": lists node " + std::to_string(node) + " more than once");
      listed[std::size_t(node)] = true;
      scene_.roots.push_back(node);
    }
  }

  const fs::path path_;
  const GltfImportOptions& options_;
  tinygltf::Model model_;
  Scene scene_;
  std::vector<std::string> ignoredExtensions_;
  struct Warning {
    std::string kind;
    std::vector<std::string> subjects;      // in order of appearance
    std::unordered_set<std::string> named;  // the same, to find repeats at once on large scenes
  };
  std::vector<Warning> warnings_;                     // in order of appearance
  std::vector<std::vector<int>> meshPrimitives_;      // glTF mesh -> Scene::meshes (one per triangle primitive)
  std::vector<int> cameraIndex_;                      // glTF camera -> Scene::cameras, -1 if skipped
  std::map<std::pair<int, bool>, int> textureIndex_;  // (glTF image, sRGB) -> Scene::textures
  std::vector<DecodeJob> decodeJobs_;                 // one per image that materials use
  std::map<int, std::size_t> decodeJobOfImage_;       // glTF image -> decodeJobs_
  std::map<int, std::string> imageFileProblems_;      // glTF image -> why its file could not be read
  std::map<int, int> firstWithSameBytes_;             // glTF image -> the first image with the same encoded bytes
  std::unordered_map<std::size_t, std::vector<int>> imagesByHash_;  // hash of encoded bytes -> images
  mutable std::size_t virtualElements_ = 0;  // elements of accessors without a bufferView read so far
};

}  // namespace

Scene loadGltf(const std::filesystem::path& path, const GltfImportOptions& options) {
  return Importer(path, options).run();
}

}  // namespace bounce::scene
