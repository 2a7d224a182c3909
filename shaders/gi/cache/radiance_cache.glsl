// The world-space radiance cache (SHaRC / kajiya's ircache class): a hash
// grid of cells keyed by quantised position, a size level that grows with
// distance to the camera, and the normal's dominant axis. Each cell holds
// what a white Lambert surface there reflects of the light arriving by
// indirect paths (demodulated, like gi.diffuse's output): a world hit off
// screen adds albedo * this to its direct light and emission, so no ray
// ever recurses. With gi.cache.direct_light, a cell also holds the direct
// light a white Lambert surface in it reflects (the bridge's, shadow rays
// included, averaged over the points gi.cache.update's paths reach in it),
// and diffuse world hits take their direct light from it instead of a
// shadow ray of their own. docs/gi.md, "The radiance
// cache", has the whole design.
//
// Buffers (the including shader defines CACHE_FIRST_BINDING; six bindings):
//   + 0 gIn_CacheConstants   CacheConstants
//   + 1 gCache_Keys          uint per cell: the key's checksum, 0 = empty
//   + 2 gCache_Accumulators  uvec4 per cell: this frame's samples, rgb in fixed point, count;
//                            then (from entry `capacity`) the same for the direct light
//   + 3 gCache_Radiance      vec4 per cell: rgb value, the samples it averages;
//                            then (from entry `capacity`) the same for the direct light (w > 0 once known)
//   + 4 gCache_Touched       uint per cell: the last frame it was queried or filled
//   + 5 gCache_Counts        uint: [0] live cells (gi.cache.view's occupancy bar); while the light
//                            changes (gi.light_change), [1] and [2] the luminance of the direct
//                            light the update's paths worked out anew and of what their cells
//                            held before, summed in fixed point (kCacheLightSumScale)
// Cells are made by the first query or fill that needs one (atomic
// compare-and-swap of the checksum into an empty slot, linear probing);
// gi.cache.update's paths add samples to the cells they pass;
// gi.cache.resolve folds each cell's samples into its value and evicts cells
// nobody touched for gi.cache.max_age frames. Samples are integers added
// atomically, so the order threads add them in changes no bit; which slot a
// cell takes can depend on it, but no lookup does (every probe is looked at
// before a cell is made), only whether a key finds room when all its probes
// are taken.
#ifndef BOUNCE_GI_RADIANCE_CACHE_GLSL
#define BOUNCE_GI_RADIANCE_CACHE_GLSL

#ifndef CACHE_FIRST_BINDING
#error "define CACHE_FIRST_BINDING (the first of the radiance cache's six bindings) first"
#endif
#define RADIANCE_CACHE

#include "gi/cache/cache_types.glsl"

layout(set = 0, binding = CACHE_FIRST_BINDING + 0, std140) CONSTANT_BLOCK CacheBlock { CacheConstants cache; }
gIn_CacheConstants;
layout(set = 0, binding = CACHE_FIRST_BINDING + 1, std430) buffer CacheKeys { uint items[]; } gCache_Keys;
layout(set = 0, binding = CACHE_FIRST_BINDING + 2, std430) buffer CacheAccumulators { uvec4 items[]; }
gCache_Accumulators;
layout(set = 0, binding = CACHE_FIRST_BINDING + 3, std430) buffer CacheRadiance { vec4 items[]; } gCache_Radiance;
layout(set = 0, binding = CACHE_FIRST_BINDING + 4, std430) buffer CacheTouched { uint items[]; } gCache_Touched;
layout(set = 0, binding = CACHE_FIRST_BINDING + 5, std430) buffer CacheCounts { uint items[]; } gCache_Counts;

