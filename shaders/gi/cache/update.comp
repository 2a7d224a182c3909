#version 460
#extension GL_GOOGLE_include_directive : require
// gi.cache.update: one ray from each radiance-cache cell listed this frame
// (the cells world hits used; at most gi.cache.update_rays), cosine
// distributed about the cell's normal and traced through the scene bridge.
// (It runs without a bridge too, for the bookkeeping, and traces nothing.)
// Its hit is shaded with the bridge's direct light, its emission and the
// cache's own value there (more bounces, no recursion); a miss sees the
// environment. With cosine sampling the mean of those radiances is what a
// white Lambert surface at the cell reflects. With gi.cache.direct_light,
// the cell's own direct light is worked out here too (the bridge's, for a
// white Lambert surface at the cell's point), for the hits that read it.
#include "gi/gi_common.glsl"
#include "shared/equirect.glsl"
#include "shared/sampling.glsl"

layout(local_size_x = 64) in;

#define CACHE_FIRST_BINDING 4
#include "gi/cache/radiance_cache.glsl"
layout(set = 0, binding = 11) uniform sampler2D gIn_Environment;
#include "gi/scene_bridge.glsl"
#include "gi/world_rays.glsl"

const uint kSaltCacheUpdate = 0x6375u;

void main() {
  CacheConstants c = gIn_CacheConstants.cache;
  uint index = gl_GlobalInvocationID.x;
  if (index == 0u) gCache_Updates.items[1] = 0u;  // gi.cache.resolve counts the live cells anew
  if (!kSceneBridgeTraces) return;
  if (index >= min(gCache_Updates.items[0], c.updateBudget)) return;
  uint slot = gCache_Updates.items[2u + index];
  // A slot listed but not yet written by the toucher (lists are appended
  // while this pass reads them) may hold another cell: then this is still a
  // sample of that cell, from that cell's own place.
  if (slot >= c.capacity || gCache_Keys.items[slot] == 0u) return;
  uvec4 cell = gCache_Cells.items[slot];
  vec3 position = uintBitsToFloat(cell.xyz);
  vec3 normal = unpackNormalOct32(cell.w);
  if (!isFinite(position)) return;
  uint rng = giSeed(uvec2(index, slot), kSaltCacheUpdate);
  vec3 t, b;
  buildOrthonormalBasis(normal, t, b);
  vec3 local = sampleCosineHemisphere(vec2(rngUniform(rng), rngUniform(rng)));
  vec3 direction = normalize(t * local.x + b * local.y + normal * local.z);
  float distance = length(position - c.cameraPosition.xyz);
  SceneHit hit = worldTraceClosest(rayOrigin(position, normal, distance), direction, kWorldRaysCacheUpdate);
  vec3 radiance = hit.hit ? offscreenHitRadiance(hit, direction, true)
                          : sanitizeRadiance(textureLod(gIn_Environment, equirectUv(direction), c.environmentMip).xyz);
  cacheAddSample(slot, radiance);
  if (c.directLight != 0u) {
    SceneHit at = sceneMiss();
    at.hit = true;
    at.t = distance;
    at.position = position;
    at.geometricNormal = normal;
    at.normal = normal;
    at.diffuseAlbedo = vec3(1.0f);
    at.baseColor = vec3(1.0f);
    cacheSetDirect(slot, sceneDirectRadiance(at, normal));
  }
}
