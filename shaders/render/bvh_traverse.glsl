// The walk through the two-level BVH, written once for the GPU
// (render/bvh_trace.glsl) and the CPU (SceneBvh in src/render/bvh.cpp), so
// both visit the same nodes in the same order and agree hit for hit.
// Algorithm and stack bound: docs/bvh.md.
//
// The includer says how the data is reached, by defining first:
//   BVH_SCENE_PARAMETER          a leading parameter of bvhTraverse, with its comma
//                                (the CPU passes its arrays; empty in GLSL)
//   BVH_TLAS_NODE(node)          the TLAS's BvhNode `node`
//   BVH_BLAS_NODE(node)          the BLASes' BvhNode `node`
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
#ifndef BOUNCE_RENDER_BVH_TRAVERSE_GLSL
#define BOUNCE_RENDER_BVH_TRAVERSE_GLSL

#include "render/bvh_types.glsl"

#ifndef BVH_CHECK_STACK
#define BVH_CHECK_STACK(size)
#endif

BOUNCE_SHARED_BEGIN

// A subtree waiting on the stack: its child reference and the distance at
// which the ray enters its box, so it is skipped once a hit is closer.
struct BvhStackEntry {
  uint node;
  float t;
};

// Hits count in (tMin, tMax); returns whether one was accepted (an any-hit
// ray stops at the first). hit.t is the far end of the interval while
// walking and shrinks with every accepted hit.
//
// One loop for both levels, so that the threads of a warp walking the TLAS
// and those walking a BLAS run the same steps together. Entering a TLAS leaf
// (one instance) moves the ray into that instance's object space, not
// renormalised, so t along it is t along the world ray, and the BLAS's
// entries go on the same stack above the TLAS's; when they are used up, the
// ray goes back to world space. Each round takes one step down the tree
// and, if that reaches a leaf, enters its instance or tests its triangles;
// then, if that leads nowhere, takes the next subtree from the stack
// ("if-if", Aila and Laine 2009: on Sponza's incoherent rays faster than
// descending to a leaf before testing leaves, "while-while"). The walk keeps
// few values live (the world-space inverse direction is worked out again on
// leaving a BLAS; no found flag): that, too, measured faster (docs/bvh.md).
bool bvhTraverse(BVH_SCENE_PARAMETER vec3 worldOrigin, vec3 worldDirection, float tMin, float tMax, bool anyHit,
                 OUT(BvhHit) hit) {
  hit = BvhHit(tMax, kBvhInvalidIndex, kBvhInvalidIndex, vec2(0.0f));
  // The ray in the space of the level being walked.
  vec3 origin = worldOrigin;
  vec3 direction = worldDirection;
  vec3 inverseDirection = bvhSafeInverse(worldDirection);
  uint instance = kBvhInvalidIndex;  // the caller's index of the instance whose BLAS is walked; invalid in the TLAS
  uint tlasEntries = 0u;             // while in a BLAS: the stack entries below this are the TLAS's
  BvhStackEntry stack[kBvhStackSize];
  uint stackSize = 0u;
  uint node = 0u;  // a child reference; kBvhInvalidIndex: nothing to enter here
  for (;;) {
    if (!bvhIsLeaf(node)) {
      BvhNode interior;
      if (instance != kBvhInvalidIndex)
        interior = BVH_BLAS_NODE(node);
      else
        interior = BVH_TLAS_NODE(node);
      float tLeft = bvhIntersectBox(origin, inverseDirection, interior.leftMin, interior.leftMax, tMin, hit.t);
      float tRight = bvhIntersectBox(origin, inverseDirection, interior.rightMin, interior.rightMax, tMin, hit.t);
      // The nearer child next; the farther one, if entered too, waits.
      bool leftFirst = tLeft <= tRight;
      if (tLeft < kNoHit && tRight < kNoHit) {
        BVH_CHECK_STACK(stackSize);
        stack[stackSize] = BvhStackEntry(leftFirst ? interior.right : interior.left, leftFirst ? tRight : tLeft);
        ++stackSize;
      }
      node = min(tLeft, tRight) < kNoHit ? (leftFirst ? interior.left : interior.right) : kBvhInvalidIndex;
      // An interior child is the next round's step; a leaf is tested in this one.
      if (!bvhIsLeaf(node)) continue;
    }
    if (node != kBvhInvalidIndex && instance == kBvhInvalidIndex) {
      // A TLAS leaf holds one instance.
      BvhInstance record = BVH_INSTANCE(bvhLeafFirst(node));
      origin = bvhTransformPoint(record.worldToObject, worldOrigin);
      direction = bvhTransformVector(record.worldToObject, worldDirection);
      inverseDirection = bvhSafeInverse(direction);
      instance = record.info.z;
      tlasEntries = stackSize;
      node = record.info.x;
      continue;
    }
    if (node != kBvhInvalidIndex) {
      uint first = bvhLeafFirst(node);
      uint end = first + bvhLeafCount(node);
      for (uint record = first; record < end; ++record) {
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
    }
    // Next: the nearest waiting subtree the ray enters before the closest
    // hit so far. When a BLAS's entries are used up, back to the TLAS.
    bool popped = false;
    while (!popped) {
      if (instance != kBvhInvalidIndex && stackSize == tlasEntries) {
        origin = worldOrigin;
        direction = worldDirection;
        inverseDirection = bvhSafeInverse(worldDirection);
        instance = kBvhInvalidIndex;
      }
      if (stackSize == 0u) break;
      --stackSize;
      popped = stack[stackSize].t <= hit.t;
      node = stack[stackSize].node;
    }
    if (!popped) break;
  }
  // Only an accepted hit sets the instance.
  bool found = hit.instance != kBvhInvalidIndex;
  if (!found) hit.t = kNoHit;
  return found;
}

BOUNCE_SHARED_END
#endif
