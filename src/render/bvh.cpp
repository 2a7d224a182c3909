#include "render/bvh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include <glm/gtc/matrix_inverse.hpp>

// The CPU runs the shader's traversal: render/bvh_traverse.glsl, with the
// data reached through a BvhTraversalData instead of storage buffers.
namespace bounce::shared {
struct BvhTraversalData {
  const std::vector<BvhNode>& tlasNodes;
  const std::vector<BvhNode>& blasNodes;
  const std::vector<BvhInstance>& instances;
  const std::vector<vec4>& positions;
  const render::BvhAlphaTest& alphaTest;
};
}  // namespace bounce::shared
// Checked access: a reference out of range throws instead of reading past an array.
#define BVH_SCENE_PARAMETER const BvhTraversalData &scene,
#define BVH_TLAS_NODE(node) scene.tlasNodes.at(node)
#define BVH_BLAS_NODE(node) scene.blasNodes.at(node)
#define BVH_INSTANCE(record) scene.instances.at(record)
#define BVH_POSITION(index) scene.positions.at(index)
#define BVH_ALPHA_TEST(instance, triangle, barycentrics) \
  (!scene.alphaTest || scene.alphaTest(instance, triangle, barycentrics))
#define BVH_CHECK_STACK(size) \
  if ((size) == kBvhStackSize) throw std::logic_error("BVH traversal stack overflow: the depth bound failed")
#include "render/bvh_traverse.glsl"

namespace bounce::render {
namespace {

using shared::kBvhAlphaMaskedBit;
using shared::kBvhInvalidIndex;
using shared::kNoHit;

// How many items a subtree whose root is at `depth` can hold when every
// split below it is a median split: maxLeafSize * 2^(maxDepth - depth).
double subtreeCapacity(const BvhBuildOptions& options, std::uint32_t depth) {
  if (depth > options.maxDepth) return 0.0;
  return double(options.maxLeafSize) * std::ldexp(1.0, int(std::min(options.maxDepth - depth, 1000u)));
}

struct SahSplit {
  int axis = -1;  // -1: no split found
  std::uint32_t lastLeftBin = 0;
  std::uint32_t leftCount = 0;
  float areaWeightedCount = std::numeric_limits<float>::max();  // leftArea * leftCount + rightArea * rightCount
};

// Maps a centroid coordinate to its bin; the same arithmetic is used when
// counting and when partitioning, so both agree on every item.
std::uint32_t binOf(float coordinate, float axisMin, float scale, std::uint32_t binCount) {
  return std::min(binCount - 1, std::uint32_t((coordinate - axisMin) * scale));
}

class Builder {
 public:
  Builder(std::span<const Aabb> itemBounds, const BvhBuildOptions& options)
      : items_(itemBounds), options_(options), centroids_(itemBounds.size()), bins_(options.binCount) {
    for (std::size_t i = 0; i < items_.size(); ++i) centroids_[i] = items_[i].centroid();
    rightArea_.resize(options.binCount);
    rightCount_.resize(options.binCount);
  }

  Bvh build() {
    const auto itemCount = std::uint32_t(items_.size());
    bvh_.itemOrder.resize(itemCount);
    std::iota(bvh_.itemOrder.begin(), bvh_.itemOrder.end(), 0u);
    bvh_.nodes.reserve(std::size_t(itemCount) * 2);
    bvh_.nodes.push_back({});
    struct Task {
      std::uint32_t node, first, count, depth;
    };
    // Depth first, left child first, so a subtree's nodes sit close together.
    std::vector<Task> tasks{{0, 0, itemCount, 0}};
    while (!tasks.empty()) {
      const Task task = tasks.back();
      tasks.pop_back();
      const std::uint32_t leftCount = split(task.node, task.first, task.count, task.depth);
      if (leftCount == 0) {
        bvh_.depth = std::max(bvh_.depth, task.depth);
        continue;
      }
      const auto left = std::uint32_t(bvh_.nodes.size());
      bvh_.nodes.push_back({});
      bvh_.nodes.push_back({});
      bvh_.nodes[task.node].leftFirst = left;
      bvh_.nodes[task.node].count = 0;
      tasks.push_back({left + 1, task.first + leftCount, task.count - leftCount, task.depth + 1});
      tasks.push_back({left, task.first, leftCount, task.depth + 1});
    }
    return std::move(bvh_);
  }

