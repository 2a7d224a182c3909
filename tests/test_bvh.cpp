// Tests of the BVH (src/render/bvh.h, gpu_bvh.h, shaders/render/bvh_trace.glsl):
// builder invariants and SAH decisions on the CPU; the traversal layout's
// invariants (child boxes in their parent, triangles in leaf order); CPU and GPU traversal
// against brute force over every triangle, on a procedural scene of 100k+
// triangles with transformed instances (and Sponza when it is available);
// alpha masking through the shader hook; and the per-frame TLAS upload
// across frames in flight.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iostream>
#include <numeric>
#include <random>
#include <thread>

#include <glm/gtc/matrix_transform.hpp>

#include "test_shaders.h"
#include "gpu/frame_loop.h"
#include "gpu/transfer.h"
#include "gpu_test.h"
#include "render/benchmark_rays.h"
#include "render/bvh.h"
#include "render/frame_renderer.h"
#include "render/gpu_bvh.h"
#include "scene/builtin_scenes.h"
#include "scene/camera_path.h"

#if __has_include("scene/gltf_import.h")
#include "scene/gltf_import.h"
#define BOUNCE_TEST_HAVE_GLTF 1
#endif

namespace bounce::render {
namespace {

using shared::kBvhAlphaMaskedBit;
using shared::kBvhInvalidIndex;
using shared::kNoHit;

// ---------------------------------------------------------------------------
// Builder

Aabb box(glm::vec3 min, glm::vec3 max) { return {min, max}; }
Aabb nodeBox(const BvhBuildNode& node) { return {node.boundsMin, node.boundsMax}; }

bool sameBox(const Aabb& a, const Aabb& b) { return a.min == b.min && a.max == b.max; }

// Checks every structural promise of buildBvh: each item in exactly one leaf
// slot, leaves of 1..maxLeafSize items, interior bounds exactly the union of
// the children's, leaf bounds exactly the union of its items', every node
// reachable once, depth as reported and within the bound.
void expectValidBvh(const Bvh& bvh, std::span<const Aabb> items, const BvhBuildOptions& options = {}) {
  ASSERT_EQ(bvh.itemOrder.size(), items.size());
  if (items.empty()) {
    EXPECT_TRUE(bvh.nodes.empty());
    return;
  }
  std::vector<std::uint32_t> sorted = bvh.itemOrder;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i) << "itemOrder is not a permutation";

  std::vector<int> slotSeen(items.size(), 0), nodeSeen(bvh.nodes.size(), 0);
  std::uint32_t deepest = 0, leaves = 0;
  struct Visit {
    std::uint32_t node, depth;
  };
  std::vector<Visit> stack{{0, 0}};
  while (!stack.empty()) {
    const Visit visit = stack.back();
    stack.pop_back();
    ASSERT_LT(visit.node, bvh.nodes.size());
    ASSERT_EQ(nodeSeen[visit.node]++, 0) << "node " << visit.node << " is reachable twice";
    const BvhBuildNode& node = bvh.nodes[visit.node];
    if (node.count == 0) {
      ASSERT_LT(node.leftFirst + 1, bvh.nodes.size());
      Aabb children = nodeBox(bvh.nodes[node.leftFirst]);
      children.extend(nodeBox(bvh.nodes[node.leftFirst + 1]));
      EXPECT_TRUE(sameBox(children, nodeBox(node))) << "interior node " << visit.node;
      stack.push_back({node.leftFirst, visit.depth + 1});
      stack.push_back({node.leftFirst + 1, visit.depth + 1});
      continue;
    }
    ++leaves;
    deepest = std::max(deepest, visit.depth);
    EXPECT_LE(node.count, options.maxLeafSize);
    ASSERT_LE(std::size_t(node.leftFirst) + node.count, items.size());
    Aabb itemsBox;
    for (std::uint32_t slot = node.leftFirst; slot < node.leftFirst + node.count; ++slot) {
      ++slotSeen[slot];
      itemsBox.extend(items[bvh.itemOrder[slot]]);
    }
    EXPECT_TRUE(sameBox(itemsBox, nodeBox(node))) << "leaf " << visit.node;
  }
  for (std::size_t slot = 0; slot < items.size(); ++slot) ASSERT_EQ(slotSeen[slot], 1) << "leaf slot " << slot;
  for (std::size_t n = 0; n < bvh.nodes.size(); ++n) ASSERT_EQ(nodeSeen[n], 1) << "node " << n << " is unreachable";
  EXPECT_EQ(bvh.nodes.size(), 2 * leaves - 1);
  EXPECT_EQ(bvh.depth, deepest);
  EXPECT_LE(bvh.depth, options.maxDepth);
}

std::vector<Aabb> randomBoxes(std::size_t count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> position(-10.0f, 10.0f), size(0.0f, 0.5f);
  std::vector<Aabb> boxes;
  for (std::size_t i = 0; i < count; ++i) {
    const glm::vec3 p(position(rng), position(rng), position(rng));
    boxes.push_back(box(p, p + glm::vec3(size(rng), size(rng), size(rng))));
  }
  return boxes;
}

TEST(BvhBuild, RandomBoxesGiveAValidTree) {
  const std::vector<Aabb> boxes = randomBoxes(5000, 1);
  const Bvh bvh = buildBvh(boxes);
  expectValidBvh(bvh, boxes);
  // A reasonably balanced tree: far from both a list and the depth bound.
  EXPECT_LT(bvh.depth, 24u);
  const BvhBuildOptions singles{.maxLeafSize = 1};
  expectValidBvh(buildBvh(boxes, singles), boxes, singles);
}

TEST(BvhBuild, SahSeparatesTwoDistantClusters) {
  std::vector<Aabb> boxes;
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> jitter(0.0f, 3.0f);
  for (int i = 0; i < 16; ++i) {
    const glm::vec3 p(jitter(rng) + (i % 2 ? 100.0f : 0.0f), jitter(rng), jitter(rng));
    boxes.push_back(box(p, p + glm::vec3(1.0f)));
  }
  const Bvh bvh = buildBvh(boxes);
  expectValidBvh(bvh, boxes);
  ASSERT_EQ(bvh.nodes[0].count, 0u);
  const BvhBuildNode& a = bvh.nodes[bvh.nodes[0].leftFirst];
  const BvhBuildNode& b = bvh.nodes[bvh.nodes[0].leftFirst + 1];
  const float lowMax = std::min(a.boundsMax.x, b.boundsMax.x);
  const float highMin = std::max(a.boundsMin.x, b.boundsMin.x);
  EXPECT_LT(lowMax, 10.0f) << "one child holds exactly the cluster near x = 0";
  EXPECT_GT(highMin, 90.0f) << "the other exactly the cluster near x = 100";
}

TEST(BvhBuild, SahKeepsOverlappingItemsInOneLeafAndSplitsDistantOnes) {
  // Three boxes (a leaf's most) that nearly coincide: any split costs a
  // traversal plus about the same intersections, so the SAH keeps one leaf.
  const std::vector<Aabb> overlapping = {box(glm::vec3(0.00f), glm::vec3(10.00f)),
                                         box(glm::vec3(0.01f), glm::vec3(10.01f)),
                                         box(glm::vec3(0.02f), glm::vec3(10.02f))};
  const Bvh kept = buildBvh(overlapping);
  expectValidBvh(kept, overlapping);
  EXPECT_EQ(kept.nodes.size(), 1u);
  EXPECT_EQ(kept.nodes[0].count, 3u);
  // Four small boxes in two distant pairs: the root splits them (rays that
  // reach one pair skip the other), each pair stays a leaf (as above).
  const std::vector<Aabb> distant = {box(glm::vec3(0.0f), glm::vec3(1.0f)), box(glm::vec3(0.1f), glm::vec3(1.1f)),
                                     box(glm::vec3(50.0f), glm::vec3(51.0f)), box(glm::vec3(50.1f), glm::vec3(51.1f))};
  const Bvh split = buildBvh(distant);
  expectValidBvh(split, distant);
  ASSERT_EQ(split.nodes.size(), 3u);
  EXPECT_EQ(split.nodes[1].count, 2u);
  EXPECT_EQ(split.nodes[2].count, 2u);
}

TEST(BvhBuild, DegenerateInputs) {
  expectValidBvh(buildBvh({}), {});

  const std::vector<Aabb> one = {box(glm::vec3(1.0f, 2.0f, 3.0f), glm::vec3(2.0f, 3.0f, 4.0f))};
  const Bvh single = buildBvh(one);
  expectValidBvh(single, one);
  ASSERT_EQ(single.nodes.size(), 1u);
  EXPECT_EQ(single.nodes[0].count, 1u);

  // All centroids equal: no SAH split exists; median splits by count.
  const std::vector<Aabb> same(1000, box(glm::vec3(-1.0f), glm::vec3(1.0f)));
  const Bvh stacked = buildBvh(same);
  expectValidBvh(stacked, same);
  EXPECT_EQ(stacked.depth, 9u) << "1000 items, 3 per leaf, halving: ceil(log2(1000 / 3)) levels";

  // Points (zero volume and area) and flat boxes (zero volume).
  std::vector<Aabb> points, flat;
  for (int i = 0; i < 300; ++i) {
    const glm::vec3 p(float(i % 17), float(i % 5), 0.0f);
    points.push_back(box(p, p));
    flat.push_back(box(p, p + glm::vec3(1.0f, 1.0f, 0.0f)));
  }
  expectValidBvh(buildBvh(points), points);
  expectValidBvh(buildBvh(flat), flat);

  EXPECT_THROW(buildBvh(one, {.maxLeafSize = 0}), std::invalid_argument);
  EXPECT_THROW(buildBvh(randomBoxes(5, 3), {.maxLeafSize = 1, .maxDepth = 2}), std::invalid_argument)
      << "5 items cannot fit in 4 leaves of 1";
}

TEST(BvhBuild, DepthStaysWithinTheBoundWhereSahWouldGoDeeper) {
  // Exponentially spaced boxes: the SAH peels a few items off the far end at
  // each level, which makes a very deep tree unless median splits step in.
  std::vector<Aabb> boxes;
  for (int i = 0; i < 2000; ++i) {
    const float x = std::pow(1.02f, float(i));
    boxes.push_back(box(glm::vec3(x, 0.0f, 0.0f), glm::vec3(x * 1.001f, 1.0f, 1.0f)));
  }
  const BvhBuildOptions unbounded{.maxDepth = 1000};
  const Bvh deep = buildBvh(boxes, unbounded);
  expectValidBvh(deep, boxes, unbounded);
  ASSERT_GT(deep.depth, 12u) << "the input must be one where the SAH alone goes deep";
  const BvhBuildOptions bounded{.maxDepth = 12};
  const Bvh shallow = buildBvh(boxes, bounded);
  expectValidBvh(shallow, boxes, bounded);
  expectValidBvh(buildBvh(boxes), boxes);
}

// ---------------------------------------------------------------------------
// The procedural test scene: a noisy sphere of ~100k triangles, a ground
// grid and two triangle soups (one Mask, one Blend material), placed by
// translated, rotated and non-uniformly scaled instances.

scene::Mesh noisySphere(int rings, int segments, float noise, unsigned seed) {
  scene::Mesh mesh;
  mesh.name = "noisy sphere";
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> bump(-noise, noise);
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const float theta = float(M_PI) * float(r) / float(rings);
      const float phi = 2.0f * float(M_PI) * float(s) / float(segments);
      const float radius = 1.0f + bump(rng);
      mesh.positions.push_back(
          radius * glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
    }
  // The pole rows make zero-area triangles: they must never be hit nor break anything.
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const auto a = std::uint32_t(r * (segments + 1) + s), b = a + 1, c = a + std::uint32_t(segments + 1), d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, c, b, b, c, d});
    }
  return mesh;
}

