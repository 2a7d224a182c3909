#version 460
#extension GL_GOOGLE_include_directive : require
// gi.cache.resolve: one thread per radiance-cache slot. Folds the samples
// the frame added into the cell's values, indirect and direct (each a
// running mean over at most gi.cache.history_samples samples, so it
// follows changes of light), clears the accumulators, and evicts cells
// nobody touched for gi.cache.max_age frames. Also counts the live cells
// into gCache_Counts[0] (the host zeroes it before this pass; gi.cache.view's
// occupancy bar shows it).
#include "gpu/constant_block.glsl"
#include "shared/finite.glsl"
#include "shared/packing.glsl"

layout(local_size_x = 64) in;

#define CACHE_FIRST_BINDING 0
#include "gi/cache/radiance_cache.glsl"

// Folds the samples accumulated in `entry` into its value.
void fold(uint entry, float historySamples) {
  uvec4 added = gCache_Accumulators.items[entry];
  if (added.w == 0u) return;
  vec4 held = gCache_Radiance.items[entry];
  vec3 mean = vec3(added.xyz) / (kCacheFixedScale * float(added.w));
  // A frame with more samples than the history holds replaces the value
  // (a weight above 1 would overshoot it).
  float samples = min(held.w + float(added.w), max(historySamples, float(added.w)));
  vec3 value = mix(held.xyz, mean, float(added.w) / samples);
  gCache_Radiance.items[entry] = vec4(sanitizeRadiance(value), min(samples, historySamples));
  gCache_Accumulators.items[entry] = uvec4(0u);
}

void main() {
  CacheConstants c = gIn_CacheConstants.cache;
  uint slot = gl_GlobalInvocationID.x;
  if (slot >= c.capacity || gCache_Keys.items[slot] == 0u) return;
  if (c.frame - gCache_Touched.items[slot] > c.maxAge) {
    gCache_Keys.items[slot] = 0u;
    gCache_Radiance.items[slot] = vec4(0.0f);
    gCache_Radiance.items[c.capacity + slot] = vec4(0.0f);
    gCache_Accumulators.items[slot] = uvec4(0u);
    gCache_Accumulators.items[c.capacity + slot] = uvec4(0u);
    return;
  }
  atomicAdd(gCache_Counts.items[0], 1u);
  fold(slot, c.historyFrames);
  fold(c.capacity + slot, c.historyFrames);
}