 private:
  // Sets the node's bounds and either makes it a leaf (returns 0) or
  // partitions its items and returns how many go to the left child.
  std::uint32_t split(std::uint32_t nodeIndex, std::uint32_t first, std::uint32_t count, std::uint32_t depth) {
    Aabb bounds, centroidBounds;
    for (std::uint32_t i = first; i < first + count; ++i) {
      const std::uint32_t item = bvh_.itemOrder[i];
      bounds.extend(items_[item]);
      centroidBounds.extend(centroids_[item]);
    }
    BvhBuildNode& node = bvh_.nodes[nodeIndex];
    node.boundsMin = bounds.min;
    node.boundsMax = bounds.max;
    node.leftFirst = first;
    node.count = count;

    const bool mustSplit = count > options_.maxLeafSize;
    if (depth >= options_.maxDepth) return 0;  // count <= maxLeafSize here, by the capacity bound
    SahSplit best = findSahSplit(first, count, centroidBounds);
    // An SAH split that leaves a child too many items for the depth left is
    // refused; the median split below always fits (each half holds at most
    // ceil(count / 2) <= the capacity one level down).
    const double childCapacity = subtreeCapacity(options_, depth + 1);
    if (best.axis >= 0 && (double(best.leftCount) > childCapacity || double(count - best.leftCount) > childCapacity))
      best.axis = -1;

    if (!mustSplit) {
      if (best.axis < 0) return 0;
      const float parentArea = bounds.halfArea();
      const float leafCost = options_.intersectionCost * float(count) * parentArea;
      const float splitCost = options_.traversalCost * parentArea + options_.intersectionCost * best.areaWeightedCount;
      if (leafCost <= splitCost) return 0;
    }
    if (best.axis >= 0) {
      const float axisMin = centroidBounds.min[best.axis];
      const float scale = binScale(centroidBounds, best.axis);
      const auto begin = bvh_.itemOrder.begin() + first;
      const auto middle = std::partition(begin, begin + count, [&](std::uint32_t item) {
        return binOf(centroids_[item][best.axis], axisMin, scale, options_.binCount) <= best.lastLeftBin;
      });
      return std::uint32_t(middle - begin);
    }
    return medianSplit(first, count, centroidBounds);
  }

  // Items split in half by their centroid along the widest centroid axis:
  // used when the SAH finds no split (all centroids equal) or one too deep.
  std::uint32_t medianSplit(std::uint32_t first, std::uint32_t count, const Aabb& centroidBounds) {
    const glm::vec3 extent = centroidBounds.max - centroidBounds.min;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const std::uint32_t half = count / 2;
    const auto begin = bvh_.itemOrder.begin() + first;
    std::nth_element(begin, begin + half, begin + count,
                     [&](std::uint32_t a, std::uint32_t b) { return centroids_[a][axis] < centroids_[b][axis]; });
    return half;
  }

  // Bins per unit length along the axis, or 0 when the centroids do not
  // spread along it (or spread too little for a finite scale).
  float binScale(const Aabb& centroidBounds, int axis) const {
    const float extent = centroidBounds.max[axis] - centroidBounds.min[axis];
    if (!(extent > 0.0f)) return 0.0f;
    // Slightly under binCount / extent, so the largest centroid lands inside the last bin.
    const float scale = float(options_.binCount) * (1.0f - 1e-6f) / extent;
    return std::isfinite(scale) ? scale : 0.0f;
  }

