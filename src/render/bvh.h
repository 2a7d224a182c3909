// Bounding volume hierarchies for ray casting: a generic binned-SAH builder,
// and the two-level scene BVH the renderer traces on the GPU (one BLAS per
// mesh, built once in object space; one TLAS over the instances, rebuilt
// every frame because nodes animate). Everything here is CPU-side; the data
// is laid out exactly as render/bvh_trace.glsl reads it, and the CPU runs
// the shader's own traversal (render/bvh_traverse.glsl) so tests can check
// it against brute force.
// Layout, build and traversal: docs/bvh.md.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "render/bvh_types.glsl"
#include "scene/scene.h"

namespace bounce::render {

using shared::BvhHit;
using shared::BvhInstance;
using shared::BvhRay;
using shared::BvhWideNode;

static_assert(sizeof(BvhWideNode) == 80, "BvhWideNode must match its std430 layout");
static_assert(sizeof(BvhInstance) == 112, "BvhInstance must match its std430 layout");

struct Aabb {
  glm::vec3 min{std::numeric_limits<float>::max()};
  glm::vec3 max{-std::numeric_limits<float>::max()};

  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void extend(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void extend(const Aabb& b) {
    min = glm::min(min, b.min);
    max = glm::max(max, b.max);
  }
  glm::vec3 centroid() const { return (min + max) * 0.5f; }
  // Half the surface area: the SAH only compares areas, so the factor 2 is dropped. 0 when empty.
  float halfArea() const {
    if (empty()) return 0.0f;
    const glm::vec3 e = max - min;
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
  bool contains(const Aabb& b) const {
    return glm::all(glm::lessThanEqual(min, b.min)) && glm::all(glm::greaterThanEqual(max, b.max));
  }
};

struct BvhBuildOptions {
  std::uint32_t binCount = 16;                         // SAH bins per axis (all three axes are tried)
  std::uint32_t maxLeafSize = shared::kBvhMaxLeafSize;  // leaves hold 1..maxLeafSize items; the SAH decides below that
  std::uint32_t maxDepth = shared::kBvhMaxDepth;  // deepest leaf (root = 0); median splits keep to it
  float traversalCost = 1.0f;                     // SAH cost of visiting an interior node ...
  float intersectionCost = 1.0f;                  // ... relative to intersecting one item
};

// A node of the binary tree buildBvh makes. count == 0: interior node whose
// children are leftFirst and leftFirst + 1; count > 0: leaf of leaf slots
// leftFirst .. leftFirst + count - 1. Bounds are the exact union of the
// children's or the items'. (The GPU reads BvhWideNodes, collapsed from
// these by SceneBvh: each holds up to eight children's quantised boxes.)
struct BvhBuildNode {
  glm::vec3 boundsMin{0.0f};
  std::uint32_t leftFirst = 0;
  glm::vec3 boundsMax{0.0f};
  std::uint32_t count = 0;
};

// A flattened binary BVH. Leaves address items through itemOrder: leaf slot
// i holds item itemOrder[i]. Zero items give no nodes at all.
struct Bvh {
  std::vector<BvhBuildNode> nodes;       // root at 0; children of an interior node are adjacent
  std::vector<std::uint32_t> itemOrder;  // a permutation of 0 .. itemCount - 1
  std::uint32_t depth = 0;               // of the deepest leaf
};

// Builds a BVH over axis-aligned boxes (one per item) by binned SAH; see docs/bvh.md.
// Throws std::invalid_argument for options that cannot hold every item
// (maxLeafSize 0, binCount below 2, more items than maxLeafSize * 2^maxDepth).
Bvh buildBvh(std::span<const Aabb> itemBounds, const BvhBuildOptions& options = {});

// The inverse of an instance's affine object-to-world transform, worked out
// in double: a float determinant overflows for scales from about 1e13 and
// underflows below about 1e-13, though their inverses fit a float well.
// Nothing when the transform is not finite, is singular (a scale of 0), or
// has an inverse beyond float's range: such an instance cannot be traced.
std::optional<glm::mat4> instanceWorldToObject(const glm::mat4& objectToWorld);

// Decides whether a hit on an alpha-masked triangle counts (the CPU twin of
// BVH_ALPHA_TEST in bvh_trace.glsl). Empty: every triangle is opaque.
using BvhAlphaTest = std::function<bool(std::uint32_t instance, std::uint32_t triangle, glm::vec2 barycentrics)>;

// What the walk did for a set of rays, in all (the CPU's walk, which is the
// GPU's): nodes fetched (both levels), instances entered, triangles tested.
struct BvhWalkStats {
  std::uint64_t rays = 0;
  std::uint64_t nodes = 0;
  std::uint64_t instances = 0;
  std::uint64_t triangles = 0;
  double perRay(std::uint64_t count) const { return rays ? double(count) / double(rays) : 0.0; }
};

// The two-level scene BVH, flattened into the arrays the GPU reads.
class SceneBvh {
 public:
  // Builds one BLAS per mesh (object space). Throws scene::SceneError when a
  // mesh's indices are out of range or its material index is invalid.
  explicit SceneBvh(const scene::Scene& scene);

  // Rebuilds the TLAS over these instances (call whenever they move). An
  // instance whose mesh has no triangles, or whose transform has no
  // instanceWorldToObject, is left out of the TLAS (it cannot be hit).
  // Throws scene::SceneError for a mesh index out of range.
  void setInstances(std::span<const scene::Instance> instances);
  // Which of the last setInstances call's instances were left out for their
  // transform (indices into that call's span), for a warning.
  const std::vector<std::size_t>& untraceableInstances() const { return untraceable_; }

  // --- The arrays uploaded to the GPU (render/bvh_trace.glsl) ---
  // Every mesh's BLAS, concatenated: child references are global (node
  // indices into this array, leaves' corner records in positions()).
  const std::vector<BvhWideNode>& blasNodes() const { return blasNodes_; }
  // Per triangle in BLAS leaf order: global vertex indices i0, i1, i2 and
  // w = material index | kBvhAlphaMaskedBit for Mask and Blend materials.
  const std::vector<glm::uvec4>& triangles() const { return triangles_; }
  // Object-space vertex positions of all meshes, concatenated in mesh order
  // (w = 1), the first vertexCount() entries; then, from 3 * firstCornerRecord(),
  // one corner record per triangle in BLAS leaf order: its three corners
  // (triangle k's at 3 * (firstCornerRecord() + k) + 0, 1, 2), copied so that
  // the traversal reads a leaf's triangles without going through their
  // indices. In a corner record the first corner's w holds the triangle's w
  // word (material | alpha bit) and the second's the triangle's index, as
  // float bits; the third's w = 1. BLAS leaves reference corner records.
  const std::vector<glm::vec4>& positions() const { return positions_; }
  std::uint32_t vertexCount() const { return vertexCount_; }
  std::uint32_t firstCornerRecord() const { return firstCornerRecord_; }
  // Instances in the TLAS, in TLAS leaf order.
  const std::vector<BvhInstance>& instances() const { return instances_; }
  // Root at 0, never empty: a scene with nothing to hit has a root without children.
  const std::vector<BvhWideNode>& tlasNodes() const { return tlasNodes_; }
  // The world box of the instances in the TLAS (empty when there are none).
  Aabb tlasBounds() const { return tlasBounds_; }

  // Where mesh m's BLAS root is in blasNodes(), or kBvhInvalidIndex for a mesh without triangles.
  std::uint32_t blasRoot(std::size_t mesh) const { return blasRoots_[mesh]; }
  // Mesh m's object-space box (that of its triangles; empty for a mesh without any).
  Aabb meshBounds(std::size_t mesh) const { return meshBounds_[mesh]; }
  // The triangles of mesh m are triangles()[meshFirstTriangle(m) .. meshFirstTriangle(m + 1) - 1]
  // (in BLAS leaf order); m may be the mesh count, which gives the total.
  std::uint32_t meshFirstTriangle(std::size_t mesh) const { return meshFirstTriangle_[mesh]; }
  // The index triangle t had in its mesh's index list (3 * it = its first index).
  std::uint32_t sourceTriangle(std::uint32_t triangle) const { return sourceTriangle_[triangle]; }
  // How many instances the last setInstances call was given (including those left out of the TLAS).
  std::size_t instanceCount() const { return instanceCount_; }
  // The deepest leaf of any BLAS, and of the TLAS (root = 0).
  std::uint32_t blasDepth() const { return blasDepth_; }
  std::uint32_t tlasDepth() const { return tlasDepth_; }
  double blasBuildSeconds() const { return blasBuildSeconds_; }
  // The threads that built the BLASes (a mesh's tree is built by one, the
  // meshes spread over the machine's cores).
  unsigned blasBuildThreads() const { return blasBuildThreads_; }
  // Bytes of the arrays the GPU reads (nodes, triangles, positions and
  // corner records, instances), for reports.
  std::size_t deviceBytes() const;

  // --- CPU traversal (the shader's, render/bvh_traverse.glsl), and brute force to check both ---
  // Closest hit in (tMin, tMax); t = kNoHit when nothing was hit.
  BvhHit traceClosest(glm::vec3 origin, glm::vec3 direction, float tMin, float tMax,
                      const BvhAlphaTest& alphaTest = {}) const;
  // Whether anything is hit in (tMin, tMax) (shadow rays).
  bool traceAny(glm::vec3 origin, glm::vec3 direction, float tMin, float tMax,
                const BvhAlphaTest& alphaTest = {}) const;
  // The walk's work for these rays (each in its (tMin, tMax), no alpha test),
  // counted on the machine's cores.
  BvhWalkStats walkStats(std::span<const BvhRay> rays, bool anyHit) const;
  // Every triangle of every TLAS instance, no hierarchy.
  BvhHit traceClosestBruteForce(glm::vec3 origin, glm::vec3 direction, float tMin, float tMax,
                                const BvhAlphaTest& alphaTest = {}) const;
  // Every hit in (tMin, tMax), in no particular order (for tests that need
  // the second-closest hit, to tell when the closest one is unambiguous).
  std::vector<BvhHit> traceAllBruteForce(glm::vec3 origin, glm::vec3 direction, float tMin, float tMax,
                                         const BvhAlphaTest& alphaTest = {}) const;

 private:
  bool trace(glm::vec3 origin, glm::vec3 direction, float tMin, float tMax, bool anyHit, const BvhAlphaTest& alphaTest,
             BvhHit& hit, BvhWalkStats* stats = nullptr) const;
  bool acceptHit(std::uint32_t instance, std::uint32_t triangle, glm::vec2 barycentrics,
                 const BvhAlphaTest& alphaTest) const;

  std::vector<BvhWideNode> blasNodes_;
  std::vector<glm::uvec4> triangles_;
  std::vector<glm::vec4> positions_;
  std::vector<std::uint32_t> blasRoots_;
  std::vector<Aabb> meshBounds_;
  std::vector<std::uint32_t> meshFirstTriangle_;
  std::vector<std::uint32_t> sourceTriangle_;
  std::vector<BvhInstance> instances_;
  std::vector<BvhWideNode> tlasNodes_;
  Aabb tlasBounds_;
  std::vector<std::size_t> untraceable_;
  std::uint32_t vertexCount_ = 0;
  std::uint32_t firstCornerRecord_ = 0;
  std::size_t instanceCount_ = 0;
  std::uint32_t blasDepth_ = 0;
  std::uint32_t tlasDepth_ = 0;
  double blasBuildSeconds_ = 0.0;
  unsigned blasBuildThreads_ = 1;
};

}  // namespace bounce::render
