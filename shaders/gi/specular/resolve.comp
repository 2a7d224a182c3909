#version 460
#extension GL_GOOGLE_include_directive : require
// gi.specular.resolve: indirect specular at full resolution (the Jitter gi pass's specular ReSTIR,
// "ReSTIR resolve"). A pixel evaluates a roughness-dependent number of
// reservoirs (shared/specular_target.glsl, resolveSampleCount: one for a
// mirror, up to gi.specular.resolve_max_samples for rough surfaces): its own
// 2x2 block's, then neighbours taken in a disk of its tangent plane as wide
// as the lobe's footprint (at most gi.specular.resolve_max_radius pixels).
//   - Surfaces smoother than gi.specular.reuse_min_roughness take their
//     block's reservoir as that reservoir's own pixel estimated it
//     (F G2 / G1 L, demodulated there): a near-mirror's lobe holds no other
//     pixel's sample, so re-evaluating one here would be noise.
//   - VNDF sampling: each reservoir's sample is evaluated at this pixel, f
//     cos L W times the reconnection Jacobian, weighted by 1 / (how many of
//     the reservoirs could have produced it), as the diffuse resolve does.
//   - Uniform sampling: the reservoirs (view-independent targets) are
//     resampled into one disposable reservoir with this pixel's real BRDF
//     target p-hat' = luminance(f cos L) (Zyanide's uniform-lobe reservoirs), which shades it.
// No occlusion test (the Jitter gi pass's specular ReSTIR). The output is demodulated, divided by the
// specular reflectance specularReflectance() gives (the composite
// multiplies it back, the reference divides by the same function); alpha is
// the hit distance (the contributions' luminance-weighted mean), which the
// temporal filter's virtual motion needs.
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"

layout(set = 0, binding = 4) uniform sampler2D gIn_BaseColorMetallic;
#define SPECULAR_READS_MATERIAL
#include "gi/specular/specular_common.glsl"
#include "shared/reservoir.glsl"
#include "shared/sampling.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 5, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 6, rgba32ui) readonly uniform uimage2D gIn_Reservoir1;
layout(set = 0, binding = 7, rgba16f) writeonly uniform image2D gOut_Specular;

const uint kSaltSpecularResolve = 0x7374u + 3u;
const uint kMaxOwners = 16u;  // gi.specular.resolve_max_samples' largest value
// The hit distance written for the environment (a half float holds it).
const float kEnvironmentHitDistance = 1.0e4f;

float hitDistanceOf(Reservoir r, vec3 from) {
  return reservoirIsEnvironment(r) ? kEnvironmentHitDistance : min(distance(r.position, from), kEnvironmentHitDistance);
}

// A reservoir the resolve evaluates, and what its coverage count needs of
// the surface it belongs to (kept small: every pixel holds up to
// kMaxOwners of them).
struct Owner {
  ivec2 halfPixel;
  vec3 position;
  vec3 normal;
  float roughness;
};

Owner ownerOf(ivec2 halfPixel, vec3 position, vec3 normal, float roughness) {
  Owner o;
  o.halfPixel = halfPixel;
  o.position = position;
  o.normal = normal;
  o.roughness = roughness;
  return o;
}

// The owner's surface as specularTargetCovers() needs it (geometry and
// lobe; F0 plays no part there). The view is recomputed for every pair:
// kept in Owner it made the resolve 3-5 % slower with 4 reservoirs and 25 %
// with 8 on the H100 (the owners live in local memory; more bytes there
// cost more than a normalize).
GlossySurface coverageSurface(Owner o) {
  vec3 view = normalize(viewPosition(gIn_Frame.frame.view) - o.position);
  return glossySurface(o.position, o.normal, view, vec3(1.0f), 1.0f, o.roughness);
}

// The reconnection Jacobian from the owner's surface to this pixel's (1 for
// the pixel's own sample), 0 where it is rejected.
float reuseScale(Reservoir r, Owner o, ivec2 pixel, vec3 position, bool jacobian) {
  if (reservoirSurfacePixel(o.halfPixel) == pixel) return 1.0f;
  return reuseJacobian(r, o.position, position, kMaxResolveJacobian, jacobian);
}

Reservoir loadReservoir(ivec2 halfPixel) {
  return unpackReservoir(imageLoad(gIn_Reservoir0, halfPixel), imageLoad(gIn_Reservoir1, halfPixel));
}

