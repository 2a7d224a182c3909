#version 460
#extension GL_GOOGLE_include_directive : require
// render.reference_path: the ground truth every GI stage is judged against.
// Unidirectional path tracing from the G-buffer's primary hits, split the way
// the GI passes split light (docs/reference.md):
//   indirect diffuse   a path leaving the primary hit by cosine sampling,
//                      demodulated (the Lambert lobe with albedo 1);
//   indirect specular  a path leaving it by GGX VNDF sampling of the specular
//                      lobe (F G2 / G1 per sample), divided by
//                      specularReflectance() in render.reference_resolve.
// Direct light at the primary hit (sun and punctual lights, emission) is
// render.direct_light's, which is exact, so it is not traced here.
//
// Every vertex, the primary one included, samples the environment and the
// emissive triangles as lights, combined with BSDF sampling by the power
// heuristic; the sun and punctual lights are deltas, sampled at every vertex
// after the primary one (directLighting()). Russian roulette ends long paths.
// Each dispatch adds sampleCount samples per pixel: even-numbered samples to
// the sums of half A, odd ones to half B, two independent estimates whose
// difference measures how converged their mean is. Each path's first hit
// distance is summed too (both halves together): the resolve hands it on in
// alpha, what a denoiser takes with a noisy signal (bounce denoise).
#include "render/scene_access.glsl"
#include "shared/environment.glsl"
#define DIRECT_LIGHTS_BINDING 20
#include "render/direct_lighting.glsl"
#define LIGHT_SAMPLING_FIRST_BINDING 22
#include "render/light_sampling.glsl"
#include "render/reference_types.glsl"
#include "shared/finite.glsl"
#include "shared/rng.glsl"
#include "shared/sampling.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 16, r32f) readonly uniform image2D gIn_ViewZ;
layout(set = 0, binding = 17, rgba16f) readonly uniform image2D gIn_NormalRoughness;
layout(set = 0, binding = 18, rgba16f) readonly uniform image2D gIn_GeometricNormal;
layout(set = 0, binding = 19, rgba8) readonly uniform image2D gIn_BaseColorMetallic;
layout(set = 0, binding = 21) uniform sampler2D gIn_Environment;
// Running sums per half: rgb = summed radiance, a = samples dropped as non-finite.
layout(set = 0, binding = 24, rgba32f) uniform image2D gHistory_DiffuseSumA;
layout(set = 0, binding = 25, rgba32f) uniform image2D gHistory_SpecularSumA;
layout(set = 0, binding = 26, rgba32f) uniform image2D gHistory_DiffuseSumB;
layout(set = 0, binding = 27, rgba32f) uniform image2D gHistory_SpecularSumB;
// Summed first-hit distances: diffuse sum, diffuse paths, specular sum, specular paths.
layout(set = 0, binding = 28, rgba32f) uniform image2D gHistory_HitDistanceSum;

layout(push_constant) uniform Params { ReferencePathParams params; };

// Where a path is: a surface and the material there.
struct PathVertex {
  vec3 position;
  vec3 normal;           // shading normal, facing the incoming ray
  vec3 geometricNormal;  // facing the incoming ray
  vec3 baseColor;
  float metallic;
  float roughness;
  float offsetScale;     // how far rays leave the surface (grows with distance from the camera)
};

LightSampling lightSampling() {
  return LightSampling(params.environmentWidth, params.environmentHeight, params.emissiveCount, params.emissivePower);
}

vec3 leavingOrigin(PathVertex x) { return offsetOrigin(x.position, x.geometricNormal, x.offsetScale); }

