// Normal and tangent generation. Everything here must stay finite whatever the
// input: meshes come from files, and a NaN that slips into a vertex attribute
// poisons a whole BVH and every frame after it.
#include "scene/tangents.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace bounce::scene {
namespace {

bool isFinite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// v / |v|, or `fallback` when v is zero or not finite. Dividing by the largest
// component first keeps tiny and huge vectors from underflowing or
// overflowing in the length computation.
glm::vec3 normalizeOr(const glm::vec3& v, const glm::vec3& fallback) {
  const float largest = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(largest > 0.0f) || !std::isfinite(largest)) return fallback;
  const glm::vec3 scaled = v / largest;
  return scaled / std::sqrt(glm::dot(scaled, scaled));
}

// A unit vector perpendicular to the unit vector n that varies smoothly with n
// (Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017), so
// flat regions without usable texcoords get consistent tangents.
glm::vec3 arbitraryTangent(const glm::vec3& n) {
  if (!isFinite(n)) return {1.0f, 0.0f, 0.0f};
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const glm::vec3 tangent{1.0f + sign * n.x * n.x * a, sign * n.x * n.y * a, -sign * n.x};
  return normalizeOr(tangent, {1.0f, 0.0f, 0.0f});
}

// The part of `tangent` perpendicular to `normal`, unit length, or nothing
// usable (zero vector) when the tangent is degenerate or along the normal.
glm::vec3 perpendicularPart(const glm::vec3& tangent, const glm::vec3& normal) {
  const glm::vec3 direction = normalizeOr(tangent, glm::vec3(0.0f));
  const glm::vec3 perpendicular = direction - normal * glm::dot(normal, direction);
  if (!(glm::dot(perpendicular, perpendicular) > 1e-8f)) return glm::vec3(0.0f);
  return normalizeOr(perpendicular, glm::vec3(0.0f));
}

void requireTriangleList(const Mesh& mesh, const char* function) {
  const auto fail = [&](const std::string& reason) {
    throw std::invalid_argument(std::string(function) + ": mesh '" + mesh.name + "': " + reason);
  };
  if (mesh.indices.size() % 3 != 0) fail("index count is not a multiple of 3");
  for (std::uint32_t index : mesh.indices)
    if (index >= mesh.positions.size()) fail("index " + std::to_string(index) + " out of range");
}

}  // namespace

void generateFlatNormals(Mesh& mesh) {
  requireTriangleList(mesh, "generateFlatNormals");
  const std::size_t vertexCount = mesh.positions.size();
  const bool hasTexcoords = mesh.texcoords.size() == vertexCount;
  const bool hasTangents = mesh.tangents.size() == vertexCount;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> texcoords;
  std::vector<glm::vec4> tangents;
  positions.reserve(mesh.indices.size());
  normals.reserve(mesh.indices.size());
  for (std::size_t first = 0; first < mesh.indices.size(); first += 3) {
    const std::uint32_t* corner = &mesh.indices[first];
    const glm::vec3& p0 = mesh.positions[corner[0]];
    const glm::vec3 normal =
        normalizeOr(glm::cross(mesh.positions[corner[1]] - p0, mesh.positions[corner[2]] - p0), {0.0f, 0.0f, 1.0f});
    for (int k = 0; k < 3; ++k) {
      positions.push_back(mesh.positions[corner[k]]);
      normals.push_back(normal);
      if (hasTexcoords) texcoords.push_back(mesh.texcoords[corner[k]]);
      if (hasTangents) tangents.push_back(mesh.tangents[corner[k]]);
    }
  }
  mesh.positions = std::move(positions);
  mesh.normals = std::move(normals);
  mesh.texcoords = std::move(texcoords);
  mesh.tangents = std::move(tangents);
  for (std::size_t i = 0; i < mesh.indices.size(); ++i) mesh.indices[i] = std::uint32_t(i);
}

