#include "render/bvh.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <future>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>

#include <glm/gtc/matrix_inverse.hpp>

// The CPU runs the shader's traversal: render/bvh_traverse.glsl, with the
// data reached through a BvhTraversalData instead of storage buffers.
namespace bounce::shared {
struct BvhTraversalData {
  const std::vector<BvhWideNode>& tlasNodes;
  const std::vector<BvhWideNode>& blasNodes;
  const std::vector<BvhInstance>& instances;
  const std::vector<vec4>& positions;
  const render::BvhAlphaTest& alphaTest;
  render::BvhWalkStats* stats = nullptr;  // counted into when set
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
#define BVH_COUNT_NODE() \
  if (scene.stats) ++scene.stats->nodes
#define BVH_COUNT_INSTANCE() \
  if (scene.stats) ++scene.stats->instances
#define BVH_COUNT_TRIANGLE() \
  if (scene.stats) ++scene.stats->triangles
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

// The traversal layout of a binary tree (docs/bvh.md): its compressed wide
// form (Ylitie, Karras and Laine 2017). Each wide node is collapsed from a
// binary interior node by opening, while it has fewer than eight children,
// its interior child of the largest surface area (the one a ray is most
// likely to enter), so a wide node is one binary node and up to six of its
// descendants. Children take the slots their directions suit (below), a
// node's interior children are laid out consecutively in slot order (the
// root first, then each node's children before their subtrees), and its
// leaves' items consecutively in slot order; `itemSlots` says which binary
// leaf slot each item position holds. Node indices start at firstNode,
// items at firstItem. A tree of one leaf is a root with one child, a tree
// of nothing a root with none, so every walk starts at a node.
class WideLayout {
 public:
  WideLayout(const Bvh& bvh, std::uint32_t firstNode, std::uint32_t firstItem)
      : bvh_(bvh), firstNode_(firstNode), firstItem_(firstItem) {
    nodes.emplace_back();
    if (bvh_.nodes.empty()) {
      fill(0, {}, 0);
    } else if (bvh_.nodes[0].count > 0) {
      fill(0, {0}, 0);
    } else {
      fill(0, collapse(0), 0);
    }
  }

  std::vector<BvhWideNode> nodes;
  std::vector<std::uint32_t> itemSlots;  // item position -> binary leaf slot (index into Bvh::itemOrder)
  std::uint32_t levels = 1;              // of wide nodes (a root alone: 1)

 private:
  static Aabb bounds(const BvhBuildNode& node) { return {node.boundsMin, node.boundsMax}; }
  bool interior(std::uint32_t index) const { return bvh_.nodes[index].count == 0; }

  // The binary nodes that become interior node `index`'s wide children.
  std::vector<std::uint32_t> collapse(std::uint32_t index) const {
    std::vector<std::uint32_t> children = {bvh_.nodes[index].leftFirst, bvh_.nodes[index].leftFirst + 1};
    while (children.size() < shared::kBvhWideArity) {
      int widest = -1;
      float widestArea = -1.0f;
      for (std::size_t c = 0; c < children.size(); ++c)
        if (interior(children[c]) && bounds(bvh_.nodes[children[c]]).halfArea() > widestArea) {
          widest = int(c);
          widestArea = bounds(bvh_.nodes[children[c]]).halfArea();
        }
      if (widest < 0) break;
      const std::uint32_t opened = children[std::size_t(widest)];
      children[std::size_t(widest)] = bvh_.nodes[opened].leftFirst;
      children.push_back(bvh_.nodes[opened].leftFirst + 1);
    }
    return children;
  }

  // Slot s serves rays of octant s (bvhOctant): it gets the child that lies
  // furthest back along that octant's diagonal, so a ray meets it first.
  // Greedy over all (child, slot) pairs, cheapest first (Ylitie et al.).
  std::array<int, shared::kBvhWideArity> assignSlots(const std::vector<std::uint32_t>& children) const {
    std::array<int, shared::kBvhWideArity> slotChild;
    slotChild.fill(-1);
    Aabb parent;
    for (const std::uint32_t c : children) parent.extend(bounds(bvh_.nodes[c]));
    struct Pair {
      float cost;
      std::uint32_t child, slot;
    };
    std::vector<Pair> pairs;
    for (std::uint32_t c = 0; c < children.size(); ++c) {
      const glm::vec3 offset = bounds(bvh_.nodes[children[c]]).centroid() - parent.centroid();
      for (std::uint32_t slot = 0; slot < shared::kBvhWideArity; ++slot) {
        const glm::vec3 diagonal((slot & 4u) ? -1.0f : 1.0f, (slot & 2u) ? -1.0f : 1.0f, (slot & 1u) ? -1.0f : 1.0f);
        pairs.push_back({glm::dot(offset, diagonal), c, slot});
      }
    }
    std::stable_sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.cost < b.cost; });
    std::vector<bool> placed(children.size(), false);
    for (const Pair& pair : pairs)
      if (!placed[pair.child] && slotChild[pair.slot] < 0) {
        slotChild[pair.slot] = int(pair.child);
        placed[pair.child] = true;
      }
    return slotChild;
  }

