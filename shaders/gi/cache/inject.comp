#version 460
#extension GL_GOOGLE_include_directive : require
// gi.cache.inject: the radiance cache filled for free from what the screen
// already knows. One pixel of every stride x stride block of the last frame
// (a different one each frame) adds its filtered indirect diffuse
// (demodulated: exactly the cells' quantity) to the cell of its surface.
// Not while the light changes (gi.light_change): last frame's picture is
// of the old light, and the cells are starting over.
#include "gi/gi_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

#define CACHE_FIRST_BINDING 4
#include "gi/cache/radiance_cache.glsl"
layout(set = 0, binding = 11, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 12) uniform sampler2D gPrev_Diffuse;
#define LIGHT_CHANGE_BINDING 13
#include "gi/light_change/light_change.glsl"

const uint kSaltCacheInject = 0x696eu;

void main() {
  CacheConstants c = gIn_CacheConstants.cache;
  if (c.enabled == 0u || !historyUsable() || historyKept() < 1.0f) return;
  uint stride = c.injectStride;
  uint rng = giSeed(uvec2(gl_GlobalInvocationID.xy), kSaltCacheInject);
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy * stride) +
                ivec2(min(uvec2(rngUniform(rng) * float(stride), rngUniform(rng) * float(stride)), uvec2(stride - 1u)));
  if (!insideFull(pixel)) return;
  Surface y = historySurfaceAt(pixel, imageLoad(gPrev_Surface, pixel).xy);
  if (y.viewZ <= 0.0f) return;
  vec4 diffuse = texelFetch(gPrev_Diffuse, pixel, 0);
  if (diffuse.w < 1.0f) return;  // no history behind it yet: too noisy to keep
  uint slot = cacheFindOrMake(cacheKey(y.position, y.normal));
  if (slot == kCacheNoCell) return;
  cacheAddSample(slot, diffuse.xyz);
}