// f cos(theta_l) of the chosen lobes, and the pdf with which sampleLobes
// draws l. kLobesAll is the whole material (sampling.glsl's one-sample MIS).
vec3 lobesBrdfCosine(uint lobes, PathVertex x, vec3 v, vec3 l, out float pdf) {
  if (lobes == kLobesAll) {
    pdf = pdfMaterial(x.normal, v, l, x.baseColor, x.metallic, x.roughness);
    return materialBrdfCosine(x.normal, v, l, x.baseColor, x.metallic, x.roughness);
  }
  pdf = 0.0f;
  float nDotL = dot(x.normal, l);
  float nDotV = dot(x.normal, v);
  if (nDotL <= 0.0f || nDotV < kMinViewCosine) return vec3(0.0f);
  if (lobes == kLobeDiffuse) {
    pdf = pdfCosineHemisphere(nDotL);
    return x.baseColor * ((1.0f - x.metallic) * kInvPi * nDotL);
  }
  vec3 t, b;
  buildOrthonormalBasis(x.normal, t, b);
  float alpha = ggxAlpha(x.roughness);
  pdf = pdfGgxReflection(vec3(dot(v, t), dot(v, b), nDotV), vec3(dot(l, t), dot(l, b), nDotL), alpha);
  return ggxSpecularCosine(x.normal, v, l, specularF0(x.baseColor, x.metallic), alpha);
}

// Draws a direction from the chosen lobes; the pdf is lobesBrdfCosine's.
bool sampleLobes(uint lobes, PathVertex x, vec3 v, vec3 u, out vec3 direction, out vec3 brdfCosine, out float pdf) {
  brdfCosine = vec3(0.0f);
  pdf = 0.0f;
  if (lobes == kLobesAll) {
    if (!sampleMaterial(x.normal, v, x.baseColor, x.metallic, x.roughness, u, direction, pdf)) return false;
    brdfCosine = materialBrdfCosine(x.normal, v, direction, x.baseColor, x.metallic, x.roughness);
    return true;
  }
  direction = x.normal;
  float nDotV = dot(x.normal, v);
  if (nDotV < kMinViewCosine) return false;
  vec3 t, b;
  buildOrthonormalBasis(x.normal, t, b);
  vec3 local;
  if (lobes == kLobeDiffuse) {
    local = sampleCosineHemisphere(u.xy);
  } else {
    vec3 viewLocal = vec3(dot(v, t), dot(v, b), nDotV);
    local = reflect(-viewLocal, sampleGgxVisibleNormal(viewLocal, ggxAlpha(x.roughness), u.xy));
  }
  if (local.z <= 0.0f) return false;
  direction = normalize(t * local.x + b * local.y + x.normal * local.z);
  brdfCosine = lobesBrdfCosine(lobes, x, v, direction, pdf);
  return pdf > 0.0f;
}

vec3 environmentLight(vec3 direction) { return environmentRadianceLod(gIn_Environment, direction, 0.0f); }

// Light samples whose direction makes a smaller cosine than this with the
// emitter's or the receiver's surface are dropped (sampledLights).
const float kGrazingLightCosine = 1e-4f;

// Light from the environment and the emissive triangles reflected at x
// towards v, one light sample each, weighted against BSDF sampling.
vec3 sampledLights(uint lobes, PathVertex x, vec3 v, inout uint rng) {
  vec3 radiance = vec3(0.0f);
  LightSampling lights = lightSampling();
  vec3 origin = leavingOrigin(x);
  vec3 direction;
  float lightPdf;
  vec2 u = vec2(rngUniform(rng), rngUniform(rng));
  if (sampleEnvironmentLight(lights, u, direction, lightPdf) && dot(x.geometricNormal, direction) > 0.0f) {
    float brdfPdf;
    vec3 f = lobesBrdfCosine(lobes, x, v, direction, brdfPdf);
    if (any(greaterThan(f, vec3(0.0f))) && !bvhTraceAny(origin, direction, 0.0f, 1e30f))
      radiance += f * environmentLight(direction) * (powerHeuristic(lightPdf, brdfPdf) / lightPdf);
  }
  EmissiveSample light;
  vec3 u3 = vec3(rngUniform(rng), rngUniform(rng), rngUniform(rng));
  if (sampleEmissiveLight(lights, u3, x.position, light)) {
    vec3 toLight = light.position - x.position;
    float distanceSquared = dot(toLight, toLight);
    direction = toLight * inversesqrt(max(distanceSquared, 1e-20f));
    float lightCosine = abs(dot(light.geometricNormal, direction));
    // A light point seen at a grazing angle (both cosines below
    // kGrazingLightCosine) brings almost nothing, and which side of the
    // emitter or of the receiver it is on is decided by rounding: a point
    // on or beside the receiver's own triangle of a closed single-sided
    // shell was taken as its lit front side, and a furnace that must stay
    // black saw light (ReferenceTest.SingleSidedEmittersLightOnlyTheirFrontSide).
    if (lightCosine > kGrazingLightCosine && distanceSquared > 0.0f &&
        dot(x.geometricNormal, direction) > kGrazingLightCosine) {
      lightPdf = light.pdfArea * distanceSquared / lightCosine;
      float brdfPdf;
      vec3 f = lobesBrdfCosine(lobes, x, v, direction, brdfPdf);
      float shadowLength = length(light.position - origin) * 0.999f;
      if (any(greaterThan(f, vec3(0.0f))) && !bvhTraceAny(origin, direction, 0.0f, shadowLength))
        radiance += f * light.emission * (powerHeuristic(lightPdf, brdfPdf) / lightPdf);
    }
  }
  return radiance;
}