  // Fills wide node `slot` (local index) from these binary children, then
  // lays out and fills its interior children's subtrees.
  void fill(std::uint32_t slot, const std::vector<std::uint32_t>& children, std::uint32_t level) {
    levels = std::max(levels, level + 1);
    const std::array<int, shared::kBvhWideArity> slotChild = assignSlots(children);
    const auto firstChild = std::uint32_t(nodes.size());
    const auto firstItem = std::uint32_t(itemSlots.size());
    if (firstNode_ + firstChild + shared::kBvhWideArity >= kBvhInvalidIndex ||
        firstItem_ + firstItem + shared::kBvhWideMaxItems >= kBvhInvalidIndex / 3)
      throw std::invalid_argument("BVH: too many nodes or items for 32-bit indices");
    std::array<std::uint32_t, shared::kBvhWideArity> meta{};
    std::uint32_t interiorMask = 0;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> interiors;  // (local node, binary node)
    Aabb box;
    for (std::uint32_t s = 0; s < shared::kBvhWideArity; ++s) {
      if (slotChild[s] < 0) continue;
      const std::uint32_t child = children[std::size_t(slotChild[s])];
      box.extend(bounds(bvh_.nodes[child]));
      if (interior(child)) {
        meta[s] = shared::bvhWideMetaInterior(s);
        interiorMask |= 1u << s;
        interiors.emplace_back(std::uint32_t(nodes.size()) + std::uint32_t(interiors.size()), child);
      } else {
        const BvhBuildNode& leaf = bvh_.nodes[child];
        if (leaf.count > shared::kBvhMaxLeafSize)
          throw std::invalid_argument("BVH: a leaf of " + std::to_string(leaf.count) + " items (at most " +
                                      std::to_string(shared::kBvhMaxLeafSize) + ")");
        meta[s] = shared::bvhWideMetaLeaf(std::uint32_t(itemSlots.size()) - firstItem, leaf.count);
        for (std::uint32_t i = 0; i < leaf.count; ++i) itemSlots.push_back(leaf.leftFirst + i);
      }
    }
    nodes.resize(nodes.size() + interiors.size());
    BvhWideNode& node = nodes[slot];
    node = {};
    node.childrenMeta = glm::uvec4(firstNode_ + firstChild, firstItem_ + firstItem, 0u, 0u);
    for (std::uint32_t s = 0; s < shared::kBvhWideArity; ++s)
      node.childrenMeta[2 + s / 4] |= meta[s] << (8u * (s % 4));
    quantize(node, box, children, slotChild);
    std::uint32_t exponents = floatBitsToUint(node.originExponents.w);
    node.originExponents.w = glm::uintBitsToFloat(exponents | (interiorMask << 24u));
    for (const auto& [local, binary] : interiors) fill(local, collapse(binary), level + 1);
  }

  static std::uint32_t floatBitsToUint(float f) { return glm::floatBitsToUint(f); }