scene::Mesh grid(int cells) {
  scene::Mesh mesh;
  mesh.name = "grid";
  for (int z = 0; z <= cells; ++z)
    for (int x = 0; x <= cells; ++x)
      mesh.positions.emplace_back(2.0f * float(x) / float(cells) - 1.0f, 0.0f, 2.0f * float(z) / float(cells) - 1.0f);
  for (int z = 0; z < cells; ++z)
    for (int x = 0; x < cells; ++x) {
      const auto a = std::uint32_t(z * (cells + 1) + x), b = a + 1, c = a + std::uint32_t(cells + 1), d = c + 1;
      mesh.indices.insert(mesh.indices.end(), {a, b, c, b, d, c});
    }
  return mesh;
}

scene::Mesh triangleSoup(int count, int material, unsigned seed) {
  scene::Mesh mesh;
  mesh.name = "soup";
  mesh.material = material;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> position(-1.0f, 1.0f), offset(-0.15f, 0.15f);
  for (int t = 0; t < count; ++t) {
    const glm::vec3 centre(position(rng), position(rng), position(rng));
    for (int v = 0; v < 3; ++v) {
      mesh.indices.push_back(std::uint32_t(mesh.positions.size()));
      mesh.positions.push_back(centre + glm::vec3(offset(rng), offset(rng), offset(rng)));
    }
  }
  return mesh;
}

scene::Scene proceduralScene() {
  scene::Scene s;
  s.name = "bvh test scene";
  s.materials.resize(4);
  s.materials[2].alphaMode = scene::AlphaMode::Mask;
  s.materials[3].alphaMode = scene::AlphaMode::Blend;
  s.meshes.push_back(noisySphere(158, 316, 0.04f, 7));  // 99,856 triangles
  s.meshes.push_back(grid(40));
  s.meshes.push_back(triangleSoup(4000, 2, 11));
  s.meshes.push_back(triangleSoup(3000, 3, 12));
  s.meshes.push_back(scene::Mesh{.name = "empty"});
  s.meshes[1].material = 1;
  return s;
}

glm::mat4 placement(glm::vec3 translation, float angle, glm::vec3 axis, glm::vec3 scale) {
  return glm::translate(glm::mat4(1.0f), translation) * glm::rotate(glm::mat4(1.0f), angle, glm::normalize(axis)) *
         glm::scale(glm::mat4(1.0f), scale);
}

// One mesh: the triangle (0,0,0), (1,0,0), (0,1,0); one default material.
scene::Scene oneTriangleScene() {
  scene::Scene s;
  s.materials.resize(1);
  scene::Mesh triangle;
  triangle.positions = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  triangle.indices = {0, 1, 2};
  s.meshes.push_back(triangle);
  return s;
}

std::vector<scene::Instance> proceduralInstances() {
  return {
      {0, 0, placement({0.0f, 1.0f, 0.0f}, 0.0f, {0, 1, 0}, glm::vec3(1.0f))},
      {0, 1, placement({3.0f, 1.0f, -1.0f}, 0.7f, {1, 1, 0}, {1.5f, 0.5f, 1.0f})},
      {0, 2, placement({-3.0f, 1.5f, 0.5f}, 2.0f, {0, 0, 1}, {0.3f, 1.2f, 0.8f})},
      {1, 3, placement({0.0f, 0.0f, 0.0f}, 0.1f, {0, 1, 0}, {8.0f, 1.0f, 8.0f})},
      {2, 4, placement({0.0f, 2.0f, -3.0f}, 0.5f, {1, 0, 1}, glm::vec3(2.0f))},
      {3, 5, placement({1.0f, 2.5f, 3.0f}, 1.0f, {0, 1, 0}, {1.0f, 2.0f, 0.5f})},
      {4, 6, glm::mat4(1.0f)},                                                     // empty mesh: nothing to hit
      {0, 7, placement({0.0f, 5.0f, 0.0f}, 0.0f, {0, 1, 0}, {1.0f, 0.0f, 1.0f})},  // singular: left out
  };
}

// ---------------------------------------------------------------------------
// The traversal layout: SceneBvh's arrays as the GPU reads them

TEST(BvhLayout, MetaBytesRoundTrip) {
  for (std::uint32_t slot = 0; slot < shared::kBvhWideArity; ++slot) {
    const std::uint32_t meta = shared::bvhWideMetaInterior(slot);
    EXPECT_TRUE(shared::bvhWideMetaIsInterior(meta)) << "slot " << slot;
    EXPECT_EQ(meta >> 5, 1u) << "an interior child is one bit of a traversal mask";
    EXPECT_EQ(meta & 0x1fu, 24u + slot) << "at 24 + its slot";
  }
  for (std::uint32_t count = 1; count <= shared::kBvhMaxLeafSize; ++count)
    for (std::uint32_t offset = 0; offset + count <= shared::kBvhWideMaxItems; ++offset) {
      const std::uint32_t meta = shared::bvhWideMetaLeaf(offset, count);
      EXPECT_FALSE(shared::bvhWideMetaIsInterior(meta)) << offset << ", " << count;
      EXPECT_EQ(shared::bvhWideMetaLeafOffset(meta), offset);
      EXPECT_EQ(shared::bvhWideMetaLeafCount(meta), count);
      EXPECT_NE(meta, 0u) << "0 is an empty slot";
      EXPECT_EQ((meta >> 5) << offset, ((1u << count) - 1u) << offset) << "its items' bits of a traversal mask";
    }
}

struct LayoutWalk {
  std::vector<int> nodeVisits;  // per node of the array walked
  std::vector<int> itemVisits;  // per leaf item (triangle or instance record)
  std::uint32_t levels = 0;     // of wide nodes below the roots walked (a root alone: 1)
};

// The exact box of a leaf's items, which the caller also checks.
using LeafItems = std::function<Aabb(std::uint32_t first, std::uint32_t count)>;

// Walks the wide tree below node `index` (at `level`; root = 0), checking
// every promise of its layout: each slot's quantised box holds its child's
// exact bounds (the union of its own children's, or its leaf's items') and
// is at most one step of the node's grid larger on each side; an interior
// child's meta byte and interior-mask bit; interior children consecutive
// from firstChild in slot order (how the walk numbers them); leaves of
// 1..maxLeafSize items, consecutive from firstItem in slot order, at most
// 24 in a node. Counts visits; returns the exact bounds below the node.
Aabb walkNode(const std::vector<BvhWideNode>& nodes, std::uint32_t index, std::uint32_t level,
              std::uint32_t maxLeafSize, const LeafItems& leafItems, LayoutWalk& walk) {
  if (index >= nodes.size()) {
    ADD_FAILURE() << "node " << index << " out of range";
    return {};
  }
  ++walk.nodeVisits[index];
  walk.levels = std::max(walk.levels, level + 1);
  const BvhWideNode& node = nodes[index];
  const glm::vec3 scale = shared::bvhWideScale(node);
  const std::uint32_t interiorMask = shared::bvhWideInteriorMask(node);
  std::uint32_t interiors = 0, items = 0;
  Aabb bounds;
  for (std::uint32_t slot = 0; slot < shared::kBvhWideArity; ++slot) {
    const std::uint32_t meta = shared::bvhWideMeta(node, slot);
    const bool interior = shared::bvhWideMetaIsInterior(meta);
    EXPECT_EQ((interiorMask >> slot) & 1u, interior ? 1u : 0u) << "node " << index << " slot " << slot;
    if (meta == 0) continue;
    Aabb exact;
    if (interior) {
      EXPECT_EQ(meta, shared::bvhWideMetaInterior(slot)) << "node " << index << " slot " << slot;
      exact = walkNode(nodes, node.childrenMeta.x + interiors, level + 1, maxLeafSize, leafItems, walk);
      ++interiors;
    } else {
      const std::uint32_t offset = shared::bvhWideMetaLeafOffset(meta), count = shared::bvhWideMetaLeafCount(meta);
      EXPECT_GE(count, 1u);
      EXPECT_LE(count, maxLeafSize) << "node " << index;
      EXPECT_EQ(meta, shared::bvhWideMetaLeaf(offset, count)) << "node " << index << " slot " << slot;
      EXPECT_EQ(offset, items) << "node " << index << ": its leaves' items follow each other in slot order";
      items += count;
      const std::uint32_t first = node.childrenMeta.y + offset;
      for (std::uint32_t item = first; item < first + count; ++item) {
        if (item >= walk.itemVisits.size()) {
          ADD_FAILURE() << "node " << index << ": leaf item " << item << " out of range";
          return bounds;
        }
        ++walk.itemVisits[item];
      }
      exact = leafItems(first, count);
    }
    glm::vec3 boxMin, boxMax;
    shared::bvhWideChildBox(node, slot, boxMin, boxMax);
    const Aabb box{boxMin, boxMax};
    EXPECT_TRUE(box.contains(exact)) << "node " << index << " slot " << slot << ": its box holds its child";
    const glm::vec3 slack = scale + (glm::abs(exact.min) + glm::abs(exact.max)) * 1e-6f;
    EXPECT_TRUE(glm::all(glm::lessThanEqual(exact.min - box.min, slack)) &&
                glm::all(glm::lessThanEqual(box.max - exact.max, slack)))
        << "node " << index << " slot " << slot << ": and is at most a grid step larger";
    bounds.extend(exact);
  }
  EXPECT_LE(items, shared::kBvhWideMaxItems) << "node " << index;
  return bounds;
}