  SahSplit findSahSplit(std::uint32_t first, std::uint32_t count, const Aabb& centroidBounds) {
    SahSplit best;
    const std::uint32_t binCount = options_.binCount;
    for (int axis = 0; axis < 3; ++axis) {
      const float scale = binScale(centroidBounds, axis);
      if (scale == 0.0f) continue;
      const float axisMin = centroidBounds.min[axis];
      for (Bin& bin : bins_) bin = {};
      for (std::uint32_t i = first; i < first + count; ++i) {
        const std::uint32_t item = bvh_.itemOrder[i];
        Bin& bin = bins_[binOf(centroids_[item][axis], axisMin, scale, binCount)];
        bin.bounds.extend(items_[item]);
        ++bin.count;
      }
      // Sweep from the right to know each right side, then from the left.
      Aabb right;
      std::uint32_t rightItems = 0;
      for (std::uint32_t b = binCount - 1; b > 0; --b) {
        right.extend(bins_[b].bounds);
        rightItems += bins_[b].count;
        rightArea_[b] = right.halfArea();
        rightCount_[b] = rightItems;
      }
      Aabb left;
      std::uint32_t leftItems = 0;
      for (std::uint32_t b = 0; b + 1 < binCount; ++b) {
        left.extend(bins_[b].bounds);
        leftItems += bins_[b].count;
        if (leftItems == 0 || rightCount_[b + 1] == 0) continue;
        const float cost = left.halfArea() * float(leftItems) + rightArea_[b + 1] * float(rightCount_[b + 1]);
        if (cost < best.areaWeightedCount) best = {axis, b, leftItems, cost};
      }
    }
    return best;
  }

  struct Bin {
    Aabb bounds;
    std::uint32_t count = 0;
  };

  std::span<const Aabb> items_;
  const BvhBuildOptions& options_;
  std::vector<glm::vec3> centroids_;
  std::vector<Bin> bins_;
  std::vector<float> rightArea_;
  std::vector<std::uint32_t> rightCount_;
  Bvh bvh_;
};

void rows3x4(const glm::mat4& m, glm::vec4 rows[3]) {
  for (int r = 0; r < 3; ++r) rows[r] = glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]);
}

// The world box of an object box under an affine transform: the box of its
// eight transformed corners, padded by a few ulps of its size so rounding in
// the transform never makes it smaller than what the BLAS can hit.
Aabb transformBounds(const glm::mat4& objectToWorld, const glm::vec3& boundsMin, const glm::vec3& boundsMax) {
  Aabb world;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? boundsMax.x : boundsMin.x, (corner & 2) ? boundsMax.y : boundsMin.y,
                      (corner & 4) ? boundsMax.z : boundsMin.z);
    world.extend(glm::vec3(objectToWorld * glm::vec4(p, 1.0f)));
  }
  const glm::vec3 pad = (glm::abs(world.min) + glm::abs(world.max) + (world.max - world.min)) * 1e-6f;
  world.min -= pad;
  world.max += pad;
  return world;
}

bool finiteMatrix(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

// The traversal layout of a binary tree (docs/bvh.md): one BvhNode per
// interior node, holding both children's boxes and references, depth first
// with the root first and a left interior child right after its parent.
// Node indices start at firstNode, leaf items at firstItem. A tree of one
// leaf gets a root whose right slot is empty, a tree of nothing a root with
// two empty slots, so every walk starts at an interior node.
class TraversalLayout {
 public:
  TraversalLayout(const Bvh& bvh, std::uint32_t firstNode, std::uint32_t firstItem)
      : bvh_(bvh), firstNode_(firstNode), firstItem_(firstItem) {}

  std::vector<BvhNode> nodes() && {
    if (bvh_.nodes.empty()) {
      nodes_.push_back({});
      setChild(0, 0, Aabb{}, kBvhInvalidIndex);
      setChild(0, 1, Aabb{}, kBvhInvalidIndex);
    } else if (bvh_.nodes[0].count > 0) {
      nodes_.push_back({});
      setChild(0, 0, bounds(bvh_.nodes[0]), reference(0));
      setChild(0, 1, Aabb{}, kBvhInvalidIndex);
    } else {
      place(0);
    }
    return std::move(nodes_);
  }

 private:
  static Aabb bounds(const BvhBuildNode& node) { return {node.boundsMin, node.boundsMax}; }

  // The reference a parent stores for binary node `index`, placing its subtree first if it is interior.
  std::uint32_t reference(std::uint32_t index) {
    const BvhBuildNode& node = bvh_.nodes[index];
    if (node.count == 0) return place(index);
    if (firstItem_ + node.leftFirst >= shared::kBvhMaxLeafFirst || node.count > shared::kBvhMaxLeafSize)
      throw std::invalid_argument("BVH: a leaf of " + std::to_string(node.count) + " items from item " +
                                  std::to_string(firstItem_ + node.leftFirst) + " does not fit a child reference");
    return shared::bvhLeafReference(firstItem_ + node.leftFirst, node.count);
  }

  // Places interior binary node `index` and, after it, its subtree; returns its global index.
  std::uint32_t place(std::uint32_t index) {
    const auto slot = std::uint32_t(nodes_.size());
    if (firstNode_ + slot >= shared::kBvhLeafBit) throw std::invalid_argument("BVH: too many nodes for a reference");
    nodes_.push_back({});
    for (std::uint32_t side = 0; side < 2; ++side) {
      const std::uint32_t child = bvh_.nodes[index].leftFirst + side;
      const std::uint32_t childReference = reference(child);  // may grow nodes_: index it afterwards
      setChild(slot, side, bounds(bvh_.nodes[child]), childReference);
    }
    return firstNode_ + slot;
  }

  void setChild(std::uint32_t slot, std::uint32_t side, const Aabb& box, std::uint32_t childReference) {
    BvhNode& node = nodes_[slot];
    if (side == 0) {
      node.leftMin = box.min;
      node.leftMax = box.max;
      node.left = childReference;
    } else {
      node.rightMin = box.min;
      node.rightMax = box.max;
      node.right = childReference;
    }
  }

  const Bvh& bvh_;
  std::uint32_t firstNode_, firstItem_;
  std::vector<BvhNode> nodes_;
};

BvhHit noHit() { return {kNoHit, kBvhInvalidIndex, kBvhInvalidIndex, glm::vec2(0.0f)}; }

}  // namespace