  // The node's grid: origin at the box's minimum, per axis the smallest
  // power-of-two scale whose 255 steps span the box; each child box rounded
  // outwards onto it, checked in the float arithmetic the walk uses
  // (origin + scale * q), so no stored box is ever smaller than its child's.
  void quantize(BvhWideNode& node, const Aabb& box, const std::vector<std::uint32_t>& children,
                const std::array<int, shared::kBvhWideArity>& slotChild) const {
    std::array<std::array<std::uint32_t, shared::kBvhWideArity>, 3> low{}, high{};
    std::uint32_t exponents = 0;
    const glm::vec3 origin = box.empty() ? glm::vec3(0.0f) : box.min;
    for (int axis = 0; axis < 3; ++axis) {
      const double extent = box.empty() ? 0.0 : double(box.max[axis]) - double(box.min[axis]);
      int exponent = -126;
      if (extent > 0.0) {
        int binary = 0;
        const double mantissa = std::frexp(extent / 255.0, &binary);  // extent / 255 = mantissa * 2^binary
        exponent = std::max(-126, mantissa == 0.5 ? binary - 1 : binary);
      }
      for (bool fits = false; !fits; ++exponent) {
        if (exponent > 127) throw std::invalid_argument("BVH: a node too large for its grid");
        const float scale = std::ldexp(1.0f, exponent);
        const auto at = [&](std::uint32_t q) { return origin[axis] + scale * float(q); };
        fits = true;
        for (std::uint32_t s = 0; s < shared::kBvhWideArity && fits; ++s) {
          if (slotChild[s] < 0) continue;
          const Aabb child = bounds(bvh_.nodes[children[std::size_t(slotChild[s])]]);
          auto q0 = std::uint32_t(
              std::clamp(std::floor((double(child.min[axis]) - double(origin[axis])) / double(scale)), 0.0, 255.0));
          while (q0 > 0 && at(q0) > child.min[axis]) --q0;
          auto q1 = std::uint32_t(
              std::clamp(std::ceil((double(child.max[axis]) - double(origin[axis])) / double(scale)), 0.0, 255.0));
          while (q1 < 255 && at(q1) < child.max[axis]) ++q1;
          if (at(q0) > child.min[axis] || at(q1) < child.max[axis]) fits = false;
          low[std::size_t(axis)][s] = q0;
          high[std::size_t(axis)][s] = q1;
        }
        if (fits) exponents |= std::uint32_t(exponent + 127) << (8 * axis);
      }
    }
    const auto pack = [](const std::array<std::uint32_t, shared::kBvhWideArity>& q, int part) {
      std::uint32_t word = 0;
      for (int i = 0; i < 4; ++i) word |= q[std::size_t(4 * part + i)] << (8 * i);
      return word;
    };
    node.originExponents = glm::vec4(origin, glm::uintBitsToFloat(exponents));
    node.lowXY = glm::uvec4(pack(low[0], 0), pack(low[0], 1), pack(low[1], 0), pack(low[1], 1));
    node.lowZHighX = glm::uvec4(pack(low[2], 0), pack(low[2], 1), pack(high[0], 0), pack(high[0], 1));
    node.highYZ = glm::uvec4(pack(high[1], 0), pack(high[1], 1), pack(high[2], 0), pack(high[2], 1));
  }

  const Bvh& bvh_;
  std::uint32_t firstNode_, firstItem_;
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
  // The walk reads corner record r at 3r .. 3r + 2, a 32-bit index.
  if (3 * (std::uint64_t(firstCornerRecord_) + triangleTotal) >= kBvhInvalidIndex)
    throw scene::SceneError(scene.name + ": too many triangles and vertices for the BVH's 32-bit indices");
  positions_.reserve(3 * (firstCornerRecord_ + triangleTotal));
  std::vector<glm::vec4> cornerRecords;
  cornerRecords.reserve(3 * triangleTotal);

  blasRoots_.assign(scene.meshes.size(), kBvhInvalidIndex);
  meshFirstTriangle_.reserve(scene.meshes.size() + 1);
  // Each mesh's tree is built on its own (the build is most of the load
  // time of a large scene), a few meshes at a time on the machine's cores,
  // with node and item numbers from 0; they are then concatenated in mesh
  // order and renumbered. Index and material checks come first, here.
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const scene::Mesh& mesh = scene.meshes[m];
    const auto fail = [&](const std::string& why) {
      return scene::SceneError(scene.name + ": mesh " + std::to_string(m) + " '" + mesh.name + "': " + why);
    };
    if (mesh.material < 0 || std::size_t(mesh.material) >= scene.materials.size())
      throw fail("material index " + std::to_string(mesh.material) + " out of range");
    for (std::size_t i = 0; i < mesh.indices.size() / 3 * 3; ++i)
      if (mesh.indices[i] >= mesh.positions.size())
        throw fail("index " + std::to_string(mesh.indices[i]) + " out of range");
  }
  struct MeshTree {
    Bvh binary;
    std::optional<WideLayout> wide;
  };
  std::vector<MeshTree> trees(scene.meshes.size());
  std::atomic<std::size_t> nextMesh{0};
  const auto buildTrees = [&] {
    std::vector<Aabb> triangleBounds;
    for (std::size_t m = nextMesh++; m < scene.meshes.size(); m = nextMesh++) {
      const scene::Mesh& mesh = scene.meshes[m];
      const std::size_t triangleCount = mesh.indices.size() / 3;
      if (triangleCount == 0) continue;
      triangleBounds.clear();
      for (std::size_t t = 0; t < triangleCount; ++t) {
        Aabb box;
        for (int corner = 0; corner < 3; ++corner) box.extend(mesh.positions[mesh.indices[3 * t + std::size_t(corner)]]);
        triangleBounds.push_back(box);
      }
      trees[m].binary = buildBvh(triangleBounds);
      trees[m].wide.emplace(trees[m].binary, 0u, 0u);
    }
  };
  {
    const unsigned helpers =
        std::max(1u, std::min<unsigned>(std::max(1u, std::thread::hardware_concurrency()),
                                        unsigned(scene.meshes.size()))) - 1;
    std::vector<std::future<void>> running;
    blasBuildThreads_ = helpers + 1;
    for (unsigned h = 0; h < helpers; ++h) running.push_back(std::async(std::launch::async, buildTrees));
    buildTrees();
    for (std::future<void>& helper : running) helper.get();  // rethrows a helper's exception
  }

  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const scene::Mesh& mesh = scene.meshes[m];
    const scene::AlphaMode alphaMode = scene.materials[std::size_t(mesh.material)].alphaMode;
    const std::uint32_t materialBits =
        std::uint32_t(mesh.material) | (alphaMode == scene::AlphaMode::Opaque ? 0u : kBvhAlphaMaskedBit);
    const auto vertexOffset = std::uint32_t(positions_.size());
    for (const glm::vec3& p : mesh.positions) positions_.emplace_back(p, 1.0f);
    const auto firstTriangle = std::uint32_t(triangles_.size());
    meshFirstTriangle_.push_back(firstTriangle);
    if (!trees[m].wide) {
      meshBounds_.emplace_back();
      continue;
    }
    const Bvh& blas = trees[m].binary;
    const auto root = std::uint32_t(blasNodes_.size());
    for (BvhWideNode node : trees[m].wide->nodes) {
      node.childrenMeta.x += root;
      node.childrenMeta.y += firstCornerRecord_ + firstTriangle;
      blasNodes_.push_back(node);
    }
    for (const std::uint32_t slot : trees[m].wide->itemSlots) {
      const std::uint32_t t = blas.itemOrder[slot];
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
    trees[m].wide.reset();  // their memory back before the next mesh's arrays grow
    trees[m].binary = {};
  }
  meshFirstTriangle_.push_back(std::uint32_t(triangles_.size()));
  positions_.resize(3 * std::size_t(firstCornerRecord_), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  positions_.insert(positions_.end(), cornerRecords.begin(), cornerRecords.end());
  blasBuildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  setInstances({});
}