void expectEachVisitedOnce(const std::vector<int>& visits, const char* what) {
  for (std::size_t i = 0; i < visits.size(); ++i) ASSERT_EQ(visits[i], 1) << what << " " << i;
}

// Every promise of the arrays the GPU reads: after the vertex positions,
// each triangle's corners copied from them in leaf order (with its material
// word and index in the w of the first two); each BLAS and the TLAS a tree of
// interior nodes whose stored child boxes are exactly the children's bounds,
// reaching every node and every item once; no leaf deeper than the stack
// bound assumes.
void expectValidTraversalLayout(const SceneBvh& bvh, std::size_t meshCount) {
  const std::vector<glm::uvec4>& triangles = bvh.triangles();
  const std::vector<glm::vec4>& positions = bvh.positions();
  const std::uint32_t firstRecord = bvh.firstCornerRecord();
  ASSERT_GE(3 * firstRecord, bvh.vertexCount());
  ASSERT_LT(3 * firstRecord, bvh.vertexCount() + 3) << "corner records follow the vertices";
  ASSERT_EQ(positions.size(), 3 * (firstRecord + triangles.size()));
  const auto corner = [&](std::uint32_t triangle, int c) { return positions[3 * (firstRecord + triangle) + c]; };
  for (std::uint32_t t = 0; t < triangles.size(); ++t) {
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(glm::vec3(corner(t, c)), glm::vec3(positions[triangles[t][c]])) << "triangle " << t << " corner " << c;
    ASSERT_EQ(glm::floatBitsToUint(corner(t, 0).w), triangles[t].w) << "triangle " << t;
    ASSERT_EQ(glm::floatBitsToUint(corner(t, 1).w), t);
    ASSERT_EQ(corner(t, 2).w, 1.0f);
  }

  LayoutWalk blas{std::vector<int>(bvh.blasNodes().size()), std::vector<int>(firstRecord + triangles.size())};
  for (std::size_t m = 0; m < meshCount; ++m) {
    const std::uint32_t begin = bvh.meshFirstTriangle(m), end = bvh.meshFirstTriangle(m + 1);
    if (begin == end) {
      EXPECT_EQ(bvh.blasRoot(m), kBvhInvalidIndex);
      EXPECT_TRUE(bvh.meshBounds(m).empty());
      continue;
    }
    // Leaves reference corner records.
    const LeafItems trianglesInLeaf = [&](std::uint32_t first, std::uint32_t count) {
      const bool inMesh = first >= firstRecord + begin && first + count <= firstRecord + end;
      EXPECT_TRUE(inMesh) << "mesh " << m << "'s BLAS reaches only its triangles";
      Aabb items;
      if (!inMesh) return items;
      for (std::uint32_t k = first; k < first + count; ++k)
        for (int c = 0; c < 3; ++c) items.extend(glm::vec3(corner(k - firstRecord, c)));
      return items;
    };
    const Aabb bounds = walkNode(bvh.blasNodes(), bvh.blasRoot(m), 0, shared::kBvhMaxLeafSize, trianglesInLeaf, blas);
    EXPECT_TRUE(sameBox(bounds, bvh.meshBounds(m))) << "mesh " << m;
  }
  expectEachVisitedOnce(blas.nodeVisits, "BLAS node");
  expectEachVisitedOnce(std::vector<int>(blas.itemVisits.begin() + firstRecord, blas.itemVisits.end()), "triangle");
  EXPECT_EQ(std::count(blas.itemVisits.begin(), blas.itemVisits.begin() + firstRecord, 0), firstRecord)
      << "leaves reference corner records only";
  EXPECT_LE(blas.levels, std::max(bvh.blasDepth(), 1u)) << "a wide tree is no deeper than its binary tree";

  LayoutWalk tlas{std::vector<int>(bvh.tlasNodes().size()), std::vector<int>(bvh.instances().size())};
  const LeafItems instanceInLeaf = [&](std::uint32_t first, std::uint32_t count) {
    EXPECT_EQ(count, 1u) << "a TLAS leaf holds one instance";
    Aabb world;
    if (first >= bvh.instances().size()) return world;
    const BvhInstance& record = bvh.instances()[first];
    const Aabb object = bvh.meshBounds(record.info.y);
    for (int corner = 0; corner < 8; ++corner)
      world.extend(shared::bvhTransformPoint(
          record.objectToWorld, glm::vec3(corner & 1 ? object.max.x : object.min.x,
                                          corner & 2 ? object.max.y : object.min.y,
                                          corner & 4 ? object.max.z : object.min.z)));
    return world;
  };
  const Aabb tlasBounds = walkNode(bvh.tlasNodes(), 0, 0, 1, instanceInLeaf, tlas);
  EXPECT_TRUE(bvh.tlasBounds().contains(tlasBounds));
  expectEachVisitedOnce(tlas.nodeVisits, "TLAS node");
  expectEachVisitedOnce(tlas.itemVisits, "instance record");
  EXPECT_LE(tlas.levels, std::max(bvh.tlasDepth(), 1u));
}

// ---------------------------------------------------------------------------
// Rays and the brute-force reference

glm::vec3 rayOrigin(const BvhRay& r) { return {r.originTMin.x, r.originTMin.y, r.originTMin.z}; }
glm::vec3 rayDirection(const BvhRay& r) { return {r.directionTMax.x, r.directionTMax.y, r.directionTMax.z}; }

// Half the rays aim at a random point of a random triangle of a random
// instance (they mostly hit); the rest go in random directions. Direction
// lengths vary (t is in their units); some rays have tMin > 0 or a finite tMax.
std::vector<BvhRay> makeRays(const SceneBvh& bvh, std::size_t count, float originSpread, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const Aabb bounds = bvh.tlasBounds();
  const glm::vec3 centre = bounds.centroid();
  const glm::vec3 half = (bounds.max - bounds.min) * 0.5f * originSpread;
  std::vector<BvhRay> rays;
  for (std::size_t i = 0; i < count; ++i) {
    const glm::vec3 origin = centre + half * glm::vec3(2 * unit(rng) - 1, 2 * unit(rng) - 1, 2 * unit(rng) - 1);
    glm::vec3 target;
    if (i % 2 == 0) {
      const BvhInstance& instance =
          bvh.instances()[std::size_t(unit(rng) * float(bvh.instances().size())) % bvh.instances().size()];
      const std::uint32_t mesh = instance.info.y;
      const std::uint32_t first = bvh.meshFirstTriangle(mesh), last = bvh.meshFirstTriangle(mesh + 1);
      const glm::uvec4 triangle =
          bvh.triangles()[first + std::uint32_t(unit(rng) * float(last - first)) % (last - first)];
      float u = unit(rng), v = unit(rng);
      if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
      const glm::vec3 p0(bvh.positions()[triangle.x]), p1(bvh.positions()[triangle.y]), p2(bvh.positions()[triangle.z]);
      target = shared::bvhTransformPoint(instance.objectToWorld, p0 * (1 - u - v) + p1 * u + p2 * v);
    } else {
      target = origin + glm::vec3(2 * unit(rng) - 1, 2 * unit(rng) - 1, 2 * unit(rng) - 1);
    }
    const float distance = glm::length(target - origin);
    const glm::vec3 direction = glm::normalize(target - origin) * (0.5f + 1.5f * unit(rng));
    const float tMin = i % 5 == 1 ? unit(rng) * 0.5f * distance : 0.0f;
    const float tMax = i % 3 == 1 ? (0.2f + 1.3f * unit(rng)) * distance : 1e30f;
    rays.push_back({glm::vec4(origin, tMin), glm::vec4(direction, tMax)});
  }
  return rays;
}

// Within `tolerance` of an edge (or vertex) of its triangle: there, float
// rounding on another device may put the hit on the neighbour or nowhere.
bool nearEdge(glm::vec2 barycentrics, float tolerance = 1e-4f) {
  return std::min({barycentrics.x, barycentrics.y, 1.0f - barycentrics.x - barycentrics.y}) < tolerance;
}

