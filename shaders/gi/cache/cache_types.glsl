// The radiance cache's constants (gIn_CacheConstants), filled from
// gi::CacheSettings by src/gi/cache/radiance_cache.cpp and laid out
// identically in GLSL (std140) and C++ (checked against each pass's SPIR-V).
#ifndef BOUNCE_GI_CACHE_TYPES_GLSL
#define BOUNCE_GI_CACHE_TYPES_GLSL

#ifdef __cplusplus
#include "shared/lang.glsl"
namespace bounce::shared {
#endif

// The most surfaces an update path bounces off (gi.cache.update_bounces).
const uint kCacheMaxBounces = 4u;

struct CacheConstants {
  vec4 cameraPosition;   // xyz: where cell sizes are measured from
  uint capacity;         // cells; a power of two
  uint enabled;          // 0: queries answer nothing, nothing is written
  uint frame;            // counts frames since the cache was cleared (ages)
  uint updateStride;     // gi.cache.update starts a path at one pixel of every stride x stride block
  uint updateBounces;    // surfaces each update path bounces off at most (1..kCacheMaxBounces)
  float cellSize;        // a cell's edge as a fraction of its distance to the camera
  float historyFrames;   // a cell's value averages at most this many frames of samples
  uint maxAge;           // cells untouched for more frames are evicted
  uint injectStride;     // gi.cache.inject takes one pixel of every stride x stride block
  float environmentMip;  // prefiltered environment level update rays that miss read
  uint directLight;      // 1: cells also hold the direct light at their point (gi.cache.direct_light)
};

#ifdef __cplusplus
}  // namespace bounce::shared
#endif

#endif