// The block reservoir a pixel starts from: its own 2x2 block's if that is
// the same surface, else the nearest neighbouring block's that is; `owner`
// is its surface.
ivec2 ownBlock(ivec2 pixel, Surface x, out GlossySurface owner) {
  ivec2 base = pixel / 2;
  ivec2 away = ivec2((pixel.x & 1) == 1 ? 1 : -1, (pixel.y & 1) == 1 ? 1 : -1);
  ivec2 offsets[4] = ivec2[4](ivec2(0), ivec2(away.x, 0), ivec2(0, away.y), away);
  for (uint k = 0u; k < 4u; ++k) {
    ivec2 halfPixel = base + offsets[k];
    if (!insideHalf(halfPixel)) continue;
    ivec2 ownerPixel = reservoirSurfacePixel(halfPixel);
    float roughness;
    Surface surface = gbufferSurfaceRoughness(ownerPixel, roughness);
    if (!similarSurface(x.viewZ, x.normal, surface.viewZ, surface.normal, 0.1f, 0.8f)) continue;
    owner = pixelGlossySurface(surface, roughness, ownerPixel);
    return halfPixel;
  }
  float roughness;
  Surface surface = gbufferSurfaceRoughness(reservoirSurfacePixel(base), roughness);
  owner = pixelGlossySurface(surface, roughness, reservoirSurfacePixel(base));
  return base;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  float roughness;
  Surface x = gbufferSurfaceRoughness(pixel, roughness);
  if (x.viewZ <= 0.0f) {
    imageStore(gOut_Specular, pixel, vec4(0.0f));
    return;
  }
  SpecularConstants c = gIn_SpecularConstants.specular;
  GlossySurface s = pixelGlossySurface(x, roughness, pixel);
  GlossySurface blockOwner;
  ivec2 block = ownBlock(pixel, x, blockOwner);
  Reservoir own = loadReservoir(block);

  if (!specularReuses(s)) {
    // The block's own estimate, demodulated at its own surface.
    vec3 demodulated = vec3(0.0f);
    float hitDistance = kEnvironmentHitDistance;
    if (reservoirHasSample(own)) {
      demodulated = specularSampleContribution(own, blockOwner) * own.W /
                    specularReflectance(blockOwner.f0, dot(blockOwner.normal, blockOwner.view), blockOwner.roughness);
      hitDistance = hitDistanceOf(own, x.position);
    }
    imageStore(gOut_Specular, pixel, vec4(sanitizeRadiance(demodulated), hitDistance));
    return;
  }

  // The reservoirs to evaluate: the block's, then neighbours in the lobe's footprint.
  uint wanted = min(resolveSampleCount(s.roughness, c.resolveMaxSamples, c.resolveFullRoughness), kMaxOwners);
  Owner owners[kMaxOwners];
  owners[0] = ownerOf(block, blockOwner.position, blockOwner.normal, blockOwner.roughness);
  uint count = 1u;
  if (wanted > 1u) {
    uint rng = giSeed(uvec2(pixel), kSaltSpecularResolve);
    float pixelSize = 2.0f * gIn_Frame.frame.view.projection.y * x.viewZ / fullSize().y;
    float hitDistance = reservoirHasSample(own) ? hitDistanceOf(own, x.position) : kEnvironmentHitDistance;
    float worldRadius = min(specularFootprintRadius(hitDistance, s.alpha), c.resolveMaxRadius * pixelSize);
    vec3 tangent, bitangent;
    buildOrthonormalBasis(x.normal, tangent, bitangent);
    for (uint i = 1u; i < wanted * 2u && count < wanted; ++i) {
      float ux = rngUniform(rng);
      float uy = rngUniform(rng);
      vec2 disk = sampleConcentricDisk(vec2(ux, uy)) * worldRadius;
      vec3 projected = projectToScreen(gIn_Frame.frame.view, x.position + tangent * disk.x + bitangent * disk.y,
                                       fullSize());
      if (projected.z <= 0.0f) continue;
      ivec2 halfPixel = ivec2(floor(projected.xy * 0.5f));
      if (!insideHalf(halfPixel)) continue;
      bool seen = false;
      for (uint k = 0u; k < count; ++k) seen = seen || owners[k].halfPixel == halfPixel;
      if (seen) continue;
      float ownerRoughness;
      Surface owner = gbufferSurfaceRoughness(reservoirSurfacePixel(halfPixel), ownerRoughness);
      if (!similarSurface(x.viewZ, x.normal, owner.viewZ, owner.normal, 0.1f, 0.8f)) continue;
      owners[count] = ownerOf(halfPixel, owner.position, owner.normal, ownerRoughness);
      ++count;
    }
  }

  bool jacobian = c.jacobian != 0u;
  bool disposable = c.sampling == kSpecularSamplingUniform;
  uint rng = giSeed(uvec2(pixel), kSaltSpecularResolve + 1u);
  vec3 sum = vec3(0.0f);
  float distanceSum = 0.0f;
  float distanceWeight = 0.0f;
  Reservoir shading = emptyReservoir();  // uniform sampling's disposable reservoir
  for (uint i = 0u; i < count; ++i) {
    Reservoir r = i == 0u ? own : loadReservoir(owners[i].halfPixel);
    if (!reservoirHasSample(r)) continue;
    float scale = reuseScale(r, owners[i], pixel, x.position, jacobian);
    if (scale <= 0.0f) continue;
    // Uniform MIS over the reservoirs that could have produced this sample.
    float coverage = 0.0f;
    for (uint j = 0u; j < count; ++j)
      if (reuseScale(r, owners[j], pixel, x.position, jacobian) > 0.0f &&
          specularTargetCovers(r, coverageSurface(owners[j]), c.sampling, c.lobeFraction))
        coverage += 1.0f;
    if (coverage <= 0.0f) continue;
    vec3 contribution = specularSampleContribution(r, s);
    float weight = r.W * scale / coverage;
    if (disposable) {
      reservoirStream(shading, r.position, r.normal, r.radiance, r.flags, luminance(contribution) * weight, 1.0f,
                      rngUniform(rng));
    } else {
      sum += contribution * weight;
    }
    float brightness = luminance(contribution) * weight;
    distanceSum += brightness * hitDistanceOf(r, x.position);
    distanceWeight += brightness;
  }
  if (disposable) {
    float target = specularShadingTarget(shading, s);
    reservoirFinalize(shading, target, 1.0f);
    if (reservoirHasSample(shading)) sum = specularSampleContribution(shading, s) * shading.W;
  }
  vec3 demodulated = sum / specularReflectance(s.f0, dot(s.normal, s.view), s.roughness);
  float hitDistance = distanceWeight > 0.0f ? distanceSum / distanceWeight : kEnvironmentHitDistance;
  imageStore(gOut_Specular, pixel, vec4(sanitizeRadiance(demodulated), hitDistance));
}
