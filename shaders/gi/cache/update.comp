#version 460
#extension GL_GOOGLE_include_directive : require
// gi.cache.update: paths through the scene bridge that fill the radiance
// cache with several bounces a frame (SHaRC's update). One path starts at
// one pixel of every updateStride x updateStride block of the frame (a
// different pixel each frame) and bounces off up to updateBounces surfaces,
// cosine distributed about each one's normal. Each surface it reaches is
// lit by the bridge's direct light for a white Lambert surface there (with
// gi.cache.direct_light worked out at one of them and added to its cell,
// read from the cell at the others; the branches' world hits read the
// cells too); the light the path carries back towards each
// surface it left is added to that surface's cell as one sample of what a
// white Lambert surface there reflects (cosine sampling: the mean of those
// radiances). The last surface takes what follows from the cache's own value
// there; a miss sees the environment. Light thus crosses updateBounces
// bounces in one frame instead of one, and every sample is an integer added
// to an integer (radiance_cache.glsl): which thread adds first changes no
// bit. (The pass is made only with a bridge that traces.)
// The pass whose counters its world rays add to (gi/world_ray_count.glsl).
#define WORLD_RAY_PASS kWorldRayPassCacheUpdate
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "shared/brdf.glsl"
#include "shared/color.glsl"
#include "shared/equirect.glsl"
#include "shared/sampling.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

#define CACHE_FIRST_BINDING 4
#include "gi/cache/radiance_cache.glsl"
layout(set = 0, binding = 11) uniform sampler2D gIn_Environment;
#define LIGHT_CHANGE_BINDING 12
#include "gi/light_change/light_change.glsl"
#include "gi/scene_bridge.glsl"
#include "gi/world_rays.glsl"

const uint kSaltCacheUpdate = 0x6375u;

// What a path keeps of each surface it left: the cell that takes the
// light arriving there along the ray it left by, that light so far, and
// how much of the light found further along still reaches it.
struct PathVertex {
  uint slot;
  vec3 arriving;
  vec3 throughput;
};

// The bridge's direct light (shadow rays included) that a white Lambert
// surface at the hit reflects.
vec3 whiteDirectLight(SceneHit hit) {
  SceneHit white = sceneMiss();
  white.hit = true;
  white.t = hit.t;
  white.position = hit.position;
  white.geometricNormal = hit.geometricNormal;
  white.normal = hit.normal;
  white.diffuseAlbedo = vec3(1.0f);
  white.baseColor = vec3(1.0f);
  return sanitizeRadiance(sceneDirectRadiance(white, hit.normal));
}

// With gi.cache.direct_light a path works the direct light out (shadow
// rays) at one of its surfaces, a different one each frame, and adds it to
// that surface's cell; at the others it takes the cell's, once known. The
// bounces of a path run one after the other, so each shadow ray left out
// shortens the pass (the Breakfast Room at 1080p on the H100: 1.78 ->
// 1.50 ms, the same pictures).
bool cachedDirect(uint slot, bool fresh, out vec3 direct) {
  direct = vec3(0.0f);
  if (gIn_CacheConstants.cache.directLight == 0u || fresh || slot == kCacheNoCell) return false;
  vec4 known = cacheDirect(slot);
  direct = known.xyz;
  return known.w > 0.0f;
}

// While the light changes: this direct light, worked out anew, and what
// the cell held before, added to the frame's sums (gCache_Counts [1] and
// [2]), from which gi.cache.resolve scales every cell's indirect light.
void sumLightChange(uint slot, vec3 direct) {
  vec4 known = cacheDirect(slot);
  if (known.w <= 0.0f) return;
  atomicAdd(gCache_Counts.items[1], uint(min(luminance(direct), kCacheLightSumMax) * kCacheLightSumScale + 0.5f));
  atomicAdd(gCache_Counts.items[2], uint(min(luminance(known.xyz), kCacheLightSumMax) * kCacheLightSumScale + 0.5f));
}

