#version 460
#extension GL_GOOGLE_include_directive : require
// gi.cache.resolve: one thread per radiance-cache slot. Folds the samples
// the frame added into the cell's values, indirect and direct (each a
// running mean over at most gi.cache.history_samples samples, so it
// follows changes of light), clears the accumulators, and evicts cells
// nobody touched for gi.cache.max_age frames. After a change of light
// (gi.light_change) every cell's samples count as fewer, so what follows
// outweighs what was, and while the light that bounces more than once
// still arrives a cell holds no more frames of samples than the screen's
// histories do (the hold, counted in this frame's samples of the cell).
// Also counts the live cells into gCache_Counts[0] (the host zeroes the
// counts before gi.cache.update; gi.cache.view's occupancy bar shows it).
#include "gpu/constant_block.glsl"
#include "shared/finite.glsl"
#include "shared/packing.glsl"

layout(local_size_x = 64) in;

#define CACHE_FIRST_BINDING 0
#include "gi/cache/radiance_cache.glsl"
#define LIGHT_CHANGE_BINDING 7
#include "gi/light_change/light_change.glsl"

// Folds the samples accumulated in `entry` into its value. After a change
// of light (kept < 1) the samples held count as fewer; a cell's indirect
// light is scaled by the direct light now over before (`scale`,
// directLightRatio): the light that has bounced many times, which cells
// hold and which takes longest to rebuild, follows the light put in (the
// old value left as it was would circulate through the paths that end on
// the cell; emptied, it would be rebuilt from nothing). A cell's direct
// light (`direct`) left with less than one sample is emptied: a shadow ray
// makes it anew.
void fold(uint entry, float historySamples, float kept, float hold, float scale, bool direct) {
  uvec4 added = gCache_Accumulators.items[entry];
  vec4 held = gCache_Radiance.items[entry];
  if (kept < 1.0f) {
    held = direct ? vec4(held.xyz, held.w * kept) : vec4(held.xyz * scale, held.w * kept);
    if (direct && held.w < 1.0f) held = vec4(0.0f);
  }
  if (added.w == 0u) {
    if (kept < 1.0f) gCache_Radiance.items[entry] = held;
    return;
  }
  held.w = min(held.w, hold * float(added.w));
  vec3 mean = vec3(added.xyz) / (kCacheFixedScale * float(added.w));
  // A frame with more samples than the history holds replaces the value
  // (a weight above 1 would overshoot it).
  float samples = min(held.w + float(added.w), max(historySamples, float(added.w)));
  vec3 value = mix(held.xyz, mean, float(added.w) / samples);
  gCache_Radiance.items[entry] = vec4(sanitizeRadiance(value), min(samples, historySamples));
  gCache_Accumulators.items[entry] = uvec4(0u);
}

// The direct light the update's paths worked out anew over what their
// cells held (gCache_Counts [1] and [2]); 1 where no cell held any.
float directLightRatio() {
  uint before = gCache_Counts.items[2];
  if (before == 0u) return 1.0f;
  return min(float(gCache_Counts.items[1]) / float(before), kCacheLightRatioLimit);
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
  float kept = historyKept(), hold = historyHold();
  fold(slot, c.historyFrames, kept, hold, directLightRatio(), false);
  fold(c.capacity + slot, c.historyFrames, kept, hold, 1.0f, true);
}
