#version 460
#extension GL_GOOGLE_include_directive : require
// gi.environment.prefilter: one level of the environment's prefiltered chain.
// Level k holds the radiance reflected by a GGX lobe of perceptual roughness
// environmentMipRoughness(k) under the split-sum assumption N = V = R
// (Karis, "Real Shading in Unreal Engine 4", 2013): the average of the source
// over importance-sampled GGX half-vectors, weighted by cos(theta_l). Each
// sample reads the source's box-filtered chain at the level whose texels
// cover the sample's share of the lobe's solid angle, 1 / (N pdf), so a
// small bright source (the sun in an HDR map) is spread over the lobe rather
// than caught by a few samples as fireflies. Level 0 is the source's top
// level, copied.
//
// The box-filtered chain alternates between two images (src/gi/environment_prefilter.cpp
// says why): chain level 2j is mip 2j of gIn_SourceEven, chain level 2j + 1 is
// mip 2j of gIn_SourceOdd (whose mip 0 is half the size). Both are sampled
// bilinearly with exact integer levels (a nearest-mip sampler), and the
// levels are blended here.
#include "shared/environment.glsl"
#include "shared/brdf.glsl"
#include "shared/finite.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D gIn_SourceEven;
layout(set = 0, binding = 1) uniform sampler2D gIn_SourceOdd;
layout(set = 0, binding = 2, rgba16f) writeonly uniform image2D gOut_Radiance;

layout(push_constant) uniform Params {
  uint level;         // the level of the prefiltered chain being written
  uint mipCount;      // levels in the prefiltered chain
  uint sampleCount;   // GGX samples per texel
  uint sourceLevels;  // levels in the box-filtered chain (both images together)
} params;

// The Hammersley point set: the same well-spread samples for every texel, so
// the result is smooth (any error is a slight bias of the lobe's shape, not noise).
vec2 hammersley(uint index, uint count) {
  return vec2((float(index) + 0.5f) / float(count), float(bitfieldReverse(index)) * 2.3283064365386963e-10f);
}

// An orthonormal basis around n (Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 2017).
void basisAround(vec3 n, out vec3 tangent, out vec3 bitangent) {
  float s = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (s + n.z);
  float b = n.x * n.y * a;
  tangent = vec3(1.0f + s * n.x * n.x * a, s * b, -s * n.x);
  bitangent = vec3(b, s + n.y * n.y * a, -n.y);
}

vec3 sourceLevel(int level, vec2 uv) {
  return (level & 1) == 0 ? textureLod(gIn_SourceEven, uv, float(level)).xyz
                          : textureLod(gIn_SourceOdd, uv, float(level - 1)).xyz;
}

// The box-filtered source at a fractional chain level (trilinear).
vec3 sourceRadiance(vec3 direction, float lod) {
  vec2 uv = equirectUv(direction);
  int lower = int(lod);
  float t = lod - float(lower);
  vec3 value = sourceLevel(lower, uv);
  if (t > 0.0f) value = mix(value, sourceLevel(lower + 1, uv), t);
  return value;
}

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(gOut_Radiance);
  if (texel.x >= size.x || texel.y >= size.y) return;
  if (params.level == 0u) {
    imageStore(gOut_Radiance, texel, vec4(sanitizeRadiance(texelFetch(gIn_SourceEven, texel, 0).xyz), 1.0f));
    return;
  }

  float alpha = ggxAlpha(environmentMipRoughness(float(params.level), float(params.mipCount)));
  vec3 n = equirectDirection((vec2(texel) + 0.5f) / vec2(size));
  vec3 tangent, bitangent;
  basisAround(n, tangent, bitangent);

  ivec2 sourceSize = textureSize(gIn_SourceEven, 0);
  // Texels at the equator are the largest; using their solid angle picks the
  // level whose rows (equally tall everywhere) match the sample's footprint.
  float texelSolidAngle = 2.0f * kPi * kPi / (float(sourceSize.x) * float(sourceSize.y));
  float maxLod = float(params.sourceLevels - 1u);

  vec3 sum = vec3(0.0f);
  float weightSum = 0.0f;
  for (uint i = 0u; i < params.sampleCount; ++i) {
    vec2 xi = hammersley(i, params.sampleCount);
    // GGX half-vector with pdf D(h) cos(theta_h).
    float cosThetaH = sqrt((1.0f - xi.y) / (1.0f + (alpha * alpha - 1.0f) * xi.y));
    float sinThetaH = sqrt(max(1.0f - cosThetaH * cosThetaH, 0.0f));
    float phi = 2.0f * kPi * xi.x;
    vec3 h = tangent * (sinThetaH * cos(phi)) + bitangent * (sinThetaH * sin(phi)) + n * cosThetaH;
    float nDotL = 2.0f * cosThetaH * cosThetaH - 1.0f;
    if (nDotL <= 0.0f) continue;
    vec3 l = 2.0f * cosThetaH * h - n;
    // pdf of l: D(h) cos(theta_h) / (4 v.h), and v.h = cos(theta_h) as v = n.
    float pdf = ggxD(cosThetaH, alpha) * 0.25f;
    float sampleSolidAngle = 1.0f / (float(params.sampleCount) * pdf);
    // +1: one level blurrier than the footprint, which hides the pattern of the shared sample set.
    float lod = clamp(0.5f * log2(sampleSolidAngle / texelSolidAngle) + 1.0f, 0.0f, maxLod);
    sum += sourceRadiance(l, lod) * nDotL;
    weightSum += nDotL;
  }
  imageStore(gOut_Radiance, texel, vec4(sanitizeRadiance(sum / max(weightSum, 1e-20f)), 1.0f));
}
