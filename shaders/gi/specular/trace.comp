#version 460
#extension GL_GOOGLE_include_directive : require
// gi.specular.trace: one ray per half-resolution pixel and frame (the Jitter gi pass's specular ReSTIR,
// "Sample gathering"), its direction drawn from the specular lobe
// (gi.specular.sampling: GGX visible normals, or uniformly in a cone: Zyanide's
// uniform-lobe reservoirs) with the pixel's own cycle through the first 64 Halton (2, 3) points
// (its own start and rotation). The ray is traced through this frame's
// min-max depth pyramid first (Hi-Z, gi/hiz_trace.glsl, at most
// gi.specular.trace_steps cells): a surface it hits that last frame's screen showed
// sends what last frame's composite holds there, every bounce the feedback
// has added included. What screen space cannot finish (the ray leaves the
// screen, passes behind a surface of unknown thickness, or only seems to
// reach the sky), or whose hit last frame's screen showed from a side that
// glossy surface looks different from, continues through the scene bridge
// from the start, in gi.specular.world_trace: this pass queues it (its
// direction and pdf in gOut_PendingRay, the pixel in gOut_WorldQueue) so
// that the world rays of a frame are traced together. With the bridge
// "none" such rays follow screen-only mode's policy
// (gi/screen_only_policy.glsl): one that met a background pixel sees the
// environment prefiltered at the lobe's roughness, one that passed behind a
// surface is blocked by it, one that left the screen sees what the screen's
// edge shows where it left. The sample goes into a fresh
// reservoir (M = 1) with the target of its sampling; its hit point keeps the
// hit distance, which the resolve and the filter need. A pixel at least
// gi.specular.diffuse_sample_roughness rough casts no ray: it takes the
// diffuse branch's final sample of this frame instead (storeDiffuseSample).
// The pass whose counters its world rays add to (gi/world_ray_count.glsl).
#define WORLD_RAY_PASS kWorldRayPassSpecularTrace
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
#define HIZ_BINDING 10
#define HIZ_LEVEL0_BINDING 17
#include "gi/hiz_trace.glsl"
#include "gi/previous_screen.glsl"
#define CACHE_FIRST_BINDING 24
#include "gi/cache/radiance_cache.glsl"
#include "gi/scene_bridge.glsl"
#include "gi/world_rays.glsl"

const uint kSaltSpecularTrace = 0x7374u;

#define WORLD_QUEUE_BINDING 11
layout(set = 0, binding = WORLD_QUEUE_BINDING, rgba32f) writeonly uniform image2D gOut_PendingRay;
layout(set = 0, binding = WORLD_QUEUE_BINDING + 1, std430) buffer WorldQueue { uint items[]; } gOut_WorldQueue;
#include "gi/specular/trace_common.glsl"

#define WORLD_QUEUE_APPEND
#include "gi/world_queue.glsl"
#define SCREEN_TILES_BINDING 13
#include "gi/screen_only_policy.glsl"
// The diffuse branch's final reservoirs of this frame (rough pixels take
// their sample; bound to something else, and never read, where
// diffuseSampleRoughness is above 1).
layout(set = 0, binding = 15, rgba32ui) readonly uniform uimage2D gIn_Diffuse_Reservoir0;
layout(set = 0, binding = 16, rgba32ui) readonly uniform uimage2D gIn_Diffuse_Reservoir1;

// The fresh reservoir of a pixel at least diffuseSampleRoughness rough:
// the diffuse branch's final sample at the same surface (the same
// half-resolution pixel), streamed in with that reservoir's unbiased
// contribution weight W as the inverse of its pdf (per unit solid angle,
// as the specular lobe's). RIS with a source pdf known only through W
// stays unbiased where the source's target covers the new one: the
// diffuse target (the sample's luminance times the cosine) is positive
// wherever the specular target (BRDF times the cosine times the radiance)
// is. A reservoir without a sample, or with W = 0 (not visible), leaves
// the pixel a frame with nothing, as its estimate says.
void storeDiffuseSample(ivec2 halfPixel, Reservoir r, GlossySurface s) {
  Reservoir diffuse = unpackReservoir(imageLoad(gIn_Diffuse_Reservoir0, halfPixel),
                                      imageLoad(gIn_Diffuse_Reservoir1, halfPixel));
  bool found = reservoirHasSample(diffuse) && diffuse.W > 0.0f && isFinite(diffuse.W);
  Reservoir candidate = emptyReservoir();
  candidate.flags = kReservoirHasSample | (diffuse.flags & kReservoirEnvironment);
  candidate.position = diffuse.position;
  candidate.normal = diffuse.normal;
  candidate.radiance = sanitizeRadiance(diffuse.radiance);
  storeCandidate(halfPixel, r, found, candidate, s, found ? 1.0f / diffuse.W : 1.0f);
}