bool nearIntervalEnd(float t, const BvhRay& ray) {
  return std::abs(t - ray.originTMin.w) <= 1e-5f * std::abs(t) || std::abs(t - ray.directionTMax.w) <= 1e-5f * t;
}

struct Reference {
  BvhHit closest;
  bool identityClear = true;  // the closest hit is clearly closer than any other and not on an edge
  bool blocked = false;       // any hit at all
  bool blockedClear = true;   // some hit is clearly inside its triangle (or there is none)
  // How far the closest hit's barycentrics may be from brute force's: 1e-3,
  // or more where the triangle is so small against the ray's length that
  // rounding moves them further. Moving the hit point by d changes a
  // barycentric by at most d / the triangle's shortest altitude; the point
  // is known to about 1e-4 of t along the ray (the tolerance on t), and
  // Moller-Trumbore from a far origin loses that much where the compiler
  // fuses its products differently (lavapipe with the wide BVH's walk did,
  // by 0.0027 on a 3 cm triangle hit from 8 m).
  float barycentricTolerance = 1e-3f;
};

// The barycentric tolerance for a hit on `triangle` at t along a ray of
// `direction` (world space), seen through instance record `instance`.
float barycentricTolerance(const SceneBvh& bvh, const BvhHit& hit, glm::vec3 worldDirection) {
  for (const BvhInstance& record : bvh.instances()) {
    if (record.info.z != hit.instance) continue;
    const glm::uvec4& triangle = bvh.triangles()[hit.triangle];
    const glm::vec3 p0(bvh.positions()[triangle.x]), p1(bvh.positions()[triangle.y]), p2(bvh.positions()[triangle.z]);
    const float twiceArea = glm::length(glm::cross(p1 - p0, p2 - p0));
    const float longestEdge = std::max({glm::length(p1 - p0), glm::length(p2 - p1), glm::length(p0 - p2)});
    const float shortestAltitude = twiceArea / longestEdge;
    const float along = 1e-4f * hit.t * glm::length(shared::bvhTransformVector(record.worldToObject, worldDirection));
    return std::max(1e-3f, along / shortestAltitude);
  }
  return 1e-3f;
}

Reference bruteForce(const SceneBvh& bvh, const BvhRay& ray, const BvhAlphaTest& alphaTest = {}) {
  Reference ref;
  const std::vector<BvhHit> hits =
      bvh.traceAllBruteForce(rayOrigin(ray), rayDirection(ray), ray.originTMin.w, ray.directionTMax.w, alphaTest);
  ref.closest = {kNoHit, kBvhInvalidIndex, kBvhInvalidIndex, glm::vec2(0.0f)};
  for (const BvhHit& hit : hits)
    if (hit.t < ref.closest.t) ref.closest = hit;
  ref.blocked = !hits.empty();
  if (hits.empty()) return ref;
  ref.blockedClear = std::any_of(hits.begin(), hits.end(), [&](const BvhHit& h) {
    return !nearEdge(h.barycentrics) && !nearIntervalEnd(h.t, ray);
  });
  ref.identityClear = !nearEdge(ref.closest.barycentrics) && !nearIntervalEnd(ref.closest.t, ray);
  ref.barycentricTolerance = barycentricTolerance(bvh, ref.closest, rayDirection(ray));
  for (const BvhHit& hit : hits)
    if ((hit.instance != ref.closest.instance || hit.triangle != ref.closest.triangle) &&
        hit.t <= ref.closest.t * (1.0f + 1e-4f))
      ref.identityClear = false;
  return ref;
}

// Brute force is most of this file's run time: it is spread over the cores.
std::vector<Reference> bruteForceAll(const SceneBvh& bvh, const std::vector<BvhRay>& rays,
                                     const BvhAlphaTest& alphaTest = {}) {
  std::vector<Reference> refs(rays.size());
  const std::size_t threadCount = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < threadCount; ++t)
    threads.emplace_back([&, t] {
      for (std::size_t i = t; i < rays.size(); i += threadCount) refs[i] = bruteForce(bvh, rays[i], alphaTest);
    });
  for (std::thread& thread : threads) thread.join();
  return refs;
}

// How a traversal's answers compare with brute force over a set of rays.
struct Agreement {
  int hits = 0, misses = 0, blocked = 0, unblocked = 0;
  int excused = 0;  // disagreements the reference marks as unclear (edge or interval-end grazes)
};

// Compares one closest-hit result with the reference; returns false (with a
// test failure) on a real disagreement, counts it as excused when the
// reference says the answer is unclear there.
void expectClosestAgrees(const Reference& ref, float t, std::uint32_t instance, std::uint32_t triangle,
                         glm::vec2 barycentrics, std::size_t rayIndex, Agreement& agreement) {
  const bool hit = t < kNoHit;
  const bool refHit = ref.closest.t < kNoHit;
  (refHit ? agreement.hits : agreement.misses)++;
  if (hit != refHit || (hit && std::abs(t - ref.closest.t) > 1e-4f * ref.closest.t)) {
    const bool unclear = (refHit && !ref.identityClear) || (hit && nearEdge(barycentrics));
    EXPECT_TRUE(unclear) << "ray " << rayIndex << ": t " << t << ", brute force " << ref.closest.t;
    agreement.excused += unclear;
    return;
  }
  if (hit && ref.identityClear) {
    EXPECT_EQ(instance, ref.closest.instance) << "ray " << rayIndex;
    EXPECT_EQ(triangle, ref.closest.triangle) << "ray " << rayIndex;
    EXPECT_NEAR(barycentrics.x, ref.closest.barycentrics.x, ref.barycentricTolerance) << "ray " << rayIndex;
    EXPECT_NEAR(barycentrics.y, ref.closest.barycentrics.y, ref.barycentricTolerance) << "ray " << rayIndex;
  }
}

void expectAnyAgrees(const Reference& ref, bool blocked, glm::vec2 barycentrics, std::size_t rayIndex,
                     Agreement& agreement) {
  (ref.blocked ? agreement.blocked : agreement.unblocked)++;
  if (blocked == ref.blocked) return;
  const bool unclear = !ref.blockedClear || (blocked && nearEdge(barycentrics));
  EXPECT_TRUE(unclear) << "ray " << rayIndex << ": any-hit " << blocked << ", brute force " << ref.blocked;
  agreement.excused += unclear;
}

