#version 460
#extension GL_GOOGLE_include_directive : require
// gi.composite: the frame: direct light + base colour * (1 - metallic) *
// indirect diffuse + specular reflectance * indirect specular (both branches
// hand over demodulated light; specularReflectance() is the same function
// the specular resolve divided by) (+ emission when the engine gives it
// apart). The
// engine's images are sampled (any format of their family: sRGB base
// colour reads linear, B10G11R11 direct light too). Background
// pixels keep the direct image's sky. This HDR frame is what the next
// frame's gathering samples, so what it stores is finite: non-finite direct
// light or emission counts as none, and the sum saturates at the largest
// half float.
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "shared/brdf.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4) uniform sampler2D gIn_Direct;
layout(set = 0, binding = 5) uniform sampler2D gIn_BaseColorMetallic;
layout(set = 0, binding = 6) uniform sampler2D gIn_Emissive;
layout(set = 0, binding = 7) uniform sampler2D gIn_IndirectDiffuse;
layout(set = 0, binding = 8) uniform sampler2D gIn_IndirectSpecular;
layout(set = 0, binding = 9, rgba16f) writeonly uniform image2D gOut_Composite;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  vec3 radiance = sanitizeRadiance(texelFetch(gIn_Direct, pixel, 0).xyz);
  if (gbufferDepth(pixel) > 0.0f) {
    vec4 baseColorMetallic = clamp(texelFetch(gIn_BaseColorMetallic, pixel, 0), vec4(0.0f), vec4(1.0f));
    vec3 baseColor = baseColorMetallic.xyz;
    float metallic = baseColorMetallic.w;
    radiance += baseColor * (1.0f - metallic) * texelFetch(gIn_IndirectDiffuse, pixel, 0).xyz;
    // A pixel without a usable normal has no indirect light (the branches wrote 0 there).
    float roughness;
    Surface x = gbufferSurfaceRoughness(pixel, roughness);
    if (x.viewZ > 0.0f) {
      float nDotV = dot(x.normal, normalize(viewPosition(gIn_Frame.frame.view) - x.position));
      vec3 f0 = specularF0(baseColor, metallic);
      radiance += specularReflectance(f0, nDotV, roughness) *
                  texelFetch(gIn_IndirectSpecular, pixel, 0).xyz;
    }
    if (gIn_Frame.frame.hasEmissive != 0u) radiance += sanitizeRadiance(texelFetch(gIn_Emissive, pixel, 0).xyz);
  }
  imageStore(gOut_Composite, pixel, vec4(sanitizeRadiance(radiance), 1.0f));
}
