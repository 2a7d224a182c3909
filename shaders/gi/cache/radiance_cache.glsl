// The world-space radiance cache (SHaRC / kajiya's ircache class): a hash
// grid of cells keyed by quantised position, a size level that grows with
// distance to the camera, and the normal's dominant axis. Each cell holds
// what a white Lambert surface there reflects of the light arriving by
// indirect paths (demodulated, like gi.diffuse's output): a world hit off
// screen adds albedo * this to its direct light and emission, so no ray
// ever recurses. With gi.cache.direct_light, a cell also holds the direct
// light a white Lambert surface reflects at the point it was made (the
// bridge's, shadow rays included, worked out by gi.cache.update each frame
// the cell is used), and diffuse world hits take their direct light from
// it instead of a shadow ray of their own. docs/gi.md, "The radiance
// cache", has the whole design.
//
// Buffers (the including shader defines CACHE_FIRST_BINDING; seven bindings):
//   + 0 gIn_CacheConstants   CacheConstants
//   + 1 gCache_Keys          uint per cell: the key's checksum, 0 = empty
//   + 2 gCache_Cells         uvec4 per cell: where it was made (position bits, octahedral normal)
//   + 3 gCache_Accumulators  uvec4 per cell: this frame's samples, rgb in fixed point, count
//   + 4 gCache_Radiance      vec4 per cell: rgb value, the frames of samples it averages;
//                            then (from entry `capacity`) vec4 per cell: rgb direct light, w = 1 once known
//   + 5 gCache_Touched       uint per cell: the last frame it was queried or filled
//   + 6 gCache_Updates       uint: [0] cells listed this frame, [1] live cells, then the listed indices
// Cells are made by the first query or fill that needs one (atomic
// compare-and-swap of the checksum into an empty slot, linear probing);
// gi.cache.update traces rays from the cells listed this frame;
// gi.cache.resolve folds each cell's samples into its value and evicts cells
// nobody touched for gi.cache.max_age frames.
#ifndef BOUNCE_GI_RADIANCE_CACHE_GLSL
#define BOUNCE_GI_RADIANCE_CACHE_GLSL

#ifndef CACHE_FIRST_BINDING
#error "define CACHE_FIRST_BINDING (the first of the radiance cache's seven bindings) first"
#endif
#define RADIANCE_CACHE

#include "gi/cache/cache_types.glsl"

layout(set = 0, binding = CACHE_FIRST_BINDING + 0, std140) CONSTANT_BLOCK CacheBlock { CacheConstants cache; }
gIn_CacheConstants;
layout(set = 0, binding = CACHE_FIRST_BINDING + 1, std430) buffer CacheKeys { uint items[]; } gCache_Keys;
layout(set = 0, binding = CACHE_FIRST_BINDING + 2, std430) buffer CacheCells { uvec4 items[]; } gCache_Cells;
layout(set = 0, binding = CACHE_FIRST_BINDING + 3, std430) buffer CacheAccumulators { uvec4 items[]; }
gCache_Accumulators;
layout(set = 0, binding = CACHE_FIRST_BINDING + 4, std430) buffer CacheRadiance { vec4 items[]; } gCache_Radiance;
layout(set = 0, binding = CACHE_FIRST_BINDING + 5, std430) buffer CacheTouched { uint items[]; } gCache_Touched;
layout(set = 0, binding = CACHE_FIRST_BINDING + 6, std430) buffer CacheUpdates { uint items[]; } gCache_Updates;

const uint kCacheNoCell = 0xffffffffu;
const uint kCacheProbes = 8u;
// Samples are summed in 32-bit fixed point: 1/256 resolution, each sample
// clamped to kCacheMaxSample so thousands of them fit in a frame.
const float kCacheFixedScale = 256.0f;
const float kCacheMaxSample = 4096.0f;

uint cacheHash(uint x) {  // a 32-bit integer hash (Wellons' lowbias32)
  x ^= x >> 16u;
  x *= 0x7feb352du;
  x ^= x >> 15u;
  x *= 0x846ca68bu;
  x ^= x >> 16u;
  return x;
}

// The cell a surface point falls in: its hash (the slot probing starts at)
// and checksum (what the slot stores; never 0).
struct CacheKey {
  uint hash;
  uint checksum;
};