std::optional<glm::mat4> instanceWorldToObject(const glm::mat4& objectToWorld) {
  if (!finiteMatrix(objectToWorld)) return std::nullopt;
  const glm::dmat4 transform(objectToWorld);
  const double determinant = glm::determinant(glm::dmat3(transform));
  if (determinant == 0.0 || !std::isfinite(determinant)) return std::nullopt;
  const glm::mat4 inverse(glm::affineInverse(transform));
  if (!finiteMatrix(inverse)) return std::nullopt;
  return inverse;
}

Bvh buildBvh(std::span<const Aabb> itemBounds, const BvhBuildOptions& options) {
  if (options.maxLeafSize == 0 || options.binCount < 2)
    throw std::invalid_argument("BVH build: maxLeafSize must be at least 1 and binCount at least 2");
  if (double(itemBounds.size()) > subtreeCapacity(options, 0) || itemBounds.size() >= kBvhInvalidIndex)
    throw std::invalid_argument("BVH build: " + std::to_string(itemBounds.size()) + " items do not fit in leaves of " +
                                std::to_string(options.maxLeafSize) + " at depth " + std::to_string(options.maxDepth));
  if (itemBounds.empty()) return {};
  return Builder(itemBounds, options).build();
}

SceneBvh::SceneBvh(const scene::Scene& scene) {
  const auto start = std::chrono::steady_clock::now();
  std::size_t vertexTotal = 0;
  for (const scene::Mesh& mesh : scene.meshes) vertexTotal += mesh.positions.size();
  if (vertexTotal >= kBvhInvalidIndex) throw scene::SceneError(scene.name + ": too many vertices for 32-bit indices");
  std::size_t triangleTotal = 0;
  for (const scene::Mesh& mesh : scene.meshes) triangleTotal += mesh.indices.size() / 3;
  vertexCount_ = std::uint32_t(vertexTotal);
  // Corner records start at a multiple of three entries, after the vertices.
  firstCornerRecord_ = (vertexCount_ + 2) / 3;
  if (firstCornerRecord_ + triangleTotal > shared::kBvhMaxLeafFirst)
    throw scene::SceneError(scene.name + ": too many triangles and vertices for the BVH's leaf references");
  positions_.reserve(3 * (firstCornerRecord_ + triangleTotal));
  std::vector<glm::vec4> cornerRecords;
  cornerRecords.reserve(3 * triangleTotal);

  blasRoots_.assign(scene.meshes.size(), kBvhInvalidIndex);
  meshFirstTriangle_.reserve(scene.meshes.size() + 1);
  std::vector<Aabb> triangleBounds;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const scene::Mesh& mesh = scene.meshes[m];
    const auto fail = [&](const std::string& why) {
      return scene::SceneError(scene.name + ": mesh " + std::to_string(m) + " '" + mesh.name + "': " + why);
    };
    if (mesh.material < 0 || std::size_t(mesh.material) >= scene.materials.size())
      throw fail("material index " + std::to_string(mesh.material) + " out of range");
    const scene::AlphaMode alphaMode = scene.materials[std::size_t(mesh.material)].alphaMode;
    const std::uint32_t materialBits =
        std::uint32_t(mesh.material) | (alphaMode == scene::AlphaMode::Opaque ? 0u : kBvhAlphaMaskedBit);
    const auto vertexOffset = std::uint32_t(positions_.size());
    for (const glm::vec3& p : mesh.positions) positions_.emplace_back(p, 1.0f);

    const std::size_t triangleCount = mesh.indices.size() / 3;
    triangleBounds.clear();
    for (std::size_t t = 0; t < triangleCount; ++t) {
      Aabb box;
      for (int corner = 0; corner < 3; ++corner) {
        const std::uint32_t index = mesh.indices[3 * t + std::size_t(corner)];
        if (index >= mesh.positions.size()) throw fail("index " + std::to_string(index) + " out of range");
        box.extend(mesh.positions[index]);
      }
      triangleBounds.push_back(box);
    }
    const auto firstTriangle = std::uint32_t(triangles_.size());
    meshFirstTriangle_.push_back(firstTriangle);
    if (triangleCount == 0) {
      meshBounds_.emplace_back();
      continue;
    }

    const Bvh blas = buildBvh(triangleBounds);
    const auto root = std::uint32_t(blasNodes_.size());
    for (const BvhNode& node : TraversalLayout(blas, root, firstCornerRecord_ + firstTriangle).nodes())
      blasNodes_.push_back(node);
    for (const std::uint32_t t : blas.itemOrder) {
      const std::uint32_t* index = &mesh.indices[3 * std::size_t(t)];
      const auto triangle = std::uint32_t(triangles_.size());
      triangles_.emplace_back(index[0] + vertexOffset, index[1] + vertexOffset, index[2] + vertexOffset, materialBits);
      cornerRecords.emplace_back(mesh.positions[index[0]], glm::uintBitsToFloat(materialBits));
      cornerRecords.emplace_back(mesh.positions[index[1]], glm::uintBitsToFloat(triangle));
      cornerRecords.emplace_back(mesh.positions[index[2]], 1.0f);
      sourceTriangle_.push_back(t);
    }
    blasRoots_[m] = root;
    meshBounds_.push_back({blas.nodes[0].boundsMin, blas.nodes[0].boundsMax});
    blasDepth_ = std::max(blasDepth_, blas.depth);
  }
  meshFirstTriangle_.push_back(std::uint32_t(triangles_.size()));
  positions_.resize(3 * std::size_t(firstCornerRecord_), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  positions_.insert(positions_.end(), cornerRecords.begin(), cornerRecords.end());
  blasBuildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  setInstances({});
}