void expectMostlyDecided(const Agreement& a, std::size_t rayCount) {
  EXPECT_GT(a.hits, int(rayCount) / 4) << "the rays must exercise hits";
  EXPECT_GT(a.misses, int(rayCount) / 20) << "and misses";
  EXPECT_LE(a.excused, int(rayCount) / 200) << "edge grazes are rare; many excused rays hide a bug";
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// ---------------------------------------------------------------------------
// CPU traversal

// Deep trees on both levels, and rays that wait at nearly every level of
// both: a mesh of triangles in the planes x = 2^i (each covering the half
// y + z >= 1 of the unit square [0, 1]^2 in y and z), which the SAH splits
// a few triangles at a time, so the BLAS is about 20 levels deep; and
// instances of it scaled by 2^j in y and z, whose boxes nest the same way,
// so the TLAS is as deep. A ray down the x axis at y = z = 0.75 is inside
// every box of both levels but outside every triangle (in instance j's
// object space it runs at y = z = 0.75 / 2^j); one at y = z = 1.5 hits
// instance 1 (scale 2) only.
scene::Scene deepStripScene() {
  scene::Scene s;
  s.name = "deep strip";
  s.materials.resize(1);
  scene::Mesh strip;
  for (int i = 0; i < 60; ++i) {
    const float x = std::ldexp(1.0f, i);
    const auto first = std::uint32_t(strip.positions.size());
    strip.positions.insert(strip.positions.end(), {{x, 1.0f, 0.0f}, {x, 0.0f, 1.0f}, {x, 1.0f, 1.0f}});
    strip.indices.insert(strip.indices.end(), {first, first + 1, first + 2});
  }
  s.meshes.push_back(strip);
  return s;
}

std::vector<scene::Instance> deepStripInstances() {
  std::vector<scene::Instance> instances;
  for (int j = 1; j <= 60; ++j) {
    const float scale = std::ldexp(1.0f, j);
    instances.push_back({0, j, placement(glm::vec3(0.0f), 0.0f, {0, 1, 0}, {1.0f, scale, scale})});
  }
  return instances;
}

std::vector<BvhRay> deepStripRays() {
  std::vector<BvhRay> rays;
  for (const float offset : {0.75f, 1.5f}) {
    rays.push_back({glm::vec4(-1.0f, offset, offset, 0.0f), glm::vec4(1.0f, 0.0f, 0.0f, 1e30f)});
    rays.push_back({glm::vec4(1e18f, offset, offset, 0.0f), glm::vec4(-1.0f, 0.0f, 0.0f, 1e30f)});
  }
  return rays;
}

TEST(SceneBvh, KnownHitOnAScaledInstance) {
  const scene::Scene s = oneTriangleScene();
  SceneBvh bvh(s);
  const std::vector<scene::Instance> instances = {
      {0, 0, placement({0.0f, 0.0f, -4.0f}, 0.0f, {0, 1, 0}, {2.0f, 4.0f, 3.0f})}};
  bvh.setInstances(instances);
  // Both trees are one leaf: each is a root with one slot.
  expectValidTraversalLayout(bvh, s.meshes.size());
  EXPECT_EQ(bvh.blasNodes().size(), 1u);
  EXPECT_EQ(bvh.tlasNodes().size(), 1u);
  // World triangle (0,0,-4), (2,0,-4), (0,4,-4); the ray goes down -Z through
  // (0.5, 1, 0) with a direction of length 2, so it hits at t = 2 with
  // u = 0.5 / 2 and v = 1 / 4.
  const BvhHit hit = bvh.traceClosest({0.5f, 1.0f, 0.0f}, {0.0f, 0.0f, -2.0f}, 0.0f, 1e30f);
  EXPECT_FLOAT_EQ(hit.t, 2.0f);
  EXPECT_EQ(hit.instance, 0u);
  EXPECT_EQ(hit.triangle, 0u);
  EXPECT_FLOAT_EQ(hit.barycentrics.x, 0.25f);
  EXPECT_FLOAT_EQ(hit.barycentrics.y, 0.25f);
  // Back faces are hit too, and the interval is open at both ends.
  EXPECT_FLOAT_EQ(bvh.traceClosest({0.5f, 1.0f, -8.0f}, {0.0f, 0.0f, 1.0f}, 0.0f, 1e30f).t, 4.0f);
  EXPECT_EQ(bvh.traceClosest({0.5f, 1.0f, 0.0f}, {0.0f, 0.0f, -2.0f}, 0.0f, 2.0f).t, kNoHit);
  EXPECT_FALSE(bvh.traceAny({0.5f, 1.0f, 0.0f}, {0.0f, 0.0f, -2.0f}, 2.0f, 1e30f));
  EXPECT_TRUE(bvh.traceAny({0.5f, 1.0f, 0.0f}, {0.0f, 0.0f, -2.0f}, 1.9f, 2.1f));
  EXPECT_EQ(bvh.traceClosest({3.0f, 1.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, 1e30f).t, kNoHit);
}

// The walk's counters (bench's "BVH walk" line): one triangle in one
// instance, each tree a root with one slot, so every step is known.
TEST(SceneBvh, WalkStatsCountTheNodesInstancesAndTrianglesTheWalkVisits) {
  const scene::Scene s = oneTriangleScene();
  SceneBvh bvh(s);
  bvh.setInstances(
      std::vector<scene::Instance>{{0, 0, placement({0.0f, 0.0f, -4.0f}, 0.0f, {0, 1, 0}, {2.0f, 4.0f, 3.0f})}});
  const BvhRay hits{glm::vec4(0.5f, 1.0f, 0.0f, 0.0f), glm::vec4(0.0f, 0.0f, -2.0f, 1e30f)};
  const BvhRay missesTheBox{glm::vec4(3.0f, 1.0f, 0.0f, 0.0f), glm::vec4(0.0f, 0.0f, -1.0f, 1e30f)};
  const BvhRay endsBeforeTheBox{glm::vec4(0.5f, 1.0f, 0.0f, 0.0f), glm::vec4(0.0f, 0.0f, -2.0f, 1.0f)};
  for (const bool anyHit : {false, true}) {
    SCOPED_TRACE(anyHit ? "any hit" : "closest hit");
    // TLAS root, the instance, its BLAS root, the triangle.
    BvhWalkStats one = bvh.walkStats(std::vector<BvhRay>{hits}, anyHit);
    EXPECT_EQ(one.rays, 1u);
    EXPECT_EQ(one.nodes, 2u);
    EXPECT_EQ(one.instances, 1u);
    EXPECT_EQ(one.triangles, 1u);
    // The TLAS root's one box is missed: nothing more.
    for (const BvhRay& ray : {missesTheBox, endsBeforeTheBox}) {
      const BvhWalkStats none = bvh.walkStats(std::vector<BvhRay>{ray}, anyHit);
      EXPECT_EQ(none.nodes, 1u);
      EXPECT_EQ(none.instances, 0u);
      EXPECT_EQ(none.triangles, 0u);
    }
    // Sums over many rays, whichever thread walked each.
    const std::vector<BvhRay> many(999, hits);
    const BvhWalkStats all = bvh.walkStats(many, anyHit);
    EXPECT_EQ(all.rays, 999u);
    EXPECT_EQ(all.nodes, 2u * 999u);
    EXPECT_DOUBLE_EQ(all.perRay(all.triangles), 1.0);
  }
}

// A float determinant overflows at a scale of 1e13 and underflows at 1e-13;
// such instances used to be left out as if singular. Only transforms with no
// inverse in floats are left out now, and they are listed.
TEST(SceneBvh, InstancesScaledFarFromOneAreTracedAndOnlyUninvertibleOnesLeftOut) {
  const scene::Scene s = oneTriangleScene();
  SceneBvh bvh(s);
  const std::vector<scene::Instance> instances = {
      {0, 0, placement({100.0f, 0.0f, -10.0f}, 0.0f, {0, 1, 0}, glm::vec3(1e15f))},  // 1e15 m wide
      {0, 1, placement({0.0f, 0.0f, -20.0f}, 0.0f, {0, 1, 0}, glm::vec3(1e-15f))},   // a femtometre wide
      {0, 2, placement({0.0f, 0.0f, -30.0f}, 0.0f, {0, 1, 0}, {1.0f, 0.0f, 1.0f})},  // flattened: singular
      {0, 3, placement({0.0f, 0.0f, -40.0f}, 0.0f, {0, 1, 0}, glm::vec3(1e-39f))},   // inverse beyond float
  };
  bvh.setInstances(instances);
  EXPECT_EQ(bvh.instances().size(), 2u);
  EXPECT_EQ(bvh.untraceableInstances(), (std::vector<std::size_t>{2, 3}));
  const BvhHit big = bvh.traceClosest({101.0f, 1.0f, 0.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, 1e30f);
  EXPECT_EQ(big.instance, 0u);
  EXPECT_NEAR(big.t, 10.0f, 1e-4f);
  const BvhHit small = bvh.traceClosest({2e-16f, 2e-16f, 0.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, 1e30f);
  EXPECT_EQ(small.instance, 1u);
  EXPECT_NEAR(small.t, 20.0f, 1e-4f);
  EXPECT_NEAR(small.barycentrics.x, 0.2f, 1e-4f);

  bvh.setInstances(std::span(instances).first(2));
  EXPECT_TRUE(bvh.untraceableInstances().empty()) << "each call lists its own";
}

// The stack holds one waiting child per depth of the TLAS and then of one
// BLAS (docs/bvh.md): here both levels are deep and the rays wait at nearly
// every level, more levels together than either tree has alone.
TEST(SceneBvh, DeepTreesOnBothLevelsFitTheStack) {
  const scene::Scene s = deepStripScene();
  SceneBvh bvh(s);
  bvh.setInstances(deepStripInstances());
  expectValidTraversalLayout(bvh, s.meshes.size());
  std::cout << "depth: BLAS " << bvh.blasDepth() << ", TLAS " << bvh.tlasDepth() << "\n";
  EXPECT_GT(bvh.blasDepth() + bvh.tlasDepth(), shared::kBvhMaxDepth) << "deeper together than one level's bound";
  const std::vector<BvhRay> rays = deepStripRays();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const BvhRay& ray = rays[i];
    const BvhHit expected =
        bvh.traceClosestBruteForce(rayOrigin(ray), rayDirection(ray), ray.originTMin.w, ray.directionTMax.w);
    // The CPU traversal throws when its stack is full.
    const BvhHit hit = bvh.traceClosest(rayOrigin(ray), rayDirection(ray), ray.originTMin.w, ray.directionTMax.w);
    EXPECT_EQ(hit.t, expected.t) << "ray " << i;
    EXPECT_EQ(hit.instance, expected.instance) << "ray " << i;
    EXPECT_EQ(hit.triangle, expected.triangle) << "ray " << i;
    EXPECT_EQ(bvh.traceAny(rayOrigin(ray), rayDirection(ray), ray.originTMin.w, ray.directionTMax.w),
              expected.t < kNoHit);
    EXPECT_EQ(expected.t < kNoHit, i >= 2) << "ray " << i;
    if (expected.t < kNoHit) {
      EXPECT_EQ(expected.instance, 0u) << "only the instance of scale 2 is hit";
    }
  }
}

TEST(SceneBvh, EmptySceneHasAnEmptyRootThatNoRayEnters) {
  scene::Scene s;
  s.materials.resize(1);
  s.meshes.push_back(scene::Mesh{.name = "empty"});
  SceneBvh bvh(s);
  const std::vector<scene::Instance> instances = {{0, 0, glm::mat4(1.0f)}};
  bvh.setInstances(instances);
  EXPECT_TRUE(bvh.instances().empty());
  EXPECT_TRUE(bvh.tlasBounds().empty());
  expectValidTraversalLayout(bvh, s.meshes.size());
  ASSERT_EQ(bvh.tlasNodes().size(), 1u);
  const BvhWideNode& root = bvh.tlasNodes()[0];
  EXPECT_EQ(root.childrenMeta.z, 0u) << "no children";
  EXPECT_EQ(root.childrenMeta.w, 0u);
  for (const glm::vec3 direction : {glm::vec3(1, 0, 0), glm::vec3(0, 0, -1), glm::vec3(0.3f, -0.2f, 0.9f)}) {
    EXPECT_EQ(bvh.traceClosest(glm::vec3(0.0f), direction, 0.0f, 1e30f).t, kNoHit);
    EXPECT_FALSE(bvh.traceAny(glm::vec3(0.0f), direction, 0.0f, 1e30f));
    const glm::vec3 inverse = shared::bvhSafeInverse(direction);
    EXPECT_EQ(shared::bvhWideIntersectChildren(root, glm::vec3(0.0f), inverse, 0u, -1e30f, 1e30f), 0u);
  }
}

TEST(SceneBvh, FlattenedArraysAreConsistent) {
  const scene::Scene s = proceduralScene();
  SceneBvh bvh(s);
  const std::vector<scene::Instance> instances = proceduralInstances();
  bvh.setInstances(instances);
  EXPECT_EQ(bvh.instances().size(), instances.size() - 2) << "empty mesh and singular transform left out";
  expectValidTraversalLayout(bvh, s.meshes.size());
  EXPECT_EQ(bvh.blasRoot(4), kBvhInvalidIndex);
  EXPECT_LE(bvh.blasDepth(), shared::kBvhMaxDepth);
  std::size_t triangleTotal = 0;
  for (const scene::Mesh& mesh : s.meshes) triangleTotal += mesh.indices.size() / 3;
  ASSERT_EQ(bvh.triangles().size(), triangleTotal);
  for (std::size_t m = 0; m < s.meshes.size(); ++m) {
    std::uint32_t vertexOffset = 0;
    for (std::size_t k = 0; k < m; ++k) vertexOffset += std::uint32_t(s.meshes[k].positions.size());
    std::vector<int> seen(s.meshes[m].indices.size() / 3, 0);
    for (std::uint32_t t = bvh.meshFirstTriangle(m); t < bvh.meshFirstTriangle(m + 1); ++t) {
      const glm::uvec4& triangle = bvh.triangles()[t];
      const std::uint32_t source = bvh.sourceTriangle(t);
      ++seen[source];
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(triangle[c], s.meshes[m].indices[3 * source + std::size_t(c)] + vertexOffset);
      const bool masked = s.materials[std::size_t(s.meshes[m].material)].alphaMode != scene::AlphaMode::Opaque;
      ASSERT_EQ(triangle.w, std::uint32_t(s.meshes[m].material) | (masked ? kBvhAlphaMaskedBit : 0u));
    }
    for (int count : seen) ASSERT_EQ(count, 1) << "mesh " << m;
  }
  for (const BvhInstance& instance : bvh.instances()) {
    const glm::mat4& objectToWorld = instances[instance.info.z].objectToWorld;
    EXPECT_EQ(instance.info.x, bvh.blasRoot(instance.info.y));
    const glm::vec3 p(0.3f, -0.7f, 0.2f);
    const glm::vec3 world = shared::bvhTransformPoint(instance.objectToWorld, p);
    EXPECT_LT(glm::length(world - glm::vec3(objectToWorld * glm::vec4(p, 1.0f))), 1e-5f);
    EXPECT_LT(glm::length(shared::bvhTransformPoint(instance.worldToObject, world) - p), 1e-4f);
  }
}

TEST(SceneBvh, TraversalMatchesBruteForceOnTransformedInstances) {
  const scene::Scene s = proceduralScene();
  auto start = std::chrono::steady_clock::now();
  SceneBvh bvh(s);
  std::cout << "BLAS build, " << bvh.triangles().size() << " triangles: " << bvh.blasBuildSeconds() * 1e3 << " ms\n";
  const std::vector<scene::Instance> instances = proceduralInstances();
  start = std::chrono::steady_clock::now();
  bvh.setInstances(instances);
  std::cout << "TLAS build, " << bvh.instances().size() << " instances: " << secondsSince(start) * 1e6 << " us\n";

  const std::vector<BvhRay> rays = makeRays(bvh, 2000, 1.3f, 21);
  const std::vector<Reference> refs = bruteForceAll(bvh, rays);
  Agreement closest, any;
  start = std::chrono::steady_clock::now();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const BvhRay& ray = rays[i];
    const BvhHit hit = bvh.traceClosest(rayOrigin(ray), rayDirection(ray), ray.originTMin.w, ray.directionTMax.w);
    expectClosestAgrees(refs[i], hit.t, hit.instance, hit.triangle, hit.barycentrics, i, closest);
    const bool blocked = bvh.traceAny(rayOrigin(ray), rayDirection(ray), ray.originTMin.w, ray.directionTMax.w);
    expectAnyAgrees(refs[i], blocked, glm::vec2(0.5f, 0.25f), i, any);
  }
  std::cout << "CPU traversal, closest + any: " << secondsSince(start) / double(rays.size()) * 1e6 << " us per ray\n";
  expectMostlyDecided(closest, rays.size());
  EXPECT_EQ(closest.excused, 0) << "the CPU traversal does the brute force's arithmetic: no excuses";
  EXPECT_EQ(any.excused, 0);
  EXPECT_GT(any.blocked, int(rays.size()) / 4);
  EXPECT_GT(any.unblocked, int(rays.size()) / 20);
}

// bench --ray-origins visible: every ray starts on (just off) the surface a
// pixel of the camera sees, on the camera's side, the pixels taken in 8x8
// tiles; the pixels that see nothing give no ray.
// Checks visibleSurfaceRays on a width x height view of `bvh` from `camera`.
void checkVisibleSurfaceRays(const SceneBvh& bvh, const scene::CameraPose& camera) {
  const std::uint32_t width = 44, height = 21;  // tiles cut at the right and bottom edges
  const shared::GpuCamera gpu = gpuCamera(camera, width, height);
  const glm::vec2 size{float(width), float(height)};

  // Which pixels see a surface, by brute force, and where each would come in 8x8 tiles.
  std::uint32_t visible = 0;
  std::vector<int> tileRank(std::size_t(width) * height, -1);
  int rank = 0;
  for (std::uint32_t ty = 0; ty < height; ty += 8)
    for (std::uint32_t tx = 0; tx < width; tx += 8)
      for (std::uint32_t y = ty; y < std::min(ty + 8, height); ++y)
        for (std::uint32_t x = tx; x < std::min(tx + 8, width); ++x) {
          const glm::vec3 d = shared::cameraRayDirection(gpu, glm::vec2(x, y) + 0.5f, size);
          if (bvh.traceClosestBruteForce(camera.position, d, 0.0f, kNoHit).t == kNoHit) continue;
          ++visible;
          tileRank[std::size_t(y) * width + x] = rank++;
        }
  ASSERT_GT(visible, width * height / 2) << "the view must see the scene";
  ASSERT_LT(visible, width * height) << "the view must see some sky too";

  const VisibleSurfaceRays result = visibleSurfaceRays(bvh, camera, width, height, visible);
  EXPECT_EQ(result.pixels, width * height);
  EXPECT_EQ(result.visiblePixels, visible);
  ASSERT_EQ(result.rays.size(), visible);
  int previousRank = -1;
  for (std::size_t r = 0; r < result.rays.size(); ++r) {
    const glm::vec3 origin(result.rays[r].originTMin);
    const glm::vec3 direction(result.rays[r].directionTMax);
    EXPECT_NEAR(glm::length(direction), 1.0f, 1e-5f);
    // The camera's own ray towards the origin reaches a surface just beyond it.
    const glm::vec3 toOrigin = origin - camera.position;
    const float distance = glm::length(toOrigin);
    const BvhHit hit = bvh.traceClosestBruteForce(camera.position, toOrigin / distance, 0.0f, kNoHit);
    ASSERT_NE(hit.instance, kBvhInvalidIndex) << "ray " << r;
    EXPECT_GT(hit.t, distance) << "ray " << r << ": the origin must be on the camera's side";
    EXPECT_LT(hit.t - distance, 1e-3f * (1.0f + distance)) << "ray " << r << ": the origin must be on the surface";
    // The ray leaves on the camera's side of that surface.
    const glm::uvec4 corners = bvh.triangles()[hit.triangle];
    const BvhInstance* record = nullptr;
    for (const BvhInstance& i : bvh.instances())
      if (i.info.z == hit.instance) record = &i;
    ASSERT_NE(record, nullptr);
    const auto world = [&](std::uint32_t v) {
      return shared::bvhTransformPoint(record->objectToWorld, glm::vec3(bvh.positions()[v]));
    };
    const glm::vec3 normal = glm::cross(world(corners.y) - world(corners.x), world(corners.z) - world(corners.x));
    EXPECT_GT(glm::dot(direction, normal) * glm::dot(-toOrigin, normal), 0.0f) << "ray " << r;
    // One ray a visible pixel, in tile order.
    const glm::vec3 pixel = shared::projectToPixel(gpu, origin, size);
    const int at = tileRank[std::size_t(pixel.y) * width + std::size_t(pixel.x)];
    EXPECT_GT(at, previousRank) << "ray " << r << " at pixel " << pixel.x << ", " << pixel.y;
    previousRank = at;
  }
  EXPECT_EQ(previousRank, int(visible) - 1);

  // Fewer rays than pixels spread over all of them; more repeat pixels.
  const VisibleSurfaceRays fewer = visibleSurfaceRays(bvh, camera, width, height, visible / 4);
  ASSERT_EQ(fewer.rays.size(), visible / 4);
  const glm::vec3 last = shared::projectToPixel(gpu, glm::vec3(fewer.rays.back().originTMin), size);
  EXPECT_GT(tileRank[std::size_t(last.y) * width + std::size_t(last.x)], int(visible) * 3 / 4);
  EXPECT_EQ(visibleSurfaceRays(bvh, camera, width, height, 3 * visible).rays.size(), 3 * visible);
}

TEST(BenchmarkRays, VisibleSurfaceRaysStartWhereTheCameraLooksInTileOrder) {
  const scene::Scene scene = scene::makeBuiltinScene("sun-room");
  SceneBvh bvh(scene);
  std::vector<scene::Instance> instances = scene::instancesAt(scene, 0.0f);
  bvh.setInstances(instances);
  const scene::CameraPose camera = scene::defaultCameraPath(scene)->pose(0.0f);
  {
    SCOPED_TRACE("the camera sees the triangles' front faces");
    checkVisibleSurfaceRays(bvh, camera);
  }
  // Mirrored (x -> -x), every triangle turns its back to the same view.
  const glm::mat4 mirror = glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f));
  for (scene::Instance& instance : instances) instance.objectToWorld = mirror * instance.objectToWorld;
  bvh.setInstances(instances);
  scene::CameraPose mirrored = camera;
  mirrored.position.x = -mirrored.position.x;
  mirrored.target.x = -mirrored.target.x;
  mirrored.up.x = -mirrored.up.x;
  {
    SCOPED_TRACE("the camera sees the triangles' back faces");
    checkVisibleSurfaceRays(bvh, mirrored);
  }

  // From outside the scene, looking away from it: no rays.
  const Aabb bounds = bvh.tlasBounds();
  scene::CameraPose away = camera;
  away.position = bounds.max + (bounds.max - bounds.min);
  away.target = away.position + (bounds.max - bounds.min);
  const VisibleSurfaceRays none = visibleSurfaceRays(bvh, away, 16, 9, 16);
  EXPECT_EQ(none.visiblePixels, 0u);
  EXPECT_TRUE(none.rays.empty());
}

