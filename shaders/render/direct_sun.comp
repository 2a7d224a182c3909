#version 460
#extension GL_GOOGLE_include_directive : require
// render.direct_sun: direct sunlight at every G-buffer pixel, with a
// ray-cast shadow, and the sky behind background pixels. Lambert diffuse
// only, weighted by (1 - metallic); the GGX lobe comes with the material
// model.
#include "render/analytic_scene.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1, r32f) readonly uniform image2D gIn_ViewZ;
layout(set = 0, binding = 2, rgba16f) readonly uniform image2D gIn_NormalRoughness;
layout(set = 0, binding = 3, rgba8) readonly uniform image2D gIn_BaseColorMetallic;
layout(set = 0, binding = 4, rgba16f) writeonly uniform image2D gOut_Radiance;

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= uint(params.cameraPosition.w) || pixel.y >= uint(params.cameraRight.w)) return;
  float viewZ = imageLoad(gIn_ViewZ, ivec2(pixel)).x;
  if (viewZ <= 0.0f) {
    imageStore(gOut_Radiance, ivec2(pixel), vec4(params.skyRadiance.xyz, 0.0f));
    return;
  }
  vec3 direction = analyticCameraRay(pixel);
  vec3 position = params.cameraPosition.xyz + direction * (viewZ / dot(direction, params.cameraForward.xyz));
  vec3 normal = imageLoad(gIn_NormalRoughness, ivec2(pixel)).xyz;
  vec4 baseColorMetallic = imageLoad(gIn_BaseColorMetallic, ivec2(pixel));
  vec3 toSun = params.sunDirection.xyz;
  float cosine = max(dot(normal, toSun), 0.0f);
  // Offset along the normal, scaled with distance, so the shadow ray does not
  // hit the surface it starts on.
  vec3 shadowOrigin = position + normal * (1e-4f * max(1.0f, viewZ));
  float visible = (cosine > 0.0f && !occludedAnalyticScene(shadowOrigin, toSun, 0.0f)) ? 1.0f : 0.0f;
  vec3 diffuse = baseColorMetallic.xyz * (1.0f - baseColorMetallic.w) * kInvPi;
  vec3 radiance = diffuse * params.sunDirection.w * params.sunColor.xyz * cosine * visible;
  imageStore(gOut_Radiance, ivec2(pixel), vec4(radiance, 0.0f));
}
