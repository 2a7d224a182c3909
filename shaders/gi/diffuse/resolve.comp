#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.resolve: indirect diffuse at full resolution. Each pixel
// evaluates the samples of up to four neighbouring half-resolution
// reservoirs at its own surface: radiance * cos / pi * W, times the
// reconnection Jacobian from the reservoir's surface to this one, times the
// sample's visibility (the deferred visibility test of the Jitter gi pass) as
// gi.diffuse.visibility says: a short screen-space march (screen), an
// any-hit ray through the scene bridge (world), or the march, trusting
// gi.diffuse.sample_visibility's ray from the reservoir's own surface where
// the march cannot decide (hybrid); and averages them. Reservoirs of another
// surface (depth or normal too different) are left out. Demodulated: the
// result is what a white Lambert surface would reflect.
// The pass whose counters its world rays add to (gi/world_ray_count.glsl).
#define WORLD_RAY_PASS kWorldRayPassResolve
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "gi/diffuse/diffuse_common.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 5, rgba32ui) readonly uniform uimage2D gIn_Reservoir1;
layout(set = 0, binding = 6, r32f) readonly uniform image2D gIn_MarchDepth;
layout(set = 0, binding = 7, rgba16f) writeonly uniform image2D gOut_Diffuse;

#include "gi/screen_trace.glsl"
#include "gi/scene_bridge.glsl"
#include "gi/world_rays.glsl"

// The reservoirs a pixel evaluates: where their surfaces are.
struct Owner {
  ivec2 halfPixel;
  vec3 position;
  vec3 normal;
  bool exact;  // the owner is this pixel itself (no Jacobian)
};

// Whether `owner`'s reservoir could have handed sample r to x (its own
// reservoir could hand over anything it holds).
bool covers(Owner owner, Reservoir r, Surface x) {
  DiffuseConstants d = gIn_DiffuseConstants.diffuse;
  return canHandOver(r, owner.position, owner.normal, x.position, kMaxResolveJacobian, d.jacobian != 0u && !owner.exact,
                     d.targetFunction);
}

// One reservoir's sample evaluated at x: radiance * cos / pi * W * Jacobian * visibility.
vec3 evaluate(Surface x, Owner owner, Reservoir r, float jitter) {
  vec3 direction = sampleDirection(r, x.position);
  float cosine = dot(x.normal, direction);
  if (cosine <= 0.0f || targetPdf(r, x.position, x.normal, 0u) <= 0.0f) return vec3(0.0f);
  DiffuseConstants d = gIn_DiffuseConstants.diffuse;
  // Per reservoir (gi.diffuse.per_pixel_visibility off), the march or the
  // world ray from the reservoir's surface dropped the hidden samples.
  uint steps = d.perPixelVisibility != 0u ? d.visibilitySteps : 0u;
  bool world = kSceneBridgeTraces && d.visibilityMode == kVisibilityWorld;
  // Hybrid: what the march cannot decide was settled by the reservoir's
  // own world ray (gi.diffuse.sample_visibility), a pixel or two away.
  bool hybrid = kSceneBridgeTraces && d.visibilityMode == kVisibilityHybrid;
  float scale = 1.0f;
  if (reservoirIsEnvironment(r)) {
    // Screen space cannot prove the sky open (a sky pixel shows only that
    // the camera's ray there is free): with a bridge it only finds what blocks.
    // Where the march cannot decide, the sample's radiance already says
    // what is there: a world ray's (hybrid) or screen-only mode's policy
    // (gi/screen_only_policy.glsl, applied by the gather).
    if (world) {
      scale = worldSeesSample(r, x, kWorldRaysResolveVisibility) ? 1.0f : 0.0f;
    } else if (steps > 0u) {
      float screen = environmentVisibility(x.position, direction, x.viewZ, steps, jitter, d.visibilityThickness, false);
      scale = screen == kOccluded ? 0.0f : 1.0f;
    }
  } else {
    scale = reuseJacobian(r, owner.position, x.position, kMaxResolveJacobian, d.jacobian != 0u && !owner.exact);
    if (scale <= 0.0f) return vec3(0.0f);
    float visible = world ? (worldSeesSample(r, x, kWorldRaysResolveVisibility) ? kVisible : kOccluded)
                    : steps > 0u ? screenVisibility(x.position, r.position, steps, jitter, d.visibilityThickness, hybrid)
                                 : kVisible;
    // Screen-only: a sample beyond the screen's edge cannot be tested, and
    // counts as visible; hybrid: its reservoir's world ray found it visible.
    if (visible == kOccluded) return vec3(0.0f);
  }
  return r.radiance * (cosine * kInvPi * r.W * scale);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  Surface x = gbufferSurface(pixel);
  if (x.viewZ <= 0.0f) {
    imageStore(gOut_Diffuse, pixel, vec4(0.0f));
    return;
  }
  uint rng = giSeed(uvec2(pixel), kSaltResolve);
  ivec2 base = pixel / 2;
  // Nearest first: the reservoir of this pixel's own 2x2 block, then its neighbours towards this pixel.
  ivec2 away = ivec2((pixel.x & 1) == 1 ? 1 : -1, (pixel.y & 1) == 1 ? 1 : -1);
  ivec2 offsets[4] = ivec2[4](ivec2(0), ivec2(away.x, 0), ivec2(0, away.y), away);
  // The surfaces of the reservoirs to evaluate; each reservoir itself is
  // loaded only when its turn comes, so four of them never need registers at once.
  Owner owners[4];
  uint count = 0u;
  for (uint k = 0u; k < gIn_DiffuseConstants.diffuse.resolveReservoirs; ++k) {
    ivec2 halfPixel = base + offsets[k];
    if (!insideHalf(halfPixel)) continue;
    ivec2 ownerPixel = reservoirSurfacePixel(halfPixel);
    Surface owner = gbufferSurface(ownerPixel);
    if (!similarSurface(x.viewZ, x.normal, owner.viewZ, owner.normal, 0.1f, 0.8f)) continue;
    owners[count] = Owner(halfPixel, owner.position, owner.normal, ownerPixel == pixel);
    ++count;
  }
  // A thin feature no reservoir shares: borrow the nearest reservoir's
  // sample as if it were this surface's own.
  if (count == 0u) {
    owners[0] = Owner(base, x.position, x.normal, true);
    count = 1u;
  }
  // Each reservoir's estimate weighted by 1 / (how many of the reservoirs
  // could have handed over its sample): a uniform MIS over the reservoirs
  // that cover it, so samples only some neighbours can reach (creases,
  // corners) keep their full weight and none is counted twice.
  vec3 sum = vec3(0.0f);
  for (uint i = 0u; i < count; ++i) {
    float jitter = rngUniform(rng);
    Reservoir r = unpackReservoir(imageLoad(gIn_Reservoir0, owners[i].halfPixel),
                                  imageLoad(gIn_Reservoir1, owners[i].halfPixel));
    if (!reservoirHasSample(r)) continue;
    float coverage = 0.0f;
    for (uint j = 0u; j < count; ++j) coverage += covers(owners[j], r, x) ? 1.0f : 0.0f;
    if (coverage > 0.0f) sum += evaluate(x, owners[i], r, jitter) / coverage;
  }
  imageStore(gOut_Diffuse, pixel, vec4(sanitizeRadiance(sum), 1.0f));
}