void generateTangents(Mesh& mesh) {
  requireTriangleList(mesh, "generateTangents");
  const std::size_t originalVertexCount = mesh.positions.size();
  if (mesh.normals.size() != originalVertexCount)
    throw std::invalid_argument("generateTangents: mesh '" + mesh.name + "' needs one normal per vertex");
  const bool hasTexcoords = mesh.texcoords.size() == originalVertexCount;

  // Summed (area-weighted) tangent and bitangent directions per vertex, kept
  // apart for right-handed (0) and mirrored (1) triangles so the two sides of a
  // mirrored UV seam do not cancel each other out.
  struct Frame {
    glm::vec3 tangent{0.0f};
    glm::vec3 bitangent{0.0f};
    bool used = false;
  };
  std::vector<std::array<Frame, 2>> frames(originalVertexCount);
  const std::size_t triangleCount = mesh.indices.size() / 3;
  std::vector<std::uint8_t> mirrored(triangleCount, 0);
  for (std::size_t triangle = 0; hasTexcoords && triangle < triangleCount; ++triangle) {
    const std::uint32_t* corner = &mesh.indices[triangle * 3];
    const glm::vec3 edge1 = mesh.positions[corner[1]] - mesh.positions[corner[0]];
    const glm::vec3 edge2 = mesh.positions[corner[2]] - mesh.positions[corner[0]];
    // v is negated so the bitangent follows the upright image (see tangents.h).
    const auto uv = [&](int k) { return glm::vec2(mesh.texcoords[corner[k]].x, -mesh.texcoords[corner[k]].y); };
    const glm::vec2 duv1 = uv(1) - uv(0);
    const glm::vec2 duv2 = uv(2) - uv(0);
    const float determinant = duv1.x * duv2.y - duv2.x * duv1.y;
    const glm::vec3 faceNormal = glm::cross(edge1, edge2);
    const float doubleArea = glm::length(faceNormal);
    if (!std::isfinite(determinant) || determinant == 0.0f || !std::isfinite(doubleArea) || doubleArea == 0.0f)
      continue;
    const glm::vec3 tangent = normalizeOr((edge1 * duv2.y - edge2 * duv1.y) / determinant, glm::vec3(0.0f));
    const glm::vec3 bitangent = normalizeOr((edge2 * duv1.x - edge1 * duv2.x) / determinant, glm::vec3(0.0f));
    if (tangent == glm::vec3(0.0f) || bitangent == glm::vec3(0.0f)) continue;
    const int side = glm::dot(glm::cross(tangent, bitangent), faceNormal) < 0.0f ? 1 : 0;
    mirrored[triangle] = std::uint8_t(side);
    for (int k = 0; k < 3; ++k) {
      Frame& frame = frames[corner[k]][side];
      frame.tangent += tangent * doubleArea;
      frame.bitangent += bitangent * doubleArea;
      frame.used = true;
    }
  }

  // Split vertices used by both handednesses: the copy takes the mirrored side.
  struct Choice {
    const Frame* frame = nullptr;
    float handedness = 1.0f;
  };
  std::vector<Choice> chosen(originalVertexCount);
  std::vector<std::uint32_t> mirroredCopy(originalVertexCount, UINT32_MAX);
  for (std::size_t v = 0; v < originalVertexCount; ++v) {
    const std::array<Frame, 2>& sides = frames[v];
    if (sides[0].used)
      chosen[v] = {&sides[0], 1.0f};
    else if (sides[1].used)
      chosen[v] = {&sides[1], -1.0f};
    if (!sides[0].used || !sides[1].used) continue;
    mirroredCopy[v] = std::uint32_t(mesh.positions.size());
    mesh.positions.push_back(mesh.positions[v]);
    mesh.normals.push_back(mesh.normals[v]);
    mesh.texcoords.push_back(mesh.texcoords[v]);
    chosen.push_back({&sides[1], -1.0f});
  }
  for (std::size_t triangle = 0; triangle < triangleCount; ++triangle) {
    if (!mirrored[triangle]) continue;
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& index = mesh.indices[triangle * 3 + k];
      if (mirroredCopy[index] != UINT32_MAX) index = mirroredCopy[index];
    }
  }

  mesh.tangents.resize(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3& normal = mesh.normals[v];
    const Choice& choice = chosen[v];
    glm::vec3 tangent = choice.frame ? perpendicularPart(choice.frame->tangent, normal) : glm::vec3(0.0f);
    float handedness = choice.handedness;
    if (tangent == glm::vec3(0.0f)) {
      tangent = arbitraryTangent(normal);
    } else {
      // The sign that makes cross(normal, tangent) * w follow the summed
      // bitangent, which differs from the triangles' handedness only where the
      // vertex normal points away from the faces.
      const float along = glm::dot(glm::cross(normal, tangent), choice.frame->bitangent);
      if (along != 0.0f && std::isfinite(along)) handedness = along < 0.0f ? -1.0f : 1.0f;
    }
    mesh.tangents[v] = glm::vec4(tangent, handedness);
  }
}

std::size_t normalizeNormals(Mesh& mesh) {
  std::size_t changed = 0;
  std::vector<std::uint8_t> degenerate(mesh.normals.size(), 0);
  bool anyDegenerate = false;
  for (std::size_t v = 0; v < mesh.normals.size(); ++v) {
    glm::vec3& normal = mesh.normals[v];
    const float length = glm::length(normal);
    if (!std::isfinite(length) || length < 1e-6f) {
      degenerate[v] = 1;
      anyDegenerate = true;
      continue;
    }
    if (std::abs(length - 1.0f) > 1e-3f) ++changed;
    normal = normalizeOr(normal, {0.0f, 0.0f, 1.0f});
  }
  if (!anyDegenerate) return changed;

  std::vector<glm::vec3> faceSum(mesh.normals.size(), glm::vec3(0.0f));
  for (std::size_t first = 0; first + 2 < mesh.indices.size(); first += 3) {
    const std::uint32_t* corner = &mesh.indices[first];
    if (std::max({corner[0], corner[1], corner[2]}) >= std::min(mesh.positions.size(), mesh.normals.size())) continue;
    const glm::vec3& p0 = mesh.positions[corner[0]];
    const glm::vec3 areaNormal = glm::cross(mesh.positions[corner[1]] - p0, mesh.positions[corner[2]] - p0);
    if (!isFinite(areaNormal)) continue;
    for (int k = 0; k < 3; ++k) faceSum[corner[k]] += areaNormal;
  }
  for (std::size_t v = 0; v < mesh.normals.size(); ++v) {
    if (!degenerate[v]) continue;
    mesh.normals[v] = normalizeOr(faceSum[v], {0.0f, 0.0f, 1.0f});
    ++changed;
  }
  return changed;
}

std::size_t orthonormalizeTangents(Mesh& mesh) {
  std::size_t replaced = 0;
  const std::size_t count = std::min(mesh.tangents.size(), mesh.normals.size());
  for (std::size_t v = 0; v < count; ++v) {
    glm::vec4& tangent = mesh.tangents[v];
    glm::vec3 direction = perpendicularPart(glm::vec3(tangent), mesh.normals[v]);
    if (direction == glm::vec3(0.0f)) {
      direction = arbitraryTangent(mesh.normals[v]);
      ++replaced;
    }
    tangent = glm::vec4(direction, tangent.w < 0.0f ? -1.0f : 1.0f);
  }
  return replaced;
}

}  // namespace bounce::scene