std::size_t SceneBvh::deviceBytes() const {
  return blasNodes_.size() * sizeof(BvhNode) + triangles_.size() * sizeof(glm::uvec4) +
         positions_.size() * sizeof(glm::vec4) + instances_.size() * sizeof(BvhInstance) +
         tlasNodes_.size() * sizeof(BvhNode);
}

void SceneBvh::setInstances(std::span<const scene::Instance> instances) {
  instanceCount_ = instances.size();
  untraceable_.clear();
  std::vector<BvhInstance> records;
  std::vector<Aabb> bounds;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const scene::Instance& instance = instances[i];
    if (instance.mesh < 0 || std::size_t(instance.mesh) >= blasRoots_.size())
      throw scene::SceneError("instance " + std::to_string(i) + ": mesh index " + std::to_string(instance.mesh) +
                              " out of range");
    const std::uint32_t root = blasRoots_[std::size_t(instance.mesh)];
    if (root == kBvhInvalidIndex) continue;
    const glm::mat4& objectToWorld = instance.objectToWorld;
    const std::optional<glm::mat4> worldToObject = instanceWorldToObject(objectToWorld);
    if (!worldToObject) {
      untraceable_.push_back(i);
      continue;
    }
    BvhInstance record{};
    rows3x4(*worldToObject, record.worldToObject);
    rows3x4(objectToWorld, record.objectToWorld);
    record.info = glm::uvec4(root, std::uint32_t(instance.mesh), std::uint32_t(i), 0u);
    records.push_back(record);
    const Aabb& objectBounds = meshBounds_[std::size_t(instance.mesh)];
    bounds.push_back(transformBounds(objectToWorld, objectBounds.min, objectBounds.max));
  }
  // One instance per leaf: an instance costs a transform and a BLAS root, far
  // more than a triangle, and the traversal enters a TLAS leaf's one instance.
  const Bvh tlas = buildBvh(bounds, {.maxLeafSize = 1});
  instances_.clear();
  for (const std::uint32_t item : tlas.itemOrder) instances_.push_back(records[item]);
  tlasNodes_ = TraversalLayout(tlas, 0, 0).nodes();
  tlasBounds_ = tlas.nodes.empty() ? Aabb{} : Aabb{tlas.nodes[0].boundsMin, tlas.nodes[0].boundsMax};
  tlasDepth_ = tlas.depth;
}

