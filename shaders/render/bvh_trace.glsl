// Ray casting against the two-level scene BVH (src/render/bvh.h, docs/bvh.md).
//
// The including shader defines, before including this file:
//   #define BVH_FIRST_BINDING n   bindings n .. n + BVH_BINDING_COUNT - 1 are taken here (readonly storage buffers):
//     n + 0  gIn_BvhNodes      every mesh's BLAS nodes                  (BvhWideNode items[])
//     n + 1  gIn_BvhTriangles  i0, i1, i2, material | alpha bit             (uvec4 items[], BLAS leaf order)
//     n + 2  gIn_BvhPositions  object-space vertex positions (w = 1), then  (vec4 items[])
//                              each triangle's corners in BLAS leaf order
//     n + 3  gIn_BvhInstances  per instance transforms + BLAS root          (BvhInstance items[], TLAS leaf order)
//     n + 4  gIn_BvhTlasNodes  the TLAS over the instances              (BvhWideNode items[])
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
//   uvec4  bvhTriangle(triangle)          global vertex indices i0, i1, i2; w = material | alpha bit
//   uint   bvhTriangleMaterial(triangle)
//   vec3   bvhVertexPosition(vertex)      object space
// Hits count in the open interval (tMin, tMax); t is in units of the
// direction's length (it need not be unit length); front and back faces are
// both hit. A missed closest-hit ray has t = kNoHit.
//
// The walk itself is render/bvh_traverse.glsl, which the CPU runs too.
#ifndef BOUNCE_RENDER_BVH_TRACE_GLSL
#define BOUNCE_RENDER_BVH_TRACE_GLSL

#ifndef BVH_FIRST_BINDING
#error "define BVH_FIRST_BINDING (the first of the BVH's bindings) before including render/bvh_trace.glsl"
#endif
#define BVH_BINDING_COUNT 5
#ifndef BVH_ALPHA_TEST
#define BVH_ALPHA_TEST(instance, triangle, barycentrics) true
#endif

#include "render/bvh_types.glsl"

layout(set = 0, binding = BVH_FIRST_BINDING + 0, std430) readonly buffer BvhNodes { BvhWideNode items[]; } gIn_BvhNodes;
layout(set = 0, binding = BVH_FIRST_BINDING + 1, std430) readonly buffer BvhTriangles { uvec4 items[]; }
gIn_BvhTriangles;
layout(set = 0, binding = BVH_FIRST_BINDING + 2, std430) readonly buffer BvhPositions { vec4 items[]; }
gIn_BvhPositions;
layout(set = 0, binding = BVH_FIRST_BINDING + 3, std430) readonly buffer BvhInstances { BvhInstance items[]; }
gIn_BvhInstances;
layout(set = 0, binding = BVH_FIRST_BINDING + 4, std430) readonly buffer BvhTlasNodes { BvhWideNode items[]; }
gIn_BvhTlasNodes;

// Accessors for shading a hit.
uvec4 bvhTriangle(uint triangle) { return gIn_BvhTriangles.items[triangle]; }
uint bvhTriangleMaterial(uint triangle) { return gIn_BvhTriangles.items[triangle].w & ~kBvhAlphaMaskedBit; }
vec3 bvhVertexPosition(uint vertex) { return gIn_BvhPositions.items[vertex].xyz; }

#define BVH_SCENE_PARAMETER
#define BVH_TLAS_NODE(node) gIn_BvhTlasNodes.items[node]
#define BVH_BLAS_NODE(node) gIn_BvhNodes.items[node]
#define BVH_INSTANCE(record) gIn_BvhInstances.items[record]
#define BVH_POSITION(index) gIn_BvhPositions.items[index]
#include "render/bvh_traverse.glsl"

bool bvhTrace(vec3 origin, vec3 direction, float tMin, float tMax, bool anyHit, out BvhHit hit) {
  return bvhTraverse(origin, direction, tMin, tMax, anyHit, hit);
}

BvhHit bvhTraceClosest(vec3 origin, vec3 direction, float tMin, float tMax) {
  BvhHit hit;
  bvhTraverse(origin, direction, tMin, tMax, false, hit);
  return hit;
}

bool bvhTraceAny(vec3 origin, vec3 direction, float tMin, float tMax) {
  BvhHit hit;
  return bvhTraverse(origin, direction, tMin, tMax, true, hit);
}

#endif
