// The walk through the two-level BVH, written once for the GPU
// (render/bvh_trace.glsl) and the CPU (SceneBvh in src/render/bvh.cpp), so
// both visit the same nodes in the same order and agree hit for hit.
// Algorithm and stack bound: docs/bvh.md.
//
// The includer says how the data is reached, by defining first:
//   BVH_SCENE_PARAMETER          a leading parameter of bvhTraverse, with its comma
//                                (the CPU passes its arrays; empty in GLSL)
//   BVH_TLAS_NODE(node)          the TLAS's BvhWideNode `node`
//   BVH_BLAS_NODE(node)          the BLASes' BvhWideNode `node`
//   BVH_INSTANCE(record)         the BvhInstance `record` (TLAS leaf order)
//   BVH_POSITION(index)          the vec4 `index` of the positions buffer, where
//                                corner c of BLAS leaf item (corner record) r is
//                                at 3r + c, object space; the first corner's w
//                                holds the triangle's material word and the
//                                second's its triangle index, as float bits
//   BVH_ALPHA_TEST(instance, triangle, barycentrics)
//                                whether a hit on an alpha-masked triangle counts
//   BVH_CHECK_STACK(size)        optional, runs before every push (the CPU
//                                throws on a full stack; the GPU relies on the bound)
//   BVH_COUNT_NODE(), BVH_COUNT_INSTANCE(), BVH_COUNT_TRIANGLE()
//                                optional, run at every node fetched, instance
//                                entered and triangle tested (the CPU's walk
//                                statistics)
#ifndef BOUNCE_RENDER_BVH_TRAVERSE_GLSL
#define BOUNCE_RENDER_BVH_TRAVERSE_GLSL

#include "render/bvh_types.glsl"

#ifndef BVH_CHECK_STACK
#define BVH_CHECK_STACK(size)
#endif
#ifndef BVH_COUNT_NODE
#define BVH_COUNT_NODE()
#define BVH_COUNT_INSTANCE()
#define BVH_COUNT_TRIANGLE()
#endif

BOUNCE_SHARED_BEGIN