// Radiance reflected at the primary vertex x0 towards v0 through `firstLobes`
// (its own light samples included), following one path. Later vertices use
// params.lobes of their own materials. `firstHitDistance`: how far the
// path's first ray went (kEscapedHitDistance to the sky), 0 when the lobe
// gave no ray.
vec3 tracePath(uint firstLobes, PathVertex x0, vec3 v0, inout uint rng, out float firstHitDistance) {
  firstHitDistance = 0.0f;
  vec3 radiance = sampledLights(firstLobes, x0, v0, rng);
  vec3 direction, brdfCosine;
  float pdf;
  vec3 u = vec3(rngUniform(rng), rngUniform(rng), rngUniform(rng));
  if (!sampleLobes(firstLobes, x0, v0, u, direction, brdfCosine, pdf)) return radiance;
  if (dot(x0.geometricNormal, direction) <= 0.0f) return radiance;  // under the true surface: a light leak
  vec3 throughput = brdfCosine / pdf;
  vec3 origin = leavingOrigin(x0);
  float travelled = x0.offsetScale;
  LightSampling lights = lightSampling();

  for (uint bounce = 1u; bounce <= params.maxBounces + 1u; ++bounce) {
    BvhHit hit = bvhTraceClosest(origin, direction, 0.0f, 1e30f);
    if (bounce == 1u) firstHitDistance = hit.t < kEscapedHitDistance ? hit.t : kEscapedHitDistance;
    if (!(hit.t < 1e30f)) {
      radiance += throughput * environmentLight(direction) *
                  powerHeuristic(pdf, environmentLightPdf(lights, direction));
      break;
    }
    SceneSurface surface = resolveSurface(hit, direction, 1e-6f);
    if (any(greaterThan(surface.emissive, vec3(0.0f)))) {
      float lightCosine = abs(dot(surface.geometricNormal, direction));
      float lightPdf = emissiveLightPdfArea(lights, surface.material) * hit.t * hit.t / max(lightCosine, 1e-8f);
      radiance += throughput * surface.emissive * powerHeuristic(pdf, lightPdf);
    }
    // The last bounce only closes the MIS of the previous vertex's light samples.
    if (bounce > params.maxBounces) break;

    travelled += hit.t;
    PathVertex x = PathVertex(surface.position, surface.normal, surface.geometricNormal, surface.baseColor,
                              surface.metallic, surface.roughness, travelled);
    vec3 v = -direction;
    radiance += throughput * (directLighting(x.position, leavingOrigin(x), x.normal, x.geometricNormal, v, x.baseColor,
                                             x.metallic, x.roughness) +
                              sampledLights(params.lobes, x, v, rng));

    u = vec3(rngUniform(rng), rngUniform(rng), rngUniform(rng));
    if (!sampleLobes(params.lobes, x, v, u, direction, brdfCosine, pdf)) break;
    if (dot(x.geometricNormal, direction) <= 0.0f) break;
    throughput *= brdfCosine / pdf;
    origin = leavingOrigin(x);
    if (bounce >= params.rouletteBounces) {
      float survival = min(max(throughput.x, max(throughput.y, throughput.z)), 0.95f);
      if (rngUniform(rng) >= survival) break;
      throughput /= survival;
    }
  }
  return radiance;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  vec2 size = gIn_Frame.frame.imageSize.xy;
  if (pixel.x >= int(size.x) || pixel.y >= int(size.y)) return;
  float viewZ = imageLoad(gIn_ViewZ, pixel).x;
  if (viewZ <= 0.0f) return;  // background: no surface, nothing indirect

  vec3 direction = cameraRayDirection(gIn_Frame.frame.camera, vec2(pixel) + 0.5f + gIn_Frame.frame.jitter.xy, size);
  vec3 v0 = -direction;
  vec4 normalRoughness = imageLoad(gIn_NormalRoughness, pixel);
  vec4 baseColorMetallic = imageLoad(gIn_BaseColorMetallic, pixel);
  PathVertex x0;
  x0.position = gIn_Frame.frame.camera.position.xyz + direction * (viewZ / dot(direction, gIn_Frame.frame.camera.forward.xyz));
  x0.normal = normalize(normalRoughness.xyz);  // rgba16f: renormalise, or GGX peaks at alpha 0.0025 miss
  x0.geometricNormal = normalize(imageLoad(gIn_GeometricNormal, pixel).xyz);
  x0.baseColor = baseColorMetallic.xyz;
  x0.metallic = baseColorMetallic.w;
  x0.roughness = normalRoughness.w;
  x0.offsetScale = viewZ;
  // Diffuse is demodulated: the Lambert lobe of a white dielectric.
  PathVertex x0Diffuse = x0;
  x0Diffuse.baseColor = vec3(1.0f);
  x0Diffuse.metallic = 0.0f;

  vec4 diffuseSum[2] = vec4[2](imageLoad(gHistory_DiffuseSumA, pixel), imageLoad(gHistory_DiffuseSumB, pixel));
  vec4 specularSum[2] = vec4[2](imageLoad(gHistory_SpecularSumA, pixel), imageLoad(gHistory_SpecularSumB, pixel));
  vec4 hitDistanceSum = imageLoad(gHistory_HitDistanceSum, pixel);
  for (uint s = 0u; s < params.sampleCount; ++s) {
    uint sampleIndex = params.sampleBase + params.firstSample + s;
    uint halfIndex = (params.firstSample + s) & 1u;
    uint rng = rngSeed(uvec2(pixel), sampleIndex, params.seed);
    float diffuseDistance = 0.0f, specularDistance = 0.0f;
    vec3 diffuse = (params.lobes & kLobeDiffuse) != 0u ? tracePath(kLobeDiffuse, x0Diffuse, v0, rng, diffuseDistance)
                                                       : vec3(0.0f);
    vec3 specular = (params.lobes & kLobeSpecular) != 0u ? tracePath(kLobeSpecular, x0, v0, rng, specularDistance)
                                                         : vec3(0.0f);
    // A non-finite sample would poison the whole sum; drop it and count it.
    if (isFinite(diffuse)) diffuseSum[halfIndex].xyz += diffuse;
    else diffuseSum[halfIndex].w += 1.0f;
    if (isFinite(specular)) specularSum[halfIndex].xyz += specular;
    else specularSum[halfIndex].w += 1.0f;
    // Paths whose lobe gave no ray know no distance and are left out.
    if (diffuseDistance > 0.0f) hitDistanceSum.xy += vec2(diffuseDistance, 1.0f);
    if (specularDistance > 0.0f) hitDistanceSum.zw += vec2(specularDistance, 1.0f);
  }
  imageStore(gHistory_DiffuseSumA, pixel, diffuseSum[0]);
  imageStore(gHistory_SpecularSumA, pixel, specularSum[0]);
  imageStore(gHistory_DiffuseSumB, pixel, diffuseSum[1]);
  imageStore(gHistory_SpecularSumB, pixel, specularSum[1]);
  imageStore(gHistory_HitDistanceSum, pixel, hitDistanceSum);
}
