// The BVH's GPU data and its ray-box / ray-triangle tests, shared by the host
// (C++: the builder, the CPU traversal) and the shaders (render/bvh_trace.glsl),
// so both agree on the layout and on the arithmetic. The traversal itself is
// shared too: render/bvh_traverse.glsl. Layout and algorithms: docs/bvh.md.
//
// Buffer structs are vec4s and uvec4s, except BvhNode, whose vec3 + uint
// pairs pack into 16 bytes identically in std430 and in C++ (glm::vec3 is
// 12 bytes with 4-byte alignment); the C++ side static_asserts the sizes.
#ifndef BOUNCE_RENDER_BVH_TYPES_GLSL
#define BOUNCE_RENDER_BVH_TYPES_GLSL
#include "shared/intersect.glsl"
#include "shared/lang.glsl"

// The structs live in a named namespace in C++ (the functions below are in
// BOUNCE_SHARED_BEGIN's unnamed one), so that classes in headers can hold them.
#ifdef __cplusplus
namespace bounce::shared {
#endif

// An interior node with both children's boxes, so a visit is one 64-byte
// fetch. left and right are child references (bvhIsLeaf and friends below):
// an interior node's index in the same array, or a leaf's items (triangles
// for a BLAS, instance records for the TLAS). Every tree starts at an
// interior node; a slot without a child (a tree of one leaf, or of nothing)
// has an inverted box (min > max), which no ray enters, and the reference
// kBvhInvalidIndex.
struct BvhNode {
  vec3 leftMin;
  uint left;
  vec3 leftMax;
  uint right;
  vec3 rightMin;
  uint unused0;
  vec3 rightMax;
  uint unused1;
};

// One placed mesh as the TLAS leaves see it. Records are stored in TLAS leaf
// order; info.z maps back to the caller's instance index.
struct BvhInstance {
  vec4 worldToObject[3];  // rows of a 3x4 affine matrix
  vec4 objectToWorld[3];  // rows of a 3x4 affine matrix
  uvec4 info;             // x = BLAS root node (interior), y = mesh index, z = caller's instance index, w unused
};

// What a ray hit. t is measured along the world-space direction as given
// (not renormalised), kNoHit when nothing was hit. triangle indexes the
// triangles buffer (BLAS leaf order); barycentrics (u, v) weight the second
// and third vertex: p = p0 * (1 - u - v) + p1 * u + p2 * v.
struct BvhHit {
  float t;
  uint instance;
  uint triangle;
  vec2 barycentrics;
};

// render.bvh_trace_rays: one ray in, one result out.
struct BvhRay {
  vec4 originTMin;     // xyz world origin, w = tMin (hits count in the open interval (tMin, tMax))
  vec4 directionTMax;  // xyz world direction (any length; t is in its units), w = tMax
};

struct BvhTraceResult {
  vec4 tBarycentrics;  // x = t (kNoHit: missed), yz = barycentrics, w = 1 if an any-hit ray was blocked, else 0
  uvec4 ids;           // x = instance (caller's index), y = triangle, z = its material index, w unused
                       // (kBvhInvalidIndex where missed)
};

struct BvhTraceRaysParams {
  uvec4 rayCountMode;  // x = number of rays, y = kBvhTraceClosest or kBvhTraceAny, zw unused
};

#ifdef __cplusplus
}  // namespace bounce::shared
#endif

BOUNCE_SHARED_BEGIN
// Deepest leaf of any BVH level (root = depth 0); the builder falls back to
// median splits to stay within it. The walk keeps at most one waiting child
// per depth of each level (docs/bvh.md), so the TLAS's entries and then one
// BLAS's never need more than kBvhStackSize.
const uint kBvhMaxDepth = 32u;
const uint kBvhStackSize = 2u * kBvhMaxDepth;

// A child reference with this bit set is a leaf: its first item in the bits
// above kBvhLeafCountBits, its item count minus one in those below. So a
// leaf holds 1 .. kBvhMaxLeafSize items and the first item is below
// kBvhMaxLeafFirst; without it, the reference is an interior node's index.
const uint kBvhLeafBit = 0x80000000u;
const uint kBvhLeafCountBits = 2u;
const uint kBvhMaxLeafSize = 1u << kBvhLeafCountBits;
const uint kBvhMaxLeafFirst = kBvhLeafBit >> kBvhLeafCountBits;

// Set in a triangle's w when its material is alpha-masked (glTF MASK or BLEND):
// a hit on it must pass the alpha test before it counts.
const uint kBvhAlphaMaskedBit = 0x80000000u;
const uint kBvhInvalidIndex = 0xffffffffu;

