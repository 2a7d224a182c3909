// Ray casting against the two-level scene BVH (src/render/bvh.h, docs/bvh.md).
//
// The including shader defines, before including this file:
//   #define BVH_FIRST_BINDING n   bindings n .. n + 4 are taken here (readonly storage buffers):
//     n + 0  gIn_BvhNodes      every mesh's BLAS nodes            (BvhNode items[])
//     n + 1  gIn_BvhTriangles  i0, i1, i2, material | alpha bit   (uvec4 items[], BLAS leaf order)
//     n + 2  gIn_BvhPositions  object-space vertex positions       (vec4 items[], w = 1)
//     n + 3  gIn_BvhInstances  per instance transforms + BLAS root (BvhInstance items[], TLAS leaf order)
//     n + 4  gIn_BvhTlasNodes  the TLAS over the instances         (BvhNode items[])
//   and optionally
//   #define BVH_ALPHA_TEST(instance, triangle, barycentrics) myTest(instance, triangle, barycentrics)
//     called for hits on alpha-masked triangles only; false = transparent
//     here, the ray goes on. Default: every triangle is opaque.
// The host declares these bindings with GpuBvh::traceResources() and binds
// them with GpuBvh::appendBinds().
//
// Provides
//   BvhHit bvhTraceClosest(vec3 origin, vec3 direction, float tMin, float tMax)
//   bool   bvhTraceAny(vec3 origin, vec3 direction, float tMin, float tMax)
//   bool   bvhTrace(origin, direction, tMin, tMax, bool anyHit, out BvhHit hit)   (both in one, for
//          passes that choose at run time; an any-hit ray's hit is the first one accepted)
// Hits count in the open interval (tMin, tMax); t is in units of the
// direction's length (it need not be unit length); front and back faces are
// both hit. A missed closest-hit ray has t = kNoHit.
//
// src/render/bvh.cpp (SceneBvh::trace, traceBlas) mirrors this traversal
// line for line; change both together.
#ifndef BOUNCE_RENDER_BVH_TRACE_GLSL
#define BOUNCE_RENDER_BVH_TRACE_GLSL

#ifndef BVH_FIRST_BINDING
#error "define BVH_FIRST_BINDING (the first of the five BVH bindings) before including render/bvh_trace.glsl"
#endif
#ifndef BVH_ALPHA_TEST
#define BVH_ALPHA_TEST(instance, triangle, barycentrics) true
#endif

#include "render/bvh_types.glsl"

layout(set = 0, binding = BVH_FIRST_BINDING + 0, std430) readonly buffer BvhNodes { BvhNode items[]; } gIn_BvhNodes;
layout(set = 0, binding = BVH_FIRST_BINDING + 1, std430) readonly buffer BvhTriangles { uvec4 items[]; }
gIn_BvhTriangles;
layout(set = 0, binding = BVH_FIRST_BINDING + 2, std430) readonly buffer BvhPositions { vec4 items[]; }
gIn_BvhPositions;
layout(set = 0, binding = BVH_FIRST_BINDING + 3, std430) readonly buffer BvhInstances { BvhInstance items[]; }
gIn_BvhInstances;
layout(set = 0, binding = BVH_FIRST_BINDING + 4, std430) readonly buffer BvhTlasNodes { BvhNode items[]; }
gIn_BvhTlasNodes;

// Accessors for shading a hit.
uvec4 bvhTriangle(uint triangle) { return gIn_BvhTriangles.items[triangle]; }
uint bvhTriangleMaterial(uint triangle) { return gIn_BvhTriangles.items[triangle].w & ~kBvhAlphaMaskedBit; }
vec3 bvhVertexPosition(uint vertex) { return gIn_BvhPositions.items[vertex].xyz; }