// Hits count in (tMin, tMax); returns whether one was accepted (an any-hit
// ray stops at the first). hit.t is the far end of the interval while
// walking and shrinks with every accepted hit.
//
// The walk of a compressed wide BVH (Ylitie et al. 2017) over both levels
// in one loop, so that the threads of a warp walking the TLAS and those
// walking a BLAS run the same steps together. It holds two groups: a node
// group (x: the first child node of a node whose children were tested; y:
// the interior children entered, as traversal bits 24 .. 31, over the
// node's interior mask in bits 0 .. 7, which numbers them) and an item group
// (x: the node's first item; y: the items of its leaves entered, bits
// 0 .. 23). Each round takes the nearest interior child of the node group,
// tests that node's eight boxes and makes its children the groups; the rest
// of the old node group waits on the stack. The item group's triangles are
// tested at once; in the TLAS an item is an instance, whose entry moves the
// ray into the instance's object space (not renormalised, so t along it is
// t along the world ray) and walks its BLAS on the same stack, above the
// TLAS's entries (the rest of both groups waits there); when those are used
// up, the ray goes back to world space.
bool bvhTraverse(BVH_SCENE_PARAMETER vec3 worldOrigin, vec3 worldDirection, float tMin, float tMax, bool anyHit,
                 OUT(BvhHit) hit) {
  hit = BvhHit(tMax, kBvhInvalidIndex, kBvhInvalidIndex, vec2(0.0f));
  // The ray in the space of the level being walked.
  vec3 origin = worldOrigin;
  vec3 direction = worldDirection;
  vec3 inverseDirection = bvhSafeInverse(worldDirection);
  uint octantInverse4 = (7u - bvhOctant(worldDirection)) * 0x01010101u;
  uint instance = kBvhInvalidIndex;  // the caller's index of the instance whose BLAS is walked; invalid in the TLAS
  uint tlasEntries = 0u;             // while in a BLAS: the stack entries below this are the TLAS's
  uvec2 stack[kBvhStackSize];
  uint stackSize = 0u;
  // The root, as the one interior child of a node that has no other: bit 31,
  // no interior slot below it, so child 0 from node 0.
  uvec2 nodeGroup = uvec2(0u, 0x80000000u);
  for (;;) {
    uvec2 itemGroup = uvec2(0u);
    if ((nodeGroup.y & kBvhGroupInteriorBits) != 0u) {
      uint bit = uint(findMSB(nodeGroup.y));
      uint slot = (bit - 24u) ^ (octantInverse4 & 7u);
      uint index = nodeGroup.x + uint(bitCount(nodeGroup.y & ((1u << slot) - 1u)));
      nodeGroup.y &= ~(1u << bit);
      if ((nodeGroup.y & kBvhGroupInteriorBits) != 0u) {
        BVH_CHECK_STACK(stackSize);
        stack[stackSize] = nodeGroup;
        ++stackSize;
      }
      BVH_COUNT_NODE();
      BvhWideNode node;
      if (instance != kBvhInvalidIndex)
        node = BVH_BLAS_NODE(index);
      else
        node = BVH_TLAS_NODE(index);
      uint hits = bvhWideIntersectChildren(node, origin, inverseDirection, octantInverse4, tMin, hit.t);
      nodeGroup = uvec2(node.childrenMeta.x, (hits & kBvhGroupInteriorBits) | bvhWideInteriorMask(node));
      itemGroup = uvec2(node.childrenMeta.y, hits & kBvhGroupItemBits);
    } else {
      // A group of items only: the instances of a TLAS node still to enter.
      itemGroup = nodeGroup;
      nodeGroup = uvec2(0u);
    }
    if (instance == kBvhInvalidIndex && itemGroup.y != 0u) {
      // An instance: the rest of both groups waits, the items above the nodes.
      uint bit = uint(findMSB(itemGroup.y));
      itemGroup.y &= ~(1u << bit);
      if ((nodeGroup.y & kBvhGroupInteriorBits) != 0u) {
        BVH_CHECK_STACK(stackSize);
        stack[stackSize] = nodeGroup;
        ++stackSize;
      }
      if (itemGroup.y != 0u) {
        BVH_CHECK_STACK(stackSize);
        stack[stackSize] = itemGroup;
        ++stackSize;
      }
      BVH_COUNT_INSTANCE();
      BvhInstance record = BVH_INSTANCE(itemGroup.x + bit);
      origin = bvhTransformPoint(record.worldToObject, worldOrigin);
      direction = bvhTransformVector(record.worldToObject, worldDirection);
      inverseDirection = bvhSafeInverse(direction);
      octantInverse4 = (7u - bvhOctant(direction)) * 0x01010101u;
      instance = record.info.z;
      tlasEntries = stackSize;
      nodeGroup = uvec2(record.info.x, 0x80000000u);
      continue;
    }
    while (itemGroup.y != 0u) {
      uint bit = uint(findMSB(itemGroup.y));
      itemGroup.y &= ~(1u << bit);
      uint record = itemGroup.x + bit;
      BVH_COUNT_TRIANGLE();
      vec4 p0 = BVH_POSITION(3u * record);
      vec4 p1 = BVH_POSITION(3u * record + 1u);
      vec4 p2 = BVH_POSITION(3u * record + 2u);
      float t = 0.0f;
      vec2 barycentrics = vec2(0.0f);
      if (!bvhIntersectTriangle(origin, direction, vec3(p0.x, p0.y, p0.z), vec3(p1.x, p1.y, p1.z),
                                vec3(p2.x, p2.y, p2.z), tMin, hit.t, t, barycentrics))
        continue;
      uint triangle = floatBitsToUint(p1.w);
      if ((floatBitsToUint(p0.w) & kBvhAlphaMaskedBit) != 0u && !(BVH_ALPHA_TEST(instance, triangle, barycentrics)))
        continue;
      hit = BvhHit(t, instance, triangle, barycentrics);
      if (anyHit) return true;
    }
    if ((nodeGroup.y & kBvhGroupInteriorBits) == 0u) {
      // Next: what waits on the stack. When a BLAS's entries are used up, back to the TLAS.
      if (instance != kBvhInvalidIndex && stackSize == tlasEntries) {
        origin = worldOrigin;
        direction = worldDirection;
        inverseDirection = bvhSafeInverse(worldDirection);
        octantInverse4 = (7u - bvhOctant(worldDirection)) * 0x01010101u;
        instance = kBvhInvalidIndex;
      }
      if (stackSize == 0u) break;
      --stackSize;
      nodeGroup = stack[stackSize];
    }
  }
  // Only an accepted hit sets the instance.
  bool found = hit.instance != kBvhInvalidIndex;
  if (!found) hit.t = kNoHit;
  return found;
}

BOUNCE_SHARED_END
#endif