const uint kBvhTraceClosest = 0u;
const uint kBvhTraceAny = 1u;

uint bvhLeafReference(uint first, uint count) { return kBvhLeafBit | (first << kBvhLeafCountBits) | (count - 1u); }
bool bvhIsLeaf(uint reference) { return (reference & kBvhLeafBit) != 0u; }
uint bvhLeafFirst(uint reference) { return (reference & ~kBvhLeafBit) >> kBvhLeafCountBits; }
uint bvhLeafCount(uint reference) { return (reference & (kBvhMaxLeafSize - 1u)) + 1u; }

// 1 / direction, with zero components nudged to +-1e-20 first, so the slab
// test never multiplies 0 by infinity (which would make NaN).
vec3 bvhSafeInverse(vec3 direction) {
  vec3 d = direction;
  if (abs(d.x) < 1e-20f) d.x = d.x >= 0.0f ? 1e-20f : -1e-20f;
  if (abs(d.y) < 1e-20f) d.y = d.y >= 0.0f ? 1e-20f : -1e-20f;
  if (abs(d.z) < 1e-20f) d.z = d.z >= 0.0f ? 1e-20f : -1e-20f;
  return vec3(1.0f / d.x, 1.0f / d.y, 1.0f / d.z);
}

// Slab test: the distance at which the ray enters the box within
// [tMin, tMax], or kNoHit. Near and far planes are chosen by the direction's
// sign (not by min/max of the two), so an inverted (empty) box is never
// entered. The far distance is widened by 1 + 2 * gamma(3) (Ize, "Robust BVH
// Ray Traversal", 2013) so that rounding never culls a hit on the boundary.
float bvhIntersectBox(vec3 origin, vec3 inverseDirection, vec3 boundsMin, vec3 boundsMax, float tMin, float tMax) {
  vec3 toMin = (boundsMin - origin) * inverseDirection;
  vec3 toMax = (boundsMax - origin) * inverseDirection;
  float nearX = inverseDirection.x >= 0.0f ? toMin.x : toMax.x;
  float nearY = inverseDirection.y >= 0.0f ? toMin.y : toMax.y;
  float nearZ = inverseDirection.z >= 0.0f ? toMin.z : toMax.z;
  float farX = inverseDirection.x >= 0.0f ? toMax.x : toMin.x;
  float farY = inverseDirection.y >= 0.0f ? toMax.y : toMin.y;
  float farZ = inverseDirection.z >= 0.0f ? toMax.z : toMin.z;
  float tNear = max(max(nearX, nearY), max(nearZ, tMin));
  float tFar = min(min(farX, farY), farZ) * 1.0000004f;
  tFar = min(tFar, tMax);
  return tNear <= tFar ? tNear : kNoHit;
}

// Moller-Trumbore, both faces. True when the ray hits the triangle at
// tMin < t < tMax; t and barycentrics are then set. Every comparison is
// written so that NaN (degenerate triangle, det = 0) fails it.
bool bvhIntersectTriangle(vec3 origin, vec3 direction, vec3 p0, vec3 p1, vec3 p2, float tMin, float tMax,
                          OUT(float) t, OUT(vec2) barycentrics) {
  vec3 edge1 = p1 - p0;
  vec3 edge2 = p2 - p0;
  vec3 p = cross(direction, edge2);
  float det = dot(edge1, p);
  if (det == 0.0f) return false;
  float inverseDet = 1.0f / det;
  vec3 s = origin - p0;
  float u = dot(s, p) * inverseDet;
  if (!(u >= 0.0f && u <= 1.0f)) return false;
  vec3 q = cross(s, edge1);
  float v = dot(direction, q) * inverseDet;
  if (!(v >= 0.0f && u + v <= 1.0f)) return false;
  float hitT = dot(edge2, q) * inverseDet;
  if (!(hitT > tMin && hitT < tMax)) return false;
  t = hitT;
  barycentrics = vec2(u, v);
  return true;
}

vec3 bvhTransformPoint(const vec4 rows[3], vec3 p) {
  return vec3(dot(rows[0], vec4(p, 1.0f)), dot(rows[1], vec4(p, 1.0f)), dot(rows[2], vec4(p, 1.0f)));
}

vec3 bvhTransformVector(const vec4 rows[3], vec3 v) {
  return vec3(dot(vec3(rows[0].x, rows[0].y, rows[0].z), v), dot(vec3(rows[1].x, rows[1].y, rows[1].z), v),
              dot(vec3(rows[2].x, rows[2].y, rows[2].z), v));
}

BOUNCE_SHARED_END
#endif