// Walks one instance's BLAS with the ray in object space. hit.t is the far
// end of the interval and shrinks with every accepted hit. Returns true when
// a hit was accepted (for any-hit rays, at the first one).
bool bvhTraverseBlas(BvhInstance instance, vec3 worldOrigin, vec3 worldDirection, float tMin, bool anyHit,
                     inout BvhHit hit) {
  // Not renormalised, so t along the object-space ray is t along the world ray.
  vec3 origin = bvhTransformPoint(instance.worldToObject, worldOrigin);
  vec3 direction = bvhTransformVector(instance.worldToObject, worldDirection);
  vec3 inverseDirection = bvhSafeInverse(direction);
  uint root = instance.info.x;
  uint instanceIndex = instance.info.z;
  BvhNode rootNode = gIn_BvhNodes.items[root];
  if (bvhIntersectBox(origin, inverseDirection, rootNode.boundsMin, rootNode.boundsMax, tMin, hit.t) >= kNoHit)
    return false;
  bool found = false;
  // One entry per level at most; the builder bounds every level's depth by kBvhMaxDepth.
  uint stack[kBvhMaxDepth];
  uint stackSize = 0u;
  uint nodeIndex = root;
  for (;;) {
    BvhNode node = gIn_BvhNodes.items[nodeIndex];
    if (node.count == 0u) {
      uvec2 next = bvhChildrenInOrder(gIn_BvhNodes.items[node.leftFirst], gIn_BvhNodes.items[node.leftFirst + 1u],
                                      node.leftFirst, origin, inverseDirection, tMin, hit.t);
      if (next.x != kBvhInvalidIndex) {
        if (next.y != kBvhInvalidIndex) stack[stackSize++] = next.y;
        nodeIndex = next.x;
        continue;
      }
    } else {
      for (uint k = node.leftFirst; k < node.leftFirst + node.count; ++k) {
        uvec4 triangle = gIn_BvhTriangles.items[k];
        float t;
        vec2 barycentrics;
        if (!bvhIntersectTriangle(origin, direction, gIn_BvhPositions.items[triangle.x].xyz,
                                  gIn_BvhPositions.items[triangle.y].xyz, gIn_BvhPositions.items[triangle.z].xyz, tMin,
                                  hit.t, t, barycentrics))
          continue;
        if ((triangle.w & kBvhAlphaMaskedBit) != 0u && !(BVH_ALPHA_TEST(instanceIndex, k, barycentrics))) continue;
        hit = BvhHit(t, instanceIndex, k, barycentrics);
        found = true;
        if (anyHit) return true;
      }
    }
    if (stackSize == 0u) break;
    nodeIndex = stack[--stackSize];
  }
  return found;
}

// The TLAS walk; each leaf's instances are walked with bvhTraverseBlas.
bool bvhTrace(vec3 origin, vec3 direction, float tMin, float tMax, bool anyHit, out BvhHit hit) {
  hit = BvhHit(tMax, kBvhInvalidIndex, kBvhInvalidIndex, vec2(0.0f));
  vec3 inverseDirection = bvhSafeInverse(direction);
  BvhNode root = gIn_BvhTlasNodes.items[0];
  bool found = false;
  if (bvhIntersectBox(origin, inverseDirection, root.boundsMin, root.boundsMax, tMin, tMax) < kNoHit) {
    uint stack[kBvhMaxDepth];
    uint stackSize = 0u;
    uint nodeIndex = 0u;
    for (;;) {
      BvhNode node = gIn_BvhTlasNodes.items[nodeIndex];
      if (node.count == 0u) {
        uvec2 next = bvhChildrenInOrder(gIn_BvhTlasNodes.items[node.leftFirst], gIn_BvhTlasNodes.items[node.leftFirst + 1u],
                                        node.leftFirst, origin, inverseDirection, tMin, hit.t);
        if (next.x != kBvhInvalidIndex) {
          if (next.y != kBvhInvalidIndex) stack[stackSize++] = next.y;
          nodeIndex = next.x;
          continue;
        }
      } else {
        for (uint k = node.leftFirst; k < node.leftFirst + node.count; ++k) {
          if (!bvhTraverseBlas(gIn_BvhInstances.items[k], origin, direction, tMin, anyHit, hit)) continue;
          if (anyHit) return true;
          found = true;
        }
      }
      if (stackSize == 0u) break;
      nodeIndex = stack[--stackSize];
    }
  }
  if (!found) hit = BvhHit(kNoHit, kBvhInvalidIndex, kBvhInvalidIndex, vec2(0.0f));
  return found;
}

BvhHit bvhTraceClosest(vec3 origin, vec3 direction, float tMin, float tMax) {
  BvhHit hit;
  bvhTrace(origin, direction, tMin, tMax, false, hit);
  return hit;
}

bool bvhTraceAny(vec3 origin, vec3 direction, float tMin, float tMax) {
  BvhHit hit;
  return bvhTrace(origin, direction, tMin, tMax, true, hit);
}

#endif
