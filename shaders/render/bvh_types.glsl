// The BVH's GPU data and its ray-box / ray-triangle tests, shared by the host
// (C++: the builder, the CPU traversal) and the shaders (render/bvh_trace.glsl),
// so both agree on the layout and on the arithmetic. The traversal itself is
// shared too: render/bvh_traverse.glsl. Layout and algorithms: docs/bvh.md.
//
// Buffer structs are vec4s and uvec4s, so they are laid out identically in
// std430 and in C++; the C++ side static_asserts the sizes.
#ifndef BOUNCE_RENDER_BVH_TYPES_GLSL
#define BOUNCE_RENDER_BVH_TYPES_GLSL
#include "shared/intersect.glsl"
#include "shared/lang.glsl"

// The structs live in a named namespace in C++ (the functions below are in
// BOUNCE_SHARED_BEGIN's unnamed one), so that classes in headers can hold them.
#ifdef __cplusplus
namespace bounce::shared {
#endif

// An 8-wide node, 80 bytes (Ylitie, Karras and Laine, "Efficient
// Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017).
// Its children's boxes are stored quantised to 8 bits on a grid of the
// node's own: slot s's box is origin + scale * (low_s, high_s), with scale a
// power of two per axis (an exponent byte), so a node holds eight boxes in
// the room of one and a half full-precision ones. A slot holds nothing, an
// interior node or a leaf of 1..3 items (triangles' corner records in a
// BLAS, instance records in the TLAS); the interior children of a node are
// consecutive nodes from `firstChild` in slot order, its leaves' items
// consecutive records from `firstItem` (at most 24). Children sit in slots
// by direction, so that a ray visits them nearest first by walking the
// slots in an order its octant decides (bvh_traverse.glsl, docs/bvh.md).
//
//   originExponents  xyz: the grid's origin (the node box's minimum corner);
//                    w: as uint bits, the x, y, z scale exponents (biased as a
//                    float's: scale = 2^(e - 127)) in bytes 0..2 and the
//                    interior mask (bit s: slot s holds an interior node) in byte 3
//   childrenMeta     x: first child node; y: first item; z, w: the meta byte of
//                    slots 0..3 and 4..7 (bvhWideMetaInterior, bvhWideMetaLeaf)
//   lowXY            the quantised box minimum of slots 0..3, 4..7 in x, then y
//   lowZHighX        ... in z, then the maximum in x
//   highYZ           the maximum in y, then z
struct BvhWideNode {
  vec4 originExponents;
  uvec4 childrenMeta;
  uvec4 lowXY;
  uvec4 lowZHighX;
  uvec4 highYZ;
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
// Deepest leaf of any binary BVH level (root = depth 0); the builder falls
// back to median splits to stay within it. A wide tree is collapsed from a
// binary one, so it is no deeper. The walk keeps at most two waiting
// groups per depth of the TLAS and one per depth of a BLAS (docs/bvh.md),
// so kBvhStackSize entries always suffice.
const uint kBvhMaxDepth = 32u;
const uint kBvhStackSize = 3u * kBvhMaxDepth;

// Children of a wide node, and items of one of its leaves (the meta byte's
// unary count has three bits), and of all of its leaves together (the item
// bits of a traversal group, 24 .. 31 being its interior children's).
const uint kBvhWideArity = 8u;
const uint kBvhMaxLeafSize = 3u;
const uint kBvhWideMaxItems = 24u;
const uint kBvhGroupInteriorBits = 0xff000000u;
const uint kBvhGroupItemBits = 0x00ffffffu;

// Set in a triangle's w when its material is alpha-masked (glTF MASK or BLEND):
// a hit on it must pass the alpha test before it counts.
const uint kBvhAlphaMaskedBit = 0x80000000u;
const uint kBvhInvalidIndex = 0xffffffffu;

const uint kBvhTraceClosest = 0u;
const uint kBvhTraceAny = 1u;

// Meta bytes. Empty: 0. Interior: 0b001 in the top three bits and 24 +
// slot in the low five, so bits 4 and 3 are both set, which no leaf's are
// (its item offset is below 24): the walk tells the two apart with
// (meta & (meta << 1)) & 0x10. Leaf: its item count in unary in the top
// three bits (1, 3 or 7) and its first item's offset from firstItem in the
// low five. Read as a traversal mask, a meta byte's top bits shifted to its
// low five's position are the child's bits in a group: the interior child's
// bit 24 + slot, or the leaf's items' bits.
uint bvhWideMetaInterior(uint slot) { return 0x20u | (24u + slot); }
uint bvhWideMetaLeaf(uint offset, uint count) { return (((1u << count) - 1u) << 5u) | offset; }
bool bvhWideMetaIsInterior(uint meta) { return ((meta & (meta << 1u)) & 0x10u) != 0u; }
uint bvhWideMetaLeafOffset(uint meta) { return meta & 0x1fu; }
uint bvhWideMetaLeafCount(uint meta) { return uint(bitCount(meta >> 5u)); }
uint bvhWideMeta(BvhWideNode node, uint slot) {
  uint word = slot < 4u ? node.childrenMeta.z : node.childrenMeta.w;
  return (word >> (8u * (slot & 3u))) & 0xffu;
}

// The byte of slot `slot` in a pair of words (slots 0..3, then 4..7).
uint bvhWideByte(uint low, uint high, uint slot) { return ((slot < 4u ? low : high) >> (8u * (slot & 3u))) & 0xffu; }

// The scale of the node's grid along each axis, 2^(e - 127).
vec3 bvhWideScale(BvhWideNode node) {
  uint packed = floatBitsToUint(node.originExponents.w);
  return vec3(uintBitsToFloat((packed & 0xffu) << 23u), uintBitsToFloat(((packed >> 8u) & 0xffu) << 23u),
              uintBitsToFloat(((packed >> 16u) & 0xffu) << 23u));
}
uint bvhWideInteriorMask(BvhWideNode node) { return floatBitsToUint(node.originExponents.w) >> 24u; }

// Slot s's box as the walk sees it, origin + scale * q (each product exact:
// an 8-bit integer times a power of two).
void bvhWideChildBox(BvhWideNode node, uint slot, OUT(vec3) boxMin, OUT(vec3) boxMax) {
  vec3 origin = vec3(node.originExponents.x, node.originExponents.y, node.originExponents.z);
  vec3 scale = bvhWideScale(node);
  vec3 low = vec3(float(bvhWideByte(node.lowXY.x, node.lowXY.y, slot)),
                  float(bvhWideByte(node.lowXY.z, node.lowXY.w, slot)),
                  float(bvhWideByte(node.lowZHighX.x, node.lowZHighX.y, slot)));
  vec3 high = vec3(float(bvhWideByte(node.lowZHighX.z, node.lowZHighX.w, slot)),
                   float(bvhWideByte(node.highYZ.x, node.highYZ.y, slot)),
                   float(bvhWideByte(node.highYZ.z, node.highYZ.w, slot)));
  boxMin = origin + scale * low;
  boxMax = origin + scale * high;
}

// The octant of a direction, a bit per negative component (x: 4, y: 2,
// z: 1). Slot s of a node holds the child nearest along directions of octant
// s, so a ray of octant o walks slot o first.
uint bvhOctant(vec3 direction) {
  return (direction.x < 0.0f ? 4u : 0u) | (direction.y < 0.0f ? 2u : 0u) | (direction.z < 0.0f ? 1u : 0u);
}

// 1 / direction, with zero components nudged to +-1e-20 first, so the slab
// test never multiplies 0 by infinity (which would make NaN).
vec3 bvhSafeInverse(vec3 direction) {
  vec3 d = direction;
  if (abs(d.x) < 1e-20f) d.x = d.x >= 0.0f ? 1e-20f : -1e-20f;
  if (abs(d.y) < 1e-20f) d.y = d.y >= 0.0f ? 1e-20f : -1e-20f;
  if (abs(d.z) < 1e-20f) d.z = d.z >= 0.0f ? 1e-20f : -1e-20f;
  return vec3(1.0f / d.x, 1.0f / d.y, 1.0f / d.z);
}

// Which of a wide node's children the ray enters within [tMin, tMax], as a
// traversal mask: an interior child in slot s sets bit 24 + (s ^ (7 -
// octant)), so that taking the highest bit first walks the slots in the
// ray's octant order (nearest first); a leaf sets its items' bits, 0 .. 23.
// Each box is tested in the node's grid: t = q * (scale / d) + (origin - o)
// / d, one multiply-add per plane (a slab test). The near and far planes
// are chosen by the direction's sign (not by min/max of the two), and the
// far distance is widened by 1 + 2 * gamma(3) (Ize, "Robust BVH Ray
// Traversal", 2013) so that rounding never culls a hit on the boundary.
uint bvhWideIntersectChildren(BvhWideNode node, vec3 origin, vec3 inverseDirection, uint octantInverse4, float tMin,
                              float tMax) {
  vec3 scaledInverse = bvhWideScale(node) * inverseDirection;
  vec3 shifted =
      (vec3(node.originExponents.x, node.originExponents.y, node.originExponents.z) - origin) * inverseDirection;
  uvec2 lowX = uvec2(node.lowXY.x, node.lowXY.y), highX = uvec2(node.lowZHighX.z, node.lowZHighX.w);
  uvec2 lowY = uvec2(node.lowXY.z, node.lowXY.w), highY = uvec2(node.highYZ.x, node.highYZ.y);
  uvec2 lowZ = uvec2(node.lowZHighX.x, node.lowZHighX.y), highZ = uvec2(node.highYZ.z, node.highYZ.w);
  uvec2 nearX = inverseDirection.x >= 0.0f ? lowX : highX, farX = inverseDirection.x >= 0.0f ? highX : lowX;
  uvec2 nearY = inverseDirection.y >= 0.0f ? lowY : highY, farY = inverseDirection.y >= 0.0f ? highY : lowY;
  uvec2 nearZ = inverseDirection.z >= 0.0f ? lowZ : highZ, farZ = inverseDirection.z >= 0.0f ? highZ : lowZ;
  uint hits = 0u;
  for (uint quad = 0u; quad < 2u; ++quad) {
    uint meta4 = quad == 0u ? node.childrenMeta.z : node.childrenMeta.w;
    // Per byte: 0xff where the slot holds an interior node (bvhWideMetaIsInterior).
    uint interior4 = (((meta4 & (meta4 << 1u)) & 0x10101010u) >> 4u) * 0xffu;
    uint bitIndex4 = (meta4 ^ (octantInverse4 & interior4)) & 0x1f1f1f1fu;
    uint childBits4 = (meta4 >> 5u) & 0x07070707u;
    uint nx = quad == 0u ? nearX.x : nearX.y, fx = quad == 0u ? farX.x : farX.y;
    uint ny = quad == 0u ? nearY.x : nearY.y, fy = quad == 0u ? farY.x : farY.y;
    uint nz = quad == 0u ? nearZ.x : nearZ.y, fz = quad == 0u ? farZ.x : farZ.y;
    for (uint slot = 0u; slot < 4u; ++slot) {
      uint shift = 8u * slot;
      float tNear = max(max(float((nx >> shift) & 0xffu) * scaledInverse.x + shifted.x,
                            float((ny >> shift) & 0xffu) * scaledInverse.y + shifted.y),
                        max(float((nz >> shift) & 0xffu) * scaledInverse.z + shifted.z, tMin));
      float tFar = min(min(float((fx >> shift) & 0xffu) * scaledInverse.x + shifted.x,
                           float((fy >> shift) & 0xffu) * scaledInverse.y + shifted.y),
                       float((fz >> shift) & 0xffu) * scaledInverse.z + shifted.z) *
                   1.0000004f;
      if (tNear <= min(tFar, tMax)) hits |= ((childBits4 >> shift) & 7u) << ((bitIndex4 >> shift) & 31u);
    }
  }
  return hits;
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
