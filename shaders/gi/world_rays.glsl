// Rays beyond the screen through the scene bridge, as the diffuse branch
// casts them: where they start, visibility of a sample from a surface, and
// the radiance a world hit sends back. The including shader includes
// gi/gi_common.glsl and gi/scene_bridge.glsl first and, when it binds the
// radiance cache, gi/cache/radiance_cache.glsl (RADIANCE_CACHE defined);
// every function is only called where kSceneBridgeTraces holds. Every ray
// is counted under the `purpose` its caller gives (gi/world_ray_count.glsl),
// which must be the same for every invocation calling together.
#ifndef BOUNCE_GI_WORLD_RAYS_GLSL
#define BOUNCE_GI_WORLD_RAYS_GLSL

#include "shared/brdf.glsl"
#include "shared/reservoir.glsl"

// How far a ray starts off its surface: grows with distance from the
// camera and from the origin, so float precision keeps up (the renderer's
// offsetOrigin rule; the library has no geometric normal, so along the
// shading normal).
float rayOffset(vec3 position, float viewZ) { return 2e-4f * max(1.0f, viewZ) + 1e-4f * length(position); }
vec3 rayOrigin(vec3 position, vec3 normal, float viewZ) { return position + normal * rayOffset(position, viewZ); }

// Whether nothing lies between the surface at `from` and the point `to` on
// another surface (the ray stops short of it by its own offset).
bool worldSegmentVisible(vec3 from, vec3 normal, float viewZ, vec3 to, uint purpose) {
  vec3 origin = rayOrigin(from, normal, viewZ);
  vec3 d = to - origin;
  float length2 = dot(d, d);
  if (!(length2 > 0.0f)) return true;
  float len = sqrt(length2);
  float end = len * (1.0f - 1e-3f) - 2.0f * rayOffset(to, viewZ);
  if (end <= 0.0f) return true;
  countWorldRay(purpose);
  return !sceneTraceAny(origin, d / len, end);
}

// Whether the environment is reached from `from` along `direction`.
bool worldDirectionOpen(vec3 from, vec3 normal, float viewZ, vec3 direction, uint purpose) {
  countWorldRay(purpose);
  return !sceneTraceAny(rayOrigin(from, normal, viewZ), direction, 3.0e38f);
}

// Whether the surface `at` sees a reservoir's sample: the point on a
// surface it holds, or the environment in the direction it holds.
bool worldSeesSample(Reservoir r, Surface at, uint purpose) {
  return reservoirIsEnvironment(r) ? worldDirectionOpen(at.position, at.normal, at.viewZ, r.position, purpose)
                                   : worldSegmentVisible(at.position, at.normal, at.viewZ, r.position, purpose);
}

// The first surface along a ray from `origin`, counted under `purpose`.
SceneHit worldTraceClosest(vec3 origin, vec3 direction, uint purpose) {
  countWorldRay(purpose);
  return sceneTraceClosest(origin, direction, 3.0e38f);
}

// What a world hit reflects towards the ray's origin of light arriving
// evenly: its diffuse albedo and its specular reflectance. At most 1: the
// model's white dielectric reflects a few per cent more (its Lambert lobe
// is not reduced by the Fresnel term), and a loop of light through the
// radiance cache must not gain.
vec3 hitReflectance(SceneHit hit, vec3 direction) {
  vec3 specular = specularReflectance(specularF0(hit.baseColor, hit.metallic), dot(hit.normal, -direction),
                                      hit.roughness);
  return min(hit.diffuseAlbedo + specular, vec3(1.0f));
}

// The radiance a world hit sends back along the ray, off screen: its
// emission, the direct light the bridge computes, and the light arriving
// by more bounces from the radiance cache (none without it). With
// `directFromCache` and gi.cache.direct_light, a hit whose cell knows its
// direct light takes it from there instead of asking the bridge, whose
// shadow rays are then the cell's one a frame instead of one per hit. The
// cell knows what a white Lambert surface reflects; the hit reflects its
// diffuse albedo of that and, for its specular lobe, which depends on the
// light's direction the cell does not keep, its specular reflectance
// towards the ray's origin (shared/brdf.glsl: what it reflects of light
// arriving evenly). That holds for the cell's direct and indirect light
// alike: without it metals would reflect no direct light at all (pillars'
// gold: 4 % less indirect diffuse), and the light that reaches a diffuse
// surface over a glossy one would be missing (the reference with diffuse
// paths only has 17 % less on pillars, 14 % on the Breakfast Room).
vec3 offscreenHitRadiance(SceneHit hit, vec3 direction, bool directFromCache) {
  vec3 radiance = hit.emission;
#ifdef RADIANCE_CACHE
  // The reflectance is worked out after the bridge's shadow ray, not
  // before: held across the trace, its registers slowed
  // gi.diffuse.world_candidates by 13 % (the Breakfast Room at 1080p on the
  // H200, docs/benchmarks.md).
  vec3 indirect, direct;
  if (cacheQueryLight(hit.position, hit.normal, indirect, direct) && directFromCache)
    radiance += hitReflectance(hit, direction) * (indirect + direct);
  else {
    radiance += sceneDirectRadiance(hit, -direction);
    radiance += hitReflectance(hit, direction) * indirect;
  }
#else
  radiance += sceneDirectRadiance(hit, -direction);
#endif
  return sanitizeRadiance(radiance);
}

#endif
