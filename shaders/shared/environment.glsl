// Sampling the environment from any pass: the GI library's input and the
// renderer's background (gi::EnvironmentPrefilter makes it, src/gi/environment_prefilter.cpp).
//
// The environment is an equirectangular rgba16f image (shared/equirect.glsl)
// whose mip k holds the radiance prefiltered with the GGX lobe of perceptual
// roughness k / (mipCount - 1), under the split-sum N = V = R assumption:
// mip 0 is the sharp environment. The consumer binds it as a sampler2D with
// EnvironmentPrefilter::sampler() (linear, repeating across the u = 0 seam) and calls
// environmentRadiance(); the mip count comes from the image itself.
//
// The roughness <-> mip mapping compiles as C++ too (lang.glsl), so the host
// that builds the chain and the shaders that read it use the same function.
#ifndef BOUNCE_SHARED_ENVIRONMENT_GLSL
#define BOUNCE_SHARED_ENVIRONMENT_GLSL

#include "shared/equirect.glsl"
#include "shared/lang.glsl"
#include "shared/sky.glsl"

BOUNCE_SHARED_BEGIN

// The perceptual roughness whose GGX lobe mip `level` of a chain of mipCount
// levels is prefiltered with.
float environmentMipRoughness(float level, float mipCount) {
  return mipCount > 1.0f ? clamp(level / (mipCount - 1.0f), 0.0f, 1.0f) : 0.0f;
}

// The (fractional) mip level to read for a perceptual roughness; between two
// levels the sampler blends linearly.
float environmentLod(float perceptualRoughness, float mipCount) {
  return clamp(perceptualRoughness, 0.0f, 1.0f) * max(mipCount - 1.0f, 0.0f);
}

BOUNCE_SHARED_END

#ifndef __cplusplus
// The environment's radiance towards a direction at an explicit mip level.
vec3 environmentRadianceLod(sampler2D environment, vec3 direction, float lod) {
  return textureLod(environment, equirectUv(direction), lod).xyz;
}

// Radiance reflected towards a mirror direction by a GGX lobe of the given
// perceptual roughness (the prefiltered part of the split-sum
// approximation; the consumer multiplies by its own DFG term).
vec3 environmentRadiance(sampler2D environment, vec3 direction, float perceptualRoughness) {
  float mipCount = float(textureQueryLevels(environment));
  return environmentRadianceLod(environment, direction, environmentLod(perceptualRoughness, mipCount));
}

// What a camera ray that leaves the scene sees: the sharp environment. The
// sun's disk is not in it; add sunDiskRadiance() (shared/sky.glsl) to show it.
vec3 environmentBackground(sampler2D environment, vec3 direction) {
  return environmentRadianceLod(environment, direction, 0.0f);
}
#endif

#endif
