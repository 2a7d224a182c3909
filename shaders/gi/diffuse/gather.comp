#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.gather: one reservoir per half-resolution pixel, from three
// kinds of candidates (the Jitter gi pass's diffuse ReSTIR, "Sample gathering" and "Sample weighting"):
//   screen       uniformly random pixels of the previous composited frame:
//                a surface that sent that radiance towards the camera, and
//                (Lambert) towards us; the feedback that makes multiple bounces;
//   bright       random picks among the brightest pixels of that frame;
//   environment  (without a scene bridge that traces) uniform directions
//                of the hemisphere, seen as screen-only mode's policy says
//                (gi/screen_only_policy.glsl): marched through the depth
//                buffer, a direction that reaches the sky on screen reads the
//                prefiltered environment at mip gi.diffuse.environment_mip,
//                one that leaves the screen first what the screen shows
//                where it leaves; one a surface on screen blocks is left
//                to the screen candidates, which sample that surface.
//   ray          (with a scene bridge that traces, in place of environment
//                candidates) cosine-distributed directions, marched through
//                the depth buffer; a hit on last frame's screen takes that
//                pixel's radiance. Where the march cannot decide, the ray is
//                left to gi.diffuse.world_candidates (its direction in
//                gOut_PendingRays, the pixel in gOut_WorldQueue), which traces
//                it through the bridge from the start and finishes this
//                reservoir: the world rays of a frame are traced together.
// Visibility of screen and bright candidates is not tested here
// (gi.diffuse.resolve does it); ray candidates are visible by construction.
//
// Weights are generalized RIS with pdfs per unit solid angle at the shaded
// point x: a uniformly chosen pixel is a point y on last frame's surfaces
// with area density 1 / (pixels * footprint(y)) (shared/screen_view.glsl),
// which is dA cos(theta_y) / |x - y|^2 in solid angle. Screen and bright
// candidates sample the same points, so they share the balance heuristic:
// a pixel on the list of K bright pixels is pixels / K times likelier to be
// one bright candidate than one screen candidate, and a pixel off the list
// cannot be a bright candidate at all. Which pixels are listed is known
// exactly: entry (i, j) of the last level holds the brightest pixel of the
// tile (i, j) * 2^z. Environment candidates sample
// directions to the sky, a domain of their own. Ray candidates sample
// directions (pdf cos / pi); a point on last frame's screen can come from
// either kind, so the screen techniques count rays and rays count the
// screen techniques where they hit such a point. Each candidate's weight is
// p-hat / (sum over techniques of count * pdf); the reservoir's W is then
// weightSum / p-hat(chosen), with M = 1.
// The pass whose counters its world rays add to (gi/world_ray_count.glsl).
#define WORLD_RAY_PASS kWorldRayPassGather
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "gi/diffuse/diffuse_common.glsl"
#include "shared/equirect.glsl"
#include "shared/reservoir.glsl"
#include "shared/sampling.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4, rgba16f) readonly uniform image2D gPrev_Composite;
layout(set = 0, binding = 5, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 6, rgba32f) readonly uniform image2D gIn_Brightest;
layout(set = 0, binding = 7) uniform sampler2D gIn_Environment;
layout(set = 0, binding = 8, rgba32ui) writeonly uniform uimage2D gOut_Reservoir0;
layout(set = 0, binding = 9, rgba32ui) writeonly uniform uimage2D gOut_Reservoir1;
layout(set = 0, binding = 10, r32f) readonly uniform image2D gIn_MarchDepth;

#include "gi/screen_trace.glsl"
#include "gi/diffuse/previous_screen.glsl"
#define CACHE_FIRST_BINDING 24
#include "gi/cache/radiance_cache.glsl"
#include "gi/scene_bridge.glsl"
#include "gi/world_rays.glsl"

// Where the rays the depth-buffer march cannot decide wait for
// gi.diffuse.world_candidates: per reservoir and ray candidate, the ray's
// direction (w = 1; w = 0: no ray waits), and the pixels that have one.
#define WORLD_QUEUE_BINDING 11
layout(set = 0, binding = WORLD_QUEUE_BINDING, std430) writeonly buffer PendingRays { vec4 items[]; } gOut_PendingRays;
layout(set = 0, binding = WORLD_QUEUE_BINDING + 1, std430) buffer WorldQueue { uint items[]; } gOut_WorldQueue;
#include "gi/diffuse/gather_common.glsl"