const uint kCacheNoCell = 0xffffffffu;
const uint kCacheProbes = 8u;
// Samples are summed in 32-bit fixed point: 1/256 resolution, each sample
// clamped to kCacheMaxSample so thousands of them fit in a frame.
const float kCacheFixedScale = 256.0f;
const float kCacheMaxSample = 4096.0f;
// The sums of gCache_Counts [1] and [2]: each luminance clamped to
// kCacheLightSumMax, 1/kCacheLightSumScale resolution, from at most
// kCacheLightSumPaths paths (evenly spread over the frame's): they fit 32 bits.
const float kCacheLightSumScale = 256.0f;
const float kCacheLightSumMax = 1000.0f;
const uint kCacheLightSumPaths = 16384u;
// The direct light now over before (their ratio) counts as at most this
// (a lamp switched on in a dark room).
const float kCacheLightRatioLimit = 16.0f;

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

// The cell of that key if there is one (looks, makes nothing). Every probe
// is looked at: a cell evicted earlier in the probe sequence leaves a hole
// before cells made after it.
uint cacheFind(CacheKey key) {
  uint mask = gIn_CacheConstants.cache.capacity - 1u;
  for (uint i = 0u; i < kCacheProbes; ++i) {
    uint slot = (key.hash + i) & mask;
    if (gCache_Keys.items[slot] == key.checksum) return slot;
  }
  return kCacheNoCell;
}

// The cell of that key, made if there is none, and marked used this frame
// (cells nobody uses for gi.cache.max_age frames are evicted);
// kCacheNoCell when its probes find neither it nor room. Two threads making
// the same cell try the same empty slots in the same order, so they agree.
uint cacheFindOrMake(CacheKey key) {
  uint mask = gIn_CacheConstants.cache.capacity - 1u;
  uint slot = cacheFind(key);
  for (uint i = 0u; i < kCacheProbes && slot == kCacheNoCell; ++i) {
    uint candidate = (key.hash + i) & mask;
    uint held = atomicCompSwap(gCache_Keys.items[candidate], 0u, key.checksum);
    if (held == 0u || held == key.checksum) slot = candidate;
  }
  if (slot != kCacheNoCell) atomicMax(gCache_Touched.items[slot], gIn_CacheConstants.cache.frame);
  return slot;
}

void cacheAccumulate(uint entry, vec3 value) {
  uvec3 fixedPoint = uvec3(clamp(sanitizeRadiance(value), vec3(0.0f), vec3(kCacheMaxSample)) * kCacheFixedScale + 0.5f);
  atomicAdd(gCache_Accumulators.items[entry].x, fixedPoint.x);
  atomicAdd(gCache_Accumulators.items[entry].y, fixedPoint.y);
  atomicAdd(gCache_Accumulators.items[entry].z, fixedPoint.z);
  atomicAdd(gCache_Accumulators.items[entry].w, 1u);
}

// Adds one sample of what a white Lambert surface in the cell reflects of
// indirect light.
void cacheAddSample(uint slot, vec3 value) { cacheAccumulate(slot, value); }

// Adds one sample of the direct light a white Lambert surface in the cell
// reflects (gi.cache.direct_light).
void cacheAddDirectSample(uint slot, vec3 direct) {
  cacheAccumulate(gIn_CacheConstants.cache.capacity + slot, direct);
}

// The direct light a white Lambert surface in the cell reflects, averaged
// over the points gi.cache.update's paths reached; w > 0 once known.
vec4 cacheDirect(uint slot) { return gCache_Radiance.items[gIn_CacheConstants.cache.capacity + slot]; }

// What a white Lambert surface at `position` facing `normal` reflects of
// indirect light, as the cache knows it (0 for a cell with no samples yet),
// and whether `direct` holds its direct light (gi.cache.direct_light, once
// known); makes and touches the cell, so that it is kept.
bool cacheQueryLight(vec3 position, vec3 normal, out vec3 indirect, out vec3 direct) {
  indirect = vec3(0.0f);
  direct = vec3(0.0f);
  if (gIn_CacheConstants.cache.enabled == 0u) return false;
  uint slot = cacheFindOrMake(cacheKey(position, normal));
  if (slot == kCacheNoCell) return false;
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