void main() {
  CacheConstants c = gIn_CacheConstants.cache;
  if (!kSceneBridgeTraces || c.enabled == 0u) return;
  uvec2 block = gl_GlobalInvocationID.xy;
  uint rng = giSeed(block, kSaltCacheUpdate);
  ivec2 pixel = ivec2(block * c.updateStride) +
                ivec2(min(uvec2(rngUniform(rng) * float(c.updateStride), rngUniform(rng) * float(c.updateStride)),
                          uvec2(c.updateStride - 1u)));
  if (!insideFull(pixel)) return;
  Surface start = gbufferSurface(pixel);
  if (start.viewZ <= 0.0f) return;

  uvec2 paths = gl_NumWorkGroups.xy * gl_WorkGroupSize.xy;
  uint pathIndex = block.y * paths.x + block.x;
  uint summingEvery = (paths.x * paths.y + kCacheLightSumPaths - 1u) / kCacheLightSumPaths;
  bool changing = historyKept() < 1.0f && pathIndex % summingEvery == 0u;
  PathVertex path[kCacheMaxBounces];
  uint freshBounce = min(uint(rngUniform(rng) * float(c.updateBounces)), c.updateBounces - 1u);
  vec3 position = start.position;
  vec3 normal = start.normal;
  uint here = cacheFindOrMake(cacheKey(position, normal));  // the cell of the surface the path is on
  uint left = 0u;  // surfaces the path has left so far
  bool open = false;  // the last ray missed: the environment ends the path
  vec3 environment = vec3(0.0f);
  for (uint bounce = 0u; bounce < c.updateBounces; ++bounce) {
    float distance = length(position - c.cameraPosition.xyz);
    vec3 t, b;
    buildOrthonormalBasis(normal, t, b);
    vec3 local = sampleCosineHemisphere(vec2(rngUniform(rng), rngUniform(rng)));
    vec3 direction = normalize(t * local.x + b * local.y + normal * local.z);
    path[left] = PathVertex(here, vec3(0.0f), vec3(1.0f));
    ++left;
    SceneHit hit = worldTraceClosest(rayOrigin(position, normal, distance), direction, kWorldRaysCacheUpdate);
    if (!hit.hit) {
      open = true;
      environment = sanitizeRadiance(textureLod(gIn_Environment, equirectUv(direction), c.environmentMip).xyz);
      break;
    }
    // The light of this surface towards the one the ray left: its emission
    // and its direct light, and what it reflects of the light found further
    // along (its diffuse and its specular reflectance of light arriving
    // evenly, as offscreenHitRadiance lights a world hit: light that
    // crosses a glossy surface on its way counts too).
    here = cacheFindOrMake(cacheKey(hit.position, hit.normal));
    vec3 direct;
    if (!cachedDirect(here, bounce == freshBounce, direct)) {
      direct = whiteDirectLight(hit);
      if (c.directLight != 0u && here != kCacheNoCell) {
        if (changing) sumLightChange(here, direct);
        cacheAddDirectSample(here, direct);
      }
    }
    vec3 reflectance = hitReflectance(hit, direction);
    vec3 emitted = hit.emission + reflectance * direct;
    for (uint i = 0u; i < left; ++i) {
      path[i].arriving += path[i].throughput * emitted;
      path[i].throughput *= reflectance;
    }
    position = hit.position;
    normal = hit.normal;
  }
  // What lies beyond the last surface: the environment the last ray saw, or
  // the cache's value at the surface it stopped on (more bounces).
  vec3 beyond = environment;
  if (!open && here != kCacheNoCell) beyond = gCache_Radiance.items[here].xyz;
  for (uint i = 0u; i < left; ++i)
    if (path[i].slot != kCacheNoCell) cacheAddSample(path[i].slot, path[i].arriving + path[i].throughput * beyond);
}