std::size_t SceneBvh::deviceBytes() const {
  return blasNodes_.size() * sizeof(BvhWideNode) + triangles_.size() * sizeof(glm::uvec4) +
         positions_.size() * sizeof(glm::vec4) + instances_.size() * sizeof(BvhInstance) +
         tlasNodes_.size() * sizeof(BvhWideNode);
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
  WideLayout layout(tlas, 0, 0);
  instances_.clear();
  for (const std::uint32_t slot : layout.itemSlots) instances_.push_back(records[tlas.itemOrder[slot]]);
  tlasNodes_ = std::move(layout.nodes);
  tlasBounds_ = tlas.nodes.empty() ? Aabb{} : Aabb{tlas.nodes[0].boundsMin, tlas.nodes[0].boundsMax};
  tlasDepth_ = tlas.depth;
}

bool SceneBvh::acceptHit(std::uint32_t instance, std::uint32_t triangle, glm::vec2 barycentrics,
                         const BvhAlphaTest& alphaTest) const {
  if ((triangles_[triangle].w & kBvhAlphaMaskedBit) == 0u || !alphaTest) return true;
  return alphaTest(instance, triangle, barycentrics);
}

bool SceneBvh::trace(glm::vec3 origin, glm::vec3 direction, float tMin, float tMax, bool anyHit,
                     const BvhAlphaTest& alphaTest, BvhHit& hit, BvhWalkStats* stats) const {
  const shared::BvhTraversalData data{tlasNodes_, blasNodes_, instances_, positions_, alphaTest, stats};
  return shared::bvhTraverse(data, origin, direction, tMin, tMax, anyHit, hit);
}

BvhWalkStats SceneBvh::walkStats(std::span<const BvhRay> rays, bool anyHit) const {
  const unsigned threadCount = std::clamp(std::thread::hardware_concurrency(), 1u, 64u);
  std::vector<BvhWalkStats> counts(threadCount);
  std::vector<std::exception_ptr> failures(threadCount);
  std::vector<std::thread> threads;
  for (unsigned worker = 0; worker < threadCount; ++worker)
    threads.emplace_back([&, worker] {
      try {
        for (std::size_t i = worker; i < rays.size(); i += threadCount) {
          BvhHit hit;
          trace(glm::vec3(rays[i].originTMin), glm::vec3(rays[i].directionTMax), rays[i].originTMin.w,
                rays[i].directionTMax.w, anyHit, {}, hit, &counts[worker]);
        }
      } catch (...) {
        failures[worker] = std::current_exception();
      }
    });
  for (std::thread& thread : threads) thread.join();
  for (const std::exception_ptr& failure : failures)
    if (failure) std::rethrow_exception(failure);
  BvhWalkStats total;
  for (const BvhWalkStats& c : counts) {
    total.nodes += c.nodes;
    total.instances += c.instances;
    total.triangles += c.triangles;
  }
  total.rays = rays.size();
  return total;
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
