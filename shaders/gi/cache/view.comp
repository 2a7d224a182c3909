#version 460
#extension GL_GOOGLE_include_directive : require
// gi.cache.view (captured frames only): the radiance cache seen from the
// camera. gOut_CacheRadiance: each pixel shows the value of its surface's
// cell (what the cache would answer a world ray hitting there; black where
// there is no cell). gOut_CacheCells: each cell in a colour of its own (its
// size and layout), black without one; along the top, a bar filled to the
// share of the cache's slots in use (white) over its capacity (grey).
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

#define CACHE_FIRST_BINDING 4
#include "gi/cache/radiance_cache.glsl"
layout(set = 0, binding = 11, rgba16f) writeonly uniform image2D gOut_CacheRadiance;
layout(set = 0, binding = 12, rgba8) writeonly uniform image2D gOut_CacheCells;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  CacheConstants c = gIn_CacheConstants.cache;
  int barHeight = max(int(fullSize().y) / 64, 2);
  if (pixel.y < barHeight) {
    float used = float(gCache_Counts.items[0]) / float(c.capacity);
    bool filled = (float(pixel.x) + 0.5f) / fullSize().x <= used;
    imageStore(gOut_CacheCells, pixel, filled ? vec4(1.0f) : vec4(0.3f, 0.3f, 0.3f, 1.0f));
    imageStore(gOut_CacheRadiance, pixel, vec4(0.0f));
    return;
  }
  Surface x = gbufferSurface(pixel);
  uint slot = x.viewZ > 0.0f ? cacheFind(cacheKey(x.position, x.normal)) : kCacheNoCell;
  if (slot == kCacheNoCell) {
    imageStore(gOut_CacheRadiance, pixel, vec4(0.0f));
    imageStore(gOut_CacheCells, pixel, vec4(0.0f, 0.0f, 0.0f, 1.0f));
    return;
  }
  imageStore(gOut_CacheRadiance, pixel, vec4(gCache_Radiance.items[slot].xyz, 1.0f));
  uint h = cacheHash(slot);
  vec3 colour = vec3(float(h & 255u), float((h >> 8u) & 255u), float((h >> 16u) & 255u)) / 255.0f;
  imageStore(gOut_CacheCells, pixel, vec4(0.25f + 0.75f * colour, 1.0f));
}