TEST(SceneBvh, AlphaTestSkipsRejectedHitsOnMaskedTrianglesOnly) {
  const scene::Scene s = proceduralScene();
  SceneBvh bvh(s);
  const std::vector<scene::Instance> instances = proceduralInstances();
  bvh.setInstances(instances);
  // Half of every masked triangle is cut away; the hook must only ever see masked triangles.
  int calls = 0;
  const BvhAlphaTest halfCut = [&](std::uint32_t, std::uint32_t triangle, glm::vec2 barycentrics) {
    ++calls;
    EXPECT_NE(bvh.triangles()[triangle].w & kBvhAlphaMaskedBit, 0u);
    return barycentrics.x < barycentrics.y;
  };
  const std::vector<BvhRay> rays = makeRays(bvh, 600, 1.3f, 22);
  Agreement closest, any;
  int maskedHits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const BvhRay& ray = rays[i];
    const Reference ref = bruteForce(bvh, ray, halfCut);
    const BvhHit hit =
        bvh.traceClosest(rayOrigin(ray), rayDirection(ray), ray.originTMin.w, ray.directionTMax.w, halfCut);
    expectClosestAgrees(ref, hit.t, hit.instance, hit.triangle, hit.barycentrics, i, closest);
    if (hit.t < kNoHit && (bvh.triangles()[hit.triangle].w & kBvhAlphaMaskedBit)) {
      ++maskedHits;
      EXPECT_LT(hit.barycentrics.x, hit.barycentrics.y);
    }
    expectAnyAgrees(ref,
                    bvh.traceAny(rayOrigin(ray), rayDirection(ray), ray.originTMin.w, ray.directionTMax.w, halfCut),
                    glm::vec2(0.5f, 0.25f), i, any);
  }
  EXPECT_GT(maskedHits, 10);
  EXPECT_GT(calls, maskedHits);
  EXPECT_EQ(closest.excused + any.excused, 0);
}