bool SceneBvh::acceptHit(std::uint32_t instance, std::uint32_t triangle, glm::vec2 barycentrics,
                         const BvhAlphaTest& alphaTest) const {
  if ((triangles_[triangle].w & kBvhAlphaMaskedBit) == 0u || !alphaTest) return true;
  return alphaTest(instance, triangle, barycentrics);
}

bool SceneBvh::trace(glm::vec3 origin, glm::vec3 direction, float tMin, float tMax, bool anyHit,
                     const BvhAlphaTest& alphaTest, BvhHit& hit) const {
  const shared::BvhTraversalData data{tlasNodes_, blasNodes_, instances_, positions_, alphaTest};
  return shared::bvhTraverse(data, origin, direction, tMin, tMax, anyHit, hit);
}

BvhHit SceneBvh::traceClosest(glm::vec3 origin, glm::vec3 direction, float tMin, float tMax,
                              const BvhAlphaTest& alphaTest) const {
  BvhHit hit;
  trace(origin, direction, tMin, tMax, false, alphaTest, hit);
  return hit;
}

bool SceneBvh::traceAny(glm::vec3 origin, glm::vec3 direction, float tMin, float tMax,
                        const BvhAlphaTest& alphaTest) const {
  BvhHit hit;
  return trace(origin, direction, tMin, tMax, true, alphaTest, hit);
}

std::vector<BvhHit> SceneBvh::traceAllBruteForce(glm::vec3 worldOrigin, glm::vec3 worldDirection, float tMin,
                                                 float tMax, const BvhAlphaTest& alphaTest) const {
  std::vector<BvhHit> hits;
  for (const BvhInstance& instance : instances_) {
    const glm::vec3 origin = shared::bvhTransformPoint(instance.worldToObject, worldOrigin);
    const glm::vec3 direction = shared::bvhTransformVector(instance.worldToObject, worldDirection);
    const std::uint32_t mesh = instance.info.y;
    for (std::uint32_t k = meshFirstTriangle_[mesh]; k < meshFirstTriangle_[mesh + 1]; ++k) {
      const glm::uvec4& triangle = triangles_[k];
      float t = 0.0f;
      glm::vec2 barycentrics(0.0f);
      if (shared::bvhIntersectTriangle(origin, direction, glm::vec3(positions_[triangle.x]),
                                       glm::vec3(positions_[triangle.y]), glm::vec3(positions_[triangle.z]), tMin, tMax,
                                       t, barycentrics) &&
          acceptHit(instance.info.z, k, barycentrics, alphaTest))
        hits.push_back({t, instance.info.z, k, barycentrics});
    }
  }
  return hits;
}

BvhHit SceneBvh::traceClosestBruteForce(glm::vec3 origin, glm::vec3 direction, float tMin, float tMax,
                                        const BvhAlphaTest& alphaTest) const {
  BvhHit closest = noHit();
  for (const BvhHit& hit : traceAllBruteForce(origin, direction, tMin, tMax, alphaTest))
    if (hit.t < closest.t) closest = hit;
  return closest;
}

}  // namespace bounce::render