// Where an undecided ray that did not pass behind a surface on screen left
// the screen: where the segment from its origin's pixel through the last
// point the trace vouched for crosses the edge.
ivec2 exitPixel(vec3 origin, HizRay ray, out bool towardsCamera) {
  ScreenView view = gIn_Frame.frame.view;
  vec3 start = projectViewPoint(view, toViewSpace(view, origin), fullSize());
  vec2 from = start.xy;
  vec3 last = projectViewPoint(view, toViewSpace(view, ray.lastFree), fullSize());
  towardsCamera = last.z < start.z;
  vec2 beyond = last.z > 0.0f && isFinite(last) ? last.xy + (last.xy - from) : from;
  return screenExitPixel(from, beyond);
}

// Leaves this pixel's ray to gi.specular.world_trace: its direction and pdf,
// and the pixel appended to the queue.
void enqueueWorldRay(ivec2 halfPixel, vec3 direction, float pdf) {
  imageStore(gOut_PendingRay, halfPixel, vec4(direction, pdf));
  enqueuePixel(halfPixel);
}

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideHalf(halfPixel)) return;
  ivec2 pixel = reservoirSurfacePixel(halfPixel);
  Reservoir r = emptyReservoir();
  float roughness;
  Surface x = gbufferSurfaceRoughness(pixel, roughness);
  if (x.viewZ <= 0.0f) {
    store(halfPixel, r);
    return;
  }
  r.M = 1.0f;  // one frame's ray, even when it finds nothing: later merges must weigh that too
  SpecularConstants c = gIn_SpecularConstants.specular;
  GlossySurface s = pixelGlossySurface(x, roughness, pixel);
  if (s.roughness >= c.diffuseSampleRoughness) {
    storeDiffuseSample(halfPixel, r, s);
    return;
  }
  uint pixelSeed = rngSeed(uvec2(halfPixel), 0u, gIn_Frame.frame.seed ^ kSaltSpecularTrace);
  vec2 u = haltonPixelSample(gIn_Frame.frame.frameIndex, pixelSeed);
  vec3 direction;
  float pdf;
  if (!sampleSpecularDirection(s, c.sampling, c.lobeFraction, u, direction, pdf)) {
    store(halfPixel, r);
    return;
  }

  vec3 origin = rayOrigin(x.position, x.normal, x.viewZ);
  Reservoir candidate = emptyReservoir();
  candidate.flags = kReservoirHasSample;
  bool found = false;
  bool seesSky = false;  // it met a background pixel
  ivec2 exit = pixel;    // undecided: where it left the screen
  bool towardsCamera = false;
  if (c.traceSteps > 0u) {
    HizRay ray = hizTrace(origin, direction, c.traceThickness, c.traceSteps);
    seesSky = ray.outcome == kHizSky;
    // Where what it met is read if last frame did not show it: the tile of
    // the surface it met or passed behind, else where it left the screen.
    if (ray.outcome != kHizSky) exit = ray.texel.x >= 0 ? ray.texel : exitPixel(origin, ray, towardsCamera);
    // Screen-only: a ray that passed behind a surface is blocked by it (gi/screen_only_policy.glsl).
    if (ray.outcome == kHizHit || (!kSceneBridgeTraces && ray.outcome == kHizUndecided && ray.texel.x >= 0)) {
      float hitRoughness;
      Surface y = gbufferSurfaceRoughness(ray.texel, hitRoughness);
      if (y.viewZ > 0.0f) {
        // The sample is where the ray meets the surface, not the pixel's
        // sample point: a glossy lobe re-evaluated towards the pixel's
        // centre (up to a pixel's angle off the ray) would weigh it by the
        // wrong D, for a near-mirror by orders of magnitude.
        candidate.position = ray.lastFree;
        candidate.normal = y.normal;
        found = previousRadiance(y.position, y.normal, hitRoughness, direction, candidate.radiance);
      }
    }
  }
  if (!found && kSceneBridgeTraces) {
    // Through the scene from the start, in a pass of its own (the reservoir
    // stored here, M = 1 and no sample, is what it fills in).
    enqueueWorldRay(halfPixel, direction, pdf);
    store(halfPixel, r);
    return;
  }
  if (!found) {
    // No bridge: screen-only mode's policy. A direction, as environment
    // samples are: what it sees is taken as far away.
    candidate.position = direction;
    candidate.normal = x.normal;
    candidate.flags |= kReservoirEnvironment;
    vec3 environment = sanitizeRadiance(
        environmentRadianceLod(gIn_Environment, direction, environmentLod(s.roughness, c.environmentLevels)));
    candidate.radiance = seesSky ? environment : beyondTheScreen(exit, environment, towardsCamera);
    found = true;
  }
  storeCandidate(halfPixel, r, found, candidate, s, pdf);
}