// ---------------------------------------------------------------------------
// GPU traversal (render.bvh_trace_rays on whatever device: lavapipe in CI)

std::vector<BvhTraceResult> traceOnGpu(gpu::Context& context, BvhRayTracer& tracer, GpuBvh& gpuBvh,
                                       const std::vector<BvhRay>& rays, BvhTraceMode mode) {
  gpu::Buffer rayBuffer(context, "test.rays", rays.size() * sizeof(BvhRay), gpu::BufferUsage::DeviceLocal);
  gpu::uploadBuffer(context, rayBuffer, rays.data(), rays.size() * sizeof(BvhRay));
  gpu::Buffer results(context, "test.results", rays.size() * sizeof(BvhTraceResult), gpu::BufferUsage::DeviceLocal);
  context.submitAndWait(
      [&](gpu::Recorder& r) { tracer.record(r, gpuBvh, rayBuffer, results, std::uint32_t(rays.size()), mode); });
  const std::vector<std::uint8_t> bytes = gpu::readbackBuffer(context, results);
  std::vector<BvhTraceResult> out(rays.size());
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(BvhTraceResult));
  return out;
}

glm::vec2 resultBarycentrics(const BvhTraceResult& r) { return {r.tBarycentrics.y, r.tBarycentrics.z}; }

// The hit triangle's material, as render.bvh_trace_rays reports it.
void expectMaterialReported(const SceneBvh& bvh, const BvhTraceResult& result, std::size_t rayIndex) {
  const bool hit = result.tBarycentrics.x < kNoHit;
  if (hit && result.ids.y >= bvh.triangles().size()) {
    ADD_FAILURE() << "ray " << rayIndex << ": triangle " << result.ids.y << " out of range";
    return;
  }
  EXPECT_EQ(result.ids.z, hit ? bvh.triangles()[result.ids.y].w & ~kBvhAlphaMaskedBit : kBvhInvalidIndex)
      << "ray " << rayIndex;
}

void expectGpuMatches(gpu::Context& context, BvhRayTracer& tracer, const SceneBvh& bvh, GpuBvh& gpuBvh,
                      const std::vector<BvhRay>& rays, const std::vector<Reference>& refs) {
  auto start = std::chrono::steady_clock::now();
  const std::vector<BvhTraceResult> closestResults = traceOnGpu(context, tracer, gpuBvh, rays, BvhTraceMode::Closest);
  std::cout << tracer.pass().name() << ", closest, " << rays.size() << " rays: " << secondsSince(start) * 1e3
            << " ms including upload and readback\n";
  const std::vector<BvhTraceResult> anyResults = traceOnGpu(context, tracer, gpuBvh, rays, BvhTraceMode::Any);
  Agreement closest, any;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const BvhTraceResult& c = closestResults[i];
    expectClosestAgrees(refs[i], c.tBarycentrics.x, c.ids.x, c.ids.y, resultBarycentrics(c), i, closest);
    expectMaterialReported(bvh, c, i);
    EXPECT_EQ(c.tBarycentrics.w, 0.0f) << "closest-hit rays do not set the blocked flag";
    const BvhTraceResult& a = anyResults[i];
    expectAnyAgrees(refs[i], a.tBarycentrics.w == 1.0f, resultBarycentrics(a), i, any);
    if (a.tBarycentrics.w == 1.0f) {
      EXPECT_LT(a.tBarycentrics.x, rays[i].directionTMax.w) << "the blocking hit lies inside the interval";
    }
  }
  expectMostlyDecided(closest, rays.size());
  EXPECT_LE(any.excused, int(rays.size()) / 200);
  EXPECT_GT(any.blocked, int(rays.size()) / 4);
  std::cout << "excused edge grazes: closest " << closest.excused << ", any " << any.excused << "\n";
}

using GpuBvhTest = testing::GpuTest;

TEST_F(GpuBvhTest, TraceRaysMatchesBruteForce) {
  const scene::Scene s = proceduralScene();
  SceneBvh bvh(s);
  bvh.setInstances(proceduralInstances());
  GpuBvh gpuBvh(context(), bvh, 2);
  BvhRayTracer tracer(context());
  const std::vector<BvhRay> rays = makeRays(bvh, 1500, 1.3f, 31);
  expectGpuMatches(context(), tracer, bvh, gpuBvh, rays, bruteForceAll(bvh, rays));
}

TEST_F(GpuBvhTest, DeepTreesOnBothLevelsFitTheStack) {
  const scene::Scene s = deepStripScene();
  SceneBvh bvh(s);
  bvh.setInstances(deepStripInstances());
  GpuBvh gpuBvh(context(), bvh, 1);
  BvhRayTracer tracer(context());
  const std::vector<BvhRay> rays = deepStripRays();
  const std::vector<BvhTraceResult> closest = traceOnGpu(context(), tracer, gpuBvh, rays, BvhTraceMode::Closest);
  const std::vector<BvhTraceResult> any = traceOnGpu(context(), tracer, gpuBvh, rays, BvhTraceMode::Any);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const BvhRay& ray = rays[i];
    const BvhHit expected =
        bvh.traceClosestBruteForce(rayOrigin(ray), rayDirection(ray), ray.originTMin.w, ray.directionTMax.w);
    EXPECT_EQ(closest[i].tBarycentrics.x, expected.t) << "ray " << i;
    EXPECT_EQ(closest[i].ids.x, expected.instance) << "ray " << i;
    EXPECT_EQ(closest[i].ids.y, expected.triangle) << "ray " << i;
    EXPECT_EQ(any[i].tBarycentrics.w, expected.t < kNoHit ? 1.0f : 0.0f) << "ray " << i;
  }
}

