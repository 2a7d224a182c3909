#version 460
#extension GL_GOOGLE_include_directive : require
// render.reference_resolve: the reference's images from its running sums.
// The samples are accumulated in two independent halves (A and B, alternate
// dispatches), so the same pass gives the whole estimate (both halves
// weighted by 1 / total samples) or either half alone (the other weighted 0),
// and the two halves measure how converged the whole is.
//   gOut_Diffuse    indirect diffuse, demodulated (as the GI passes output it);
//                   alpha: the mean first-hit distance of its paths (0: none)
//   gOut_Specular   indirect specular, demodulated by specularReflectance(); alpha alike
// (the noisy signals and hit distances FrameInputs::noisyDiffuse and
// noisySpecular take, at a few samples per pixel: bounce denoise)
//   gOut_Radiance   direct + base colour (1 - metallic) diffuse + specularReflectance specular
#include "gpu/constant_block.glsl"
#include "render/frame_types.glsl"
#include "render/reference_types.glsl"
#include "shared/brdf.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, std140) CONSTANT_BLOCK FrameBlock { FrameConstants frame; } gIn_Frame;
layout(set = 0, binding = 1, r32f) readonly uniform image2D gIn_ViewZ;
layout(set = 0, binding = 2, rgba16f) readonly uniform image2D gIn_NormalRoughness;
layout(set = 0, binding = 3, rgba8) readonly uniform image2D gIn_BaseColorMetallic;
layout(set = 0, binding = 4, rgba16f) readonly uniform image2D gIn_Direct;
layout(set = 0, binding = 5, rgba32f) readonly uniform image2D gIn_DiffuseSumA;
layout(set = 0, binding = 6, rgba32f) readonly uniform image2D gIn_SpecularSumA;
layout(set = 0, binding = 7, rgba32f) readonly uniform image2D gIn_DiffuseSumB;
layout(set = 0, binding = 8, rgba32f) readonly uniform image2D gIn_SpecularSumB;
layout(set = 0, binding = 9, rgba32f) readonly uniform image2D gIn_HitDistanceSum;
layout(set = 0, binding = 10, rgba32f) writeonly uniform image2D gOut_Radiance;
layout(set = 0, binding = 11, rgba32f) writeonly uniform image2D gOut_Diffuse;
layout(set = 0, binding = 12, rgba32f) writeonly uniform image2D gOut_Specular;

layout(push_constant) uniform Params { ReferenceResolveParams params; };

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  vec2 size = gIn_Frame.frame.imageSize.xy;
  if (pixel.x >= int(size.x) || pixel.y >= int(size.y)) return;
  vec3 direct = imageLoad(gIn_Direct, pixel).xyz;
  vec3 diffuse = imageLoad(gIn_DiffuseSumA, pixel).xyz * params.weightA +
                 imageLoad(gIn_DiffuseSumB, pixel).xyz * params.weightB;
  vec3 specularRadiance = imageLoad(gIn_SpecularSumA, pixel).xyz * params.weightA +
                          imageLoad(gIn_SpecularSumB, pixel).xyz * params.weightB;
  vec3 radiance = direct;
  vec3 specular = vec3(0.0f);
  if (imageLoad(gIn_ViewZ, pixel).x > 0.0f) {
    vec3 direction = cameraRayDirection(gIn_Frame.frame.camera, vec2(pixel) + 0.5f + gIn_Frame.frame.jitter.xy, size);
    vec4 normalRoughness = imageLoad(gIn_NormalRoughness, pixel);
    vec4 baseColorMetallic = imageLoad(gIn_BaseColorMetallic, pixel);
    vec3 reflectance = specularReflectance(specularF0(baseColorMetallic.xyz, baseColorMetallic.w),
                                           dot(normalize(normalRoughness.xyz), -direction), normalRoughness.w);
    specular = specularRadiance / reflectance;
    radiance += baseColorMetallic.xyz * (1.0f - baseColorMetallic.w) * diffuse + specularRadiance;
  }
  vec4 hitDistanceSum = imageLoad(gIn_HitDistanceSum, pixel);
  float diffuseDistance = hitDistanceSum.y > 0.0f ? hitDistanceSum.x / hitDistanceSum.y : 0.0f;
  float specularDistance = hitDistanceSum.w > 0.0f ? hitDistanceSum.z / hitDistanceSum.w : 0.0f;
  imageStore(gOut_Radiance, pixel, vec4(radiance, 1.0f));
  imageStore(gOut_Diffuse, pixel, vec4(diffuse, diffuseDistance));
  imageStore(gOut_Specular, pixel, vec4(specular, specularDistance));
}