#define WORLD_QUEUE_APPEND
#include "gi/world_queue.glsl"
#define SCREEN_TILES_BINDING 13
#include "gi/screen_only_policy.glsl"

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideHalf(halfPixel)) return;
  ivec2 pixel = reservoirSurfacePixel(halfPixel);
  Reservoir r = emptyReservoir();
  Surface x = gbufferSurface(pixel);
  if (x.viewZ <= 0.0f) {
    uvec4 first, second;
    packReservoir(r, first, second);
    imageStore(gOut_Reservoir0, halfPixel, first);
    imageStore(gOut_Reservoir1, halfPixel, second);
    return;
  }
  uint rng = giSeed(uvec2(halfPixel), kSaltGather);
  DiffuseConstants d = gIn_DiffuseConstants.diffuse;
  uint target = d.targetFunction;
  float environmentCount = float(d.environmentCandidates);
  ivec2 brightSize = ivec2(d.brightLevelSize);
  // Points closer than this are the shaded surface itself (or a pixel away).
  float minimumDistance = 1e-3f * x.viewZ;
  float nearField = nearFieldDistance(x);

  for (uint i = 0u; i < d.screenCandidates + d.brightCandidates; ++i) {
    bool bright = i >= d.screenCandidates;
    ivec2 source;
    float ux = rngUniform(rng);
    float uy = rngUniform(rng);
    float choice = rngUniform(rng);
    if (bright) {
      vec4 entry = imageLoad(gIn_Brightest, min(ivec2(vec2(ux, uy) * vec2(brightSize)), brightSize - 1));
      if (entry.w <= 0.0f) continue;
      source = ivec2(entry.yz);
    } else {
      source = min(ivec2(vec2(ux, uy) * fullSize()), ivec2(fullSize()) - 1);
    }
    ScreenPoint point = screenPoint(source);
    if (!point.valid || distance(point.position, x.position) < minimumDistance) continue;
    Reservoir candidate = emptyReservoir();
    candidate.position = point.position;
    candidate.normal = point.normal;
    candidate.radiance = point.radiance;
    float pHat = targetPdf(candidate, x.position, x.normal, target);
    float screenPdf = toSolidAngle(point.areaPdf, point.position, point.normal, x.position, nearField);
    if (pHat <= 0.0f || screenPdf <= 0.0f) continue;
    // Balance heuristic between the point techniques and the rays.
    float techniques = pointTechniques(screenPdf, bright || listedBright(source)) +
                       rayTechnique(x.normal, normalize(point.position - x.position));
    reservoirStream(r, point.position, point.normal, point.radiance, 0u, pHat / techniques, 0.0f, choice);
  }

  bool waiting = false;  // a ray candidate waits for the world trace
  if (kSceneBridgeTraces) {
    vec3 t, b;
    buildOrthonormalBasis(x.normal, t, b);
    vec3 origin = rayOrigin(x.position, x.normal, x.viewZ);
    for (uint i = 0u; i < d.rayCandidates; ++i) {
      uint slot = halfPixelSlot(halfPixel, d.rayCandidates, i);
      gOut_PendingRays.items[slot] = vec4(0.0f);
      vec3 local = sampleCosineHemisphere(vec2(rngUniform(rng), rngUniform(rng)));
      float choice = rngUniform(rng);
      float jitter = rngUniform(rng);
      vec3 direction = normalize(t * local.x + b * local.y + x.normal * local.z);
      float pdf = rayTechnique(x.normal, direction);
      if (pdf <= 0.0f) continue;
      // Screen space first: a surface it hits that last frame showed is read from there.
      ScreenRay screen = screenRay(origin, direction, x.viewZ, d.rayScreenSteps, jitter, d.visibilityThickness);
      ivec2 shown = ivec2(-1);
      if (screen.hit) {
        Surface y = gbufferSurface(screen.texel);
        if (y.viewZ > 0.0f) shown = previousPixelOf(y.position, y.normal);
      }
      if (shown.x < 0) {
        // Through the scene from the start, in gi.diffuse.world_candidates.
        gOut_PendingRays.items[slot] = vec4(direction, 1.0f);
        waiting = true;
        continue;
      }
      streamRayCandidate(r, x, pdf, shown, vec3(0.0f), vec3(0.0f), vec3(0.0f), 0u, nearField, choice);
    }
  }

  vec3 tangent, bitangent;
  buildOrthonormalBasis(x.normal, tangent, bitangent);
  for (uint i = 0u; i < d.environmentCandidates; ++i) {
    float ux = rngUniform(rng);
    float uy = rngUniform(rng);
    float choice = rngUniform(rng);
    float jitter = rngUniform(rng);
    vec3 local = sampleUniformHemisphere(vec2(ux, uy));
    vec3 direction = tangent * local.x + bitangent * local.y + x.normal * local.z;
    ivec2 exit;
    bool towardsCamera;
    float seen = d.visibilitySteps > 0u ? environmentVisibilityExit(x.position, direction, x.viewZ, d.visibilitySteps,
                                                                    jitter, kSolidSurfaces, false, exit, towardsCamera)
                                        : kVisible;
    if (seen == kOccluded) continue;
    vec3 environment = sanitizeRadiance(textureLod(gIn_Environment, equirectUv(direction), d.environmentMip).xyz);
    vec3 radiance = seen == kVisible ? environment : beyondTheScreen(exit, environment, towardsCamera);
    float pHat = targetBrightness(radiance, target) * local.z;
    if (pHat <= 0.0f) continue;
    reservoirStream(r, direction, x.normal, radiance, kReservoirEnvironment, pHat / (environmentCount * pdfUniformHemisphere()),
                    0.0f, choice);
  }

  if (waiting) {
    // Unfinished: gi.diffuse.world_candidates streams the rest in and
    // finalizes it. Until then W holds the weight sum (which a reservoir
    // does not store).
    r.W = r.weightSum;
    r.M = 1.0f;
    uvec4 first, second;
    packReservoir(r, first, second);
    imageStore(gOut_Reservoir0, halfPixel, first);
    imageStore(gOut_Reservoir1, halfPixel, second);
    enqueuePixel(halfPixel);
    return;
  }
  reservoirFinalize(r, targetPdf(r, x.position, x.normal, target), 1.0f);
  // One frame's worth of candidates, even when none of them lit x: that
  // too is evidence later merges must weigh.
  r.M = 1.0f;
  uvec4 first, second;
  packReservoir(r, first, second);
  imageStore(gOut_Reservoir0, halfPixel, first);
  imageStore(gOut_Reservoir1, halfPixel, second);
}