TEST_F(GpuBvhTest, AlphaHookMakesMaskedTrianglesTransparent) {
  // Hand-made: an opaque quad at z = -4 behind a Mask quad at z = -2 and a
  // Blend quad at z = -3, all covering the rays.
  scene::Scene s;
  s.materials.resize(3);
  s.materials[1].alphaMode = scene::AlphaMode::Mask;
  s.materials[2].alphaMode = scene::AlphaMode::Blend;
  for (int m = 0; m < 3; ++m) {
    scene::Mesh quad;
    quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    quad.indices = {0, 1, 2, 0, 2, 3};
    quad.material = m;
    s.meshes.push_back(quad);
  }
  SceneBvh bvh(s);
  const std::vector<scene::Instance> instances = {{0, 0, placement({0, 0, -4}, 0, {0, 1, 0}, glm::vec3(1))},
                                                  {1, 1, placement({0, 0, -2}, 0, {0, 1, 0}, glm::vec3(1))},
                                                  {2, 2, placement({0, 0, -3}, 0, {0, 1, 0}, glm::vec3(1))}};
  bvh.setInstances(instances);
  GpuBvh gpuBvh(context(), bvh, 1);
  BvhRayTracer opaque(context());
  BvhRayTracer alphaTested(context(), bvhTraceRaysPassDesc("tests.bvh_alpha_check", "tests/bvh_alpha_check", tests::shaders()));
  std::vector<BvhRay> rays;
  for (int i = 0; i < 16; ++i) {
    const glm::vec3 origin(-0.8f + 0.1f * float(i), 0.37f - 0.05f * float(i), 0.0f);
    rays.push_back({glm::vec4(origin, 0.0f), glm::vec4(0.0f, 0.0f, -1.0f, 1e30f)});  // through all three
    rays.push_back({glm::vec4(origin, 0.0f), glm::vec4(0.0f, 0.0f, -1.0f, 3.5f)});   // ends before the opaque one
  }
  const auto closestOpaque = traceOnGpu(context(), opaque, gpuBvh, rays, BvhTraceMode::Closest);
  const auto anyOpaque = traceOnGpu(context(), opaque, gpuBvh, rays, BvhTraceMode::Any);
  const auto closestCut = traceOnGpu(context(), alphaTested, gpuBvh, rays, BvhTraceMode::Closest);
  const auto anyCut = traceOnGpu(context(), alphaTested, gpuBvh, rays, BvhTraceMode::Any);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const bool reachesOpaque = rays[i].directionTMax.w > 4.0f;
    EXPECT_FLOAT_EQ(closestOpaque[i].tBarycentrics.x, 2.0f) << "ray " << i << ": without a hook the Mask quad is solid";
    EXPECT_EQ(closestOpaque[i].ids.x, 1u);
    EXPECT_EQ(anyOpaque[i].tBarycentrics.w, 1.0f);
    EXPECT_EQ(closestCut[i].tBarycentrics.x, reachesOpaque ? 4.0f : kNoHit)
        << "ray " << i << ": the hook makes the Mask and Blend quads transparent";
    EXPECT_EQ(closestCut[i].ids.x, reachesOpaque ? 0u : kBvhInvalidIndex);
    EXPECT_EQ(anyCut[i].tBarycentrics.w, reachesOpaque ? 1.0f : 0.0f) << "ray " << i;
  }

  // The same hook over the procedural scene's Mask and Blend soups, against brute force.
  const scene::Scene big = proceduralScene();
  SceneBvh bigBvh(big);
  bigBvh.setInstances(proceduralInstances());
  GpuBvh bigGpuBvh(context(), bigBvh, 1);
  const std::vector<BvhRay> randomRays = makeRays(bigBvh, 600, 1.3f, 32);
  const BvhAlphaTest rejectAll = [](std::uint32_t, std::uint32_t, glm::vec2) { return false; };
  expectGpuMatches(context(), alphaTested, bigBvh, bigGpuBvh, randomRays, bruteForceAll(bigBvh, randomRays, rejectAll));
  const std::vector<BvhTraceResult> cut =
      traceOnGpu(context(), alphaTested, bigGpuBvh, randomRays, BvhTraceMode::Closest);
  for (const BvhTraceResult& r : cut) {
    if (r.tBarycentrics.x < kNoHit) {
      EXPECT_EQ(bigBvh.triangles()[r.ids.y].w & kBvhAlphaMaskedBit, 0u);
    }
  }
}

TEST_F(GpuBvhTest, TlasUpdatesBetweenFramesInFlight) {
  // One quad, moved every frame; 64 rays straight down -Z at it. Frames are
  // recorded back to back with two in flight, sharing one results buffer,
  // so only correct per-slot staging and barriers give each frame its own
  // placement.
  scene::Scene s;
  s.materials.resize(1);
  scene::Mesh quad;
  quad.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  quad.indices = {0, 1, 2, 0, 2, 3};
  s.meshes.push_back(quad);
  SceneBvh bvh(s);
  const auto at = [](glm::vec3 p) {
    return std::vector<scene::Instance>{{0, 0, placement(p, 0, {0, 1, 0}, glm::vec3(1))}};
  };
  bvh.setInstances(at({0, 0, -1}));
  GpuBvh gpuBvh(context(), bvh, 2);
  BvhRayTracer tracer(context());

  std::vector<BvhRay> rays;
  for (int i = 0; i < 64; ++i)
    rays.push_back({glm::vec4(-0.9f + 0.028f * float(i), 0.5f - 0.013f * float(i), 0.0f, 0.0f),
                    glm::vec4(0.0f, 0.0f, -1.0f, 1e30f)});
  const std::size_t resultBytes = rays.size() * sizeof(BvhTraceResult);
  gpu::Buffer rayBuffer(context(), "test.rays", rays.size() * sizeof(BvhRay), gpu::BufferUsage::DeviceLocal);
  gpu::uploadBuffer(context(), rayBuffer, rays.data(), rays.size() * sizeof(BvhRay));
  gpu::Buffer results(context(), "test.results", resultBytes, gpu::BufferUsage::DeviceLocal);

  // Distances per frame; 0 = moved aside, every ray misses.
  const std::vector<float> depths = {2.0f, 5.0f, 0.0f, 3.0f, 7.0f, 1.5f};
  std::vector<std::unique_ptr<gpu::Buffer>> readbacks;
  {
    gpu::FrameLoop loop(context(), 2);
    for (std::size_t f = 0; f < depths.size(); ++f) {
      gpu::Recorder& recorder = loop.beginFrame();
      bvh.setInstances(at(depths[f] > 0.0f ? glm::vec3(0, 0, -depths[f]) : glm::vec3(10, 0, -2)));
      gpuBvh.updateInstances(recorder, std::uint32_t(loop.frameIndex() % loop.framesInFlight()));
      tracer.record(recorder, gpuBvh, rayBuffer, results, std::uint32_t(rays.size()), BvhTraceMode::Closest);
      readbacks.push_back(std::make_unique<gpu::Buffer>(context(), "test.readback.frame" + std::to_string(f),
                                                        resultBytes, gpu::BufferUsage::Readback));
      recorder.copyBuffer(results, *readbacks.back(), resultBytes);
      recorder.makeHostReadable(*readbacks.back());
      loop.endFrame();
    }
    loop.finish();
  }
  for (std::size_t f = 0; f < depths.size(); ++f) {
    const auto* frame = static_cast<const BvhTraceResult*>(readbacks[f]->mapped());
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if (depths[f] > 0.0f) {
        EXPECT_FLOAT_EQ(frame[i].tBarycentrics.x, depths[f]) << "frame " << f << " ray " << i;
        EXPECT_EQ(frame[i].ids.x, 0u);
      } else {
        EXPECT_EQ(frame[i].tBarycentrics.x, kNoHit) << "frame " << f << " ray " << i;
      }
    }
  }
}

// ---------------------------------------------------------------------------
// Sponza, when the scene and the glTF importer are both there

TEST_F(GpuBvhTest, SponzaMatchesBruteForceOnCpuAndGpu) {
#ifndef BOUNCE_TEST_HAVE_GLTF
  GTEST_SKIP() << "no glTF importer (src/scene/gltf_import.h) in this build";
#else
  const std::filesystem::path path =
      std::filesystem::path(BOUNCE_SOURCE_DIR) / ".." / "shared" / "scenes" / "sponza" / "Sponza.gltf";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not present";
  auto start = std::chrono::steady_clock::now();
  const scene::Scene sponza = scene::loadGltf(path, {.warn = [](const std::string&) {}});
  std::cout << "Sponza load: " << secondsSince(start) << " s\n";
  SceneBvh bvh(sponza);
  expectValidTraversalLayout(bvh, sponza.meshes.size());
  std::cout << "Sponza BLAS build, " << sponza.meshes.size() << " meshes, " << bvh.triangles().size()
            << " triangles: " << bvh.blasBuildSeconds() * 1e3 << " ms (depth " << bvh.blasDepth() << ")\n";
  start = std::chrono::steady_clock::now();
  bvh.setInstances(scene::instancesAt(sponza, 0.0f));
  std::cout << "Sponza TLAS build, " << bvh.instances().size() << " instances: " << secondsSince(start) * 1e6
            << " us\n";

  // Origins inside the atrium (the middle of the bounds), rays every way.
  const std::vector<BvhRay> rays = makeRays(bvh, 1000, 0.5f, 41);
  const std::vector<Reference> refs = bruteForceAll(bvh, rays);
  Agreement closest, any;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const BvhRay& ray = rays[i];
    const BvhHit hit = bvh.traceClosest(rayOrigin(ray), rayDirection(ray), ray.originTMin.w, ray.directionTMax.w);
    expectClosestAgrees(refs[i], hit.t, hit.instance, hit.triangle, hit.barycentrics, i, closest);
    expectAnyAgrees(refs[i], bvh.traceAny(rayOrigin(ray), rayDirection(ray), ray.originTMin.w, ray.directionTMax.w),
                    glm::vec2(0.5f, 0.25f), i, any);
  }
  EXPECT_EQ(closest.excused + any.excused, 0);
  EXPECT_GT(closest.hits, int(rays.size()) * 3 / 4) << "inside the atrium most rays hit";

  GpuBvh gpuBvh(context(), bvh, 1);
  BvhRayTracer tracer(context());
  const std::vector<BvhTraceResult> results = traceOnGpu(context(), tracer, gpuBvh, rays, BvhTraceMode::Closest);
  Agreement gpuClosest;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    expectClosestAgrees(refs[i], results[i].tBarycentrics.x, results[i].ids.x, results[i].ids.y,
                        resultBarycentrics(results[i]), i, gpuClosest);
    expectMaterialReported(bvh, results[i], i);
  }
  EXPECT_LE(gpuClosest.excused, int(rays.size()) / 200);
  const std::vector<BvhTraceResult> anyResults = traceOnGpu(context(), tracer, gpuBvh, rays, BvhTraceMode::Any);
  Agreement gpuAny;
  for (std::size_t i = 0; i < rays.size(); ++i)
    expectAnyAgrees(refs[i], anyResults[i].tBarycentrics.w == 1.0f, resultBarycentrics(anyResults[i]), i, gpuAny);
  EXPECT_LE(gpuAny.excused, int(rays.size()) / 200);
#endif
}

}  // namespace
}  // namespace bounce::render
