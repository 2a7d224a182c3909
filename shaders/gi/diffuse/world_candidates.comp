#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.world_candidates: the ray candidates gi.diffuse.gather could
// not settle by marching the depth buffer, traced through the scene bridge
// from their pixel's surface, one thread per pixel that has any. The gather
// queued those pixels (gIn_WorldQueue: a count, then each as x | y << 16),
// left each waiting ray's direction (gIn_PendingRays, per reservoir and
// candidate; w = 1 where one waits) and stored the pixel's reservoir
// unfinished, W holding the weight sum of the candidates streamed so far.
// Here each waiting ray is traced and its candidate streamed in as the
// gather would have (a hit last frame showed takes that pixel's radiance
// and counts the point techniques; one off screen is lit by the bridge and
// the radiance cache; a miss sees the environment), and the reservoir is
// finalized. Apart from the gather, a warp's threads all have rays to trace,
// and the traversal does not share its registers with the gather's
// candidates (docs/benchmarks.md, "World rays").
// The pass whose counters its world rays add to (gi/world_ray_count.glsl).
#define WORLD_RAY_PASS kWorldRayPassWorldCandidates
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "gi/diffuse/diffuse_common.glsl"
#include "shared/equirect.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4, rgba16f) readonly uniform image2D gPrev_Composite;
layout(set = 0, binding = 5, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 6, rgba32f) readonly uniform image2D gIn_Brightest;
layout(set = 0, binding = 7) uniform sampler2D gIn_Environment;
layout(set = 0, binding = 8, rgba32ui) uniform uimage2D gInOut_Reservoir0;
layout(set = 0, binding = 9, rgba32ui) uniform uimage2D gInOut_Reservoir1;
layout(set = 0, binding = 11, std430) readonly buffer PendingRays { vec4 items[]; } gIn_PendingRays;
layout(set = 0, binding = 12, std430) readonly buffer WorldQueue { uint items[]; } gIn_WorldQueue;

#include "gi/diffuse/previous_screen.glsl"
#define CACHE_FIRST_BINDING 24
#include "gi/cache/radiance_cache.glsl"
#include "gi/scene_bridge.glsl"
#include "gi/world_rays.glsl"
#include "gi/diffuse/gather_common.glsl"
#define WORLD_QUEUE_READ
#include "gi/world_queue.glsl"

const uint kSaltWorldCandidates = 0x7763u;

void main() {
  ivec2 halfPixel;
  if (!queuedPixel(halfPixel)) return;
  Surface x = gbufferSurface(reservoirSurfacePixel(halfPixel));
  Reservoir r = unpackReservoir(imageLoad(gInOut_Reservoir0, halfPixel), imageLoad(gInOut_Reservoir1, halfPixel));
  r.weightSum = r.W;
  DiffuseConstants d = gIn_DiffuseConstants.diffuse;
  uint rng = giSeed(uvec2(halfPixel), kSaltWorldCandidates);
  float nearField = nearFieldDistance(x);
  vec3 origin = rayOrigin(x.position, x.normal, x.viewZ);
  for (uint i = 0u; i < d.rayCandidates; ++i) {
    uint slot = halfPixelSlot(halfPixel, d.rayCandidates, i);
    vec4 pending = gIn_PendingRays.items[slot];
    float choice = rngUniform(rng);
    if (pending.w == 0.0f) continue;
    vec3 direction = pending.xyz;
    SceneHit hit = worldTraceClosest(origin, direction, kWorldRaysDiffuseCandidates);
    ivec2 shown = ivec2(-1);
    vec3 position = direction, normal = x.normal, radiance;
    uint flags = 0u;
    if (!hit.hit) {
      radiance = sanitizeRadiance(textureLod(gIn_Environment, equirectUv(direction), d.environmentMip).xyz);
      flags = kReservoirEnvironment;
    } else {
      position = hit.position;
      normal = hit.normal;
      shown = previousPixelOf(hit.position, hit.normal);
      radiance = shown.x >= 0 ? vec3(0.0f) : offscreenHitRadiance(hit, direction, true);
    }
    streamRayCandidate(r, x, rayTechnique(x.normal, direction), shown, position, normal, radiance, flags, nearField,
                       choice);
  }
  reservoirFinalize(r, targetPdf(r, x.position, x.normal, d.targetFunction), 1.0f);
  r.M = 1.0f;
  uvec4 first, second;
  packReservoir(r, first, second);
  imageStore(gInOut_Reservoir0, halfPixel, first);
  imageStore(gInOut_Reservoir1, halfPixel, second);
}
