// What every pass of the specular branch shares: its constants (binding 3,
// gIn_SpecularConstants), filled from gi::SpecularSettings by
// src/gi/specular/specular_branch.cpp and laid out identically in GLSL
// (std140) and C++ (checked against each pass's SPIR-V); and the glossy
// surface of a pixel (the G-buffer plus gIn_BaseColorMetallic, which the
// including shader declares when it defines SPECULAR_READS_MATERIAL). The
// including shader includes gi/gi_common.glsl and gi/gbuffer.glsl first;
// its own resources start at binding 4.
#ifndef BOUNCE_GI_SPECULAR_COMMON_GLSL
#define BOUNCE_GI_SPECULAR_COMMON_GLSL

#ifdef __cplusplus
#include "shared/lang.glsl"
namespace bounce::shared {
#endif

struct SpecularConstants {
  uint sampling;                // gi::SpecularSampling (kSpecularSampling*)
  float lobeFraction;           // uniform sampling's cone
  float reuseMinRoughness;      // below: no temporal or spatial reuse
  uint traceSteps;              // screen-space march iterations
  float traceThickness;         // fraction of viewZ
  float temporalMaxM;
  float temporalDepthTolerance;      // fraction of viewZ
  float temporalCosNormalTolerance;  // cos of the angle
  uint spatialSamples;
  float spatialMaxRadius;  // half-resolution pixels
  float spatialCosNormalTolerance;
  float spatialPlaneTolerance;  // fraction of viewZ
  uint jacobian;
  uint resolveMaxSamples;
  float resolveFullRoughness;
  float resolveMaxRadius;  // full-resolution pixels
  uint reprojection;       // gi::SpecularReprojection
  float varianceClippingGamma;
  float temporalFilterFrames;
  float environmentLevels;  // mip levels of the prefiltered environment
  uint hasPreviousFrame;    // 1: last frame's composite holds a frame to read hits from
  float diffuseSampleRoughness;  // at and above: the diffuse branch's sample, no ray (above 1: none)
  float cachedDirectRoughness;   // at and above: world hits take the cache's direct light (above 1: none)
};

#ifdef __cplusplus
}  // namespace bounce::shared
#else
// gi::SpecularReprojection
const uint kReprojectionSurface = 0u;
const uint kReprojectionVirtual = 1u;
const uint kReprojectionDual = 2u;

layout(set = 0, binding = 3, std140) CONSTANT_BLOCK SpecularBlock { SpecularConstants specular; } gIn_SpecularConstants;

#ifdef SPECULAR_READS_MATERIAL
#include "shared/specular_target.glsl"

// The glossy surface of a pixel whose surface and roughness
// gbufferSurfaceRoughness() read: adds its material.
GlossySurface pixelGlossySurface(Surface x, float roughness, ivec2 pixel) {
  vec4 baseColorMetallic = texelFetch(gIn_BaseColorMetallic, pixel, 0);
  vec3 view = normalize(viewPosition(gIn_Frame.frame.view) - x.position);
  return glossySurface(x.position, x.normal, view, clamp(vec3(baseColorMetallic), vec3(0.0f), vec3(1.0f)),
                       clamp(baseColorMetallic.w, 0.0f, 1.0f), roughness);
}

// Whether reservoirs of this surface are reused at all.
bool specularReuses(GlossySurface s) { return s.roughness >= gIn_SpecularConstants.specular.reuseMinRoughness; }
#endif
#endif

#endif
