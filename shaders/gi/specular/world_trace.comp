#version 460
#extension GL_GOOGLE_include_directive : require
// gi.specular.world_trace: the rays gi.specular.trace could not finish in
// screen space, traced through the scene bridge from their pixel, one
// thread each. The trace queued them (gIn_WorldQueue: a count, then each
// pixel as x | y << 16; gIn_PendingRay: the ray's direction and pdf) and
// stored their pixel's reservoir without a sample; this pass stores it again
// with the candidate the ray found. Traced apart, a warp's threads all have a
// ray: inside the trace only the pixels screen space failed would trace,
// the others waiting (docs/benchmarks.md, "World rays").
// The pass whose counters its world rays add to (gi/world_ray_count.glsl).
#define WORLD_RAY_PASS kWorldRayPassSpecularWorldTrace
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"

layout(set = 0, binding = 4) uniform sampler2D gIn_BaseColorMetallic;
#define SPECULAR_READS_MATERIAL
#include "gi/specular/specular_common.glsl"
#include "shared/environment.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 5, rgba16f) readonly uniform image2D gPrev_Composite;
layout(set = 0, binding = 6, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 7) uniform sampler2D gIn_Environment;
layout(set = 0, binding = 8, rgba32ui) writeonly uniform uimage2D gOut_Reservoir0;
layout(set = 0, binding = 9, rgba32ui) writeonly uniform uimage2D gOut_Reservoir1;
layout(set = 0, binding = 10, rgba32f) readonly uniform image2D gIn_PendingRay;
layout(set = 0, binding = 11, std430) readonly buffer WorldQueue { uint items[]; } gIn_WorldQueue;
#include "gi/previous_screen.glsl"
#define CACHE_FIRST_BINDING 24
#include "gi/cache/radiance_cache.glsl"
#include "gi/scene_bridge.glsl"
#include "gi/world_rays.glsl"
#include "gi/specular/trace_common.glsl"
#define WORLD_QUEUE_READ
#include "gi/world_queue.glsl"

void main() {
  ivec2 halfPixel;
  if (!queuedPixel(halfPixel)) return;
  ivec2 pixel = reservoirSurfacePixel(halfPixel);
  float roughness;
  Surface x = gbufferSurfaceRoughness(pixel, roughness);
  GlossySurface s = pixelGlossySurface(x, roughness, pixel);
  vec4 pending = imageLoad(gIn_PendingRay, halfPixel);
  vec3 direction = pending.xyz;
  float pdf = pending.w;
  Reservoir r = emptyReservoir();
  r.M = 1.0f;
  // A rough lobe blurs what it reflects over more than a cache cell: its
  // hits may take their direct light from the cell instead of a shadow ray.
  bool directFromCache = s.roughness >= gIn_SpecularConstants.specular.cachedDirectRoughness;
  Reservoir candidate =
      worldCandidate(rayOrigin(x.position, x.normal, x.viewZ), direction, x.normal, directFromCache);
  storeCandidate(halfPixel, r, true, candidate, s, pdf);
}