CacheKey cacheKey(vec3 position, vec3 normal) {
  CacheConstants c = gIn_CacheConstants.cache;
  float distance = max(length(position - c.cameraPosition.xyz), 1e-3f);
  // Sizes in powers of two, so each cell of a level is exactly one cell.
  int level = clamp(int(floor(log2(distance * c.cellSize))), -24, 24);
  float size = exp2(float(level));
  ivec3 cell = ivec3(floor(position / size));
  vec3 a = abs(normal);
  uint axis = a.x >= a.y && a.x >= a.z ? 0u : a.y >= a.z ? 1u : 2u;
  uint side = normal[axis] < 0.0f ? 1u : 0u;
  uint tag = uint(level + 32) << 3u | axis << 1u | side;
  uint h = cacheHash(uint(cell.x) ^ cacheHash(uint(cell.y) ^ cacheHash(uint(cell.z) ^ cacheHash(tag))));
  uint check = cacheHash(h ^ 0x9e3779b9u ^ uint(cell.x) * 0x85ebca6bu ^ uint(cell.z) * 0xc2b2ae35u);
  return CacheKey(h, max(check, 1u));
}

// The cell of that key, made if there is none; kCacheNoCell when the probes
// find neither it nor room.
uint cacheFindOrMake(CacheKey key, vec3 position, vec3 normal) {
  uint mask = gIn_CacheConstants.cache.capacity - 1u;
  for (uint i = 0u; i < kCacheProbes; ++i) {
    uint slot = (key.hash + i) & mask;
    uint held = atomicCompSwap(gCache_Keys.items[slot], 0u, key.checksum);
    if (held == 0u) {
      gCache_Cells.items[slot] = uvec4(floatBitsToUint(position), packNormalOct32(normal));
      return slot;
    }
    if (held == key.checksum) return slot;
  }
  return kCacheNoCell;
}

// The cell of that key if there is one (looks, makes nothing).
uint cacheFind(CacheKey key) {
  uint mask = gIn_CacheConstants.cache.capacity - 1u;
  for (uint i = 0u; i < kCacheProbes; ++i) {
    uint slot = (key.hash + i) & mask;
    uint held = gCache_Keys.items[slot];
    if (held == key.checksum) return slot;
    if (held == 0u) break;
  }
  return kCacheNoCell;
}

// Marks a cell used this frame; the first use lists it for an update ray.
void cacheTouch(uint slot) {
  CacheConstants c = gIn_CacheConstants.cache;
  if (atomicExchange(gCache_Touched.items[slot], c.frame) == c.frame) return;
  uint index = atomicAdd(gCache_Updates.items[0], 1u);
  if (index < c.updateBudget) gCache_Updates.items[2u + index] = slot;
}

// Adds one sample of what a white Lambert surface at the cell reflects.
void cacheAddSample(uint slot, vec3 value) {
  uvec3 fixedPoint = uvec3(clamp(sanitizeRadiance(value), vec3(0.0f), vec3(kCacheMaxSample)) * kCacheFixedScale + 0.5f);
  atomicAdd(gCache_Accumulators.items[slot].x, fixedPoint.x);
  atomicAdd(gCache_Accumulators.items[slot].y, fixedPoint.y);
  atomicAdd(gCache_Accumulators.items[slot].z, fixedPoint.z);
  atomicAdd(gCache_Accumulators.items[slot].w, 1u);
}

// The direct light a white Lambert surface at the cell's point reflects,
// w = 1 once gi.cache.update has worked it out (gi.cache.direct_light).
vec4 cacheDirect(uint slot) { return gCache_Radiance.items[gIn_CacheConstants.cache.capacity + slot]; }
void cacheSetDirect(uint slot, vec3 direct) {
  gCache_Radiance.items[gIn_CacheConstants.cache.capacity + slot] = vec4(sanitizeRadiance(direct), 1.0f);
}

// What a white Lambert surface at `position` facing `normal` reflects of
// indirect light, as the cache knows it (0 for a cell with no samples yet),
// and whether `direct` holds its direct light (gi.cache.direct_light, once
// worked out); makes and touches the cell, so the next frames update it.
bool cacheQueryLight(vec3 position, vec3 normal, out vec3 indirect, out vec3 direct) {
  indirect = vec3(0.0f);
  direct = vec3(0.0f);
  if (gIn_CacheConstants.cache.enabled == 0u) return false;
  uint slot = cacheFindOrMake(cacheKey(position, normal), position, normal);
  if (slot == kCacheNoCell) return false;
  cacheTouch(slot);
  indirect = gCache_Radiance.items[slot].xyz;
  if (gIn_CacheConstants.cache.directLight == 0u) return false;
  vec4 known = cacheDirect(slot);
  direct = known.xyz;
  return known.w > 0.0f;
}

vec3 cacheQuery(vec3 position, vec3 normal) {
  vec3 indirect, direct;
  cacheQueryLight(position, normal, indirect, direct);
  return indirect;
}

#endif
