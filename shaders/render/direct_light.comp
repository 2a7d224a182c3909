#version 460
#extension GL_GOOGLE_include_directive : require
// render.direct_light: direct lighting of the G-buffer's surfaces — the sun
// and every punctual light, each with a ray-traced (alpha-tested) shadow —
// through the GGX + Lambert material, plus the surface's own emission.
// Background pixels show the environment. Linear HDR, stored through
// sanitizeRadiance: light brighter than a half float saturates at its
// largest finite value (docs/conventions.md, "Non-finite values").
#include "render/scene_access.glsl"
#include "shared/finite.glsl"
#include "shared/environment.glsl"
#define DIRECT_LIGHTS_BINDING 21
#include "render/direct_lighting.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 16, r32f) readonly uniform image2D gIn_ViewZ;
layout(set = 0, binding = 17, rgba16f) readonly uniform image2D gIn_NormalRoughness;
layout(set = 0, binding = 18, rgba16f) readonly uniform image2D gIn_GeometricNormal;
layout(set = 0, binding = 19, rgba8) readonly uniform image2D gIn_BaseColorMetallic;
layout(set = 0, binding = 20, rgba16f) readonly uniform image2D gIn_Emissive;
layout(set = 0, binding = 22) uniform sampler2D gIn_Environment;
layout(set = 0, binding = 23, rgba16f) writeonly uniform image2D gOut_Radiance;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  vec2 size = gIn_Frame.frame.imageSize.xy;
  if (pixel.x >= int(size.x) || pixel.y >= int(size.y)) return;

  vec3 origin = gIn_Frame.frame.camera.position.xyz;
  vec3 direction = cameraRayDirection(gIn_Frame.frame.camera, vec2(pixel) + 0.5f + gIn_Frame.frame.jitter.xy, size);
  float viewZ = imageLoad(gIn_ViewZ, pixel).x;
  if (viewZ <= 0.0f) {
    imageStore(gOut_Radiance, pixel, vec4(sanitizeRadiance(environmentBackground(gIn_Environment, direction)), 0.0f));
    return;
  }

  vec3 position = origin + direction * (viewZ / dot(direction, gIn_Frame.frame.camera.forward.xyz));
  vec4 normalRoughness = imageLoad(gIn_NormalRoughness, pixel);
  // Stored as rgba16f: renormalised, since a GGX peak of alpha 0.0025 is
  // narrower than the half-float error of a unit vector.
  vec3 normal = normalize(normalRoughness.xyz);
  vec3 geometricNormal = normalize(imageLoad(gIn_GeometricNormal, pixel).xyz);
  vec4 baseColorMetallic = imageLoad(gIn_BaseColorMetallic, pixel);
  vec3 toCamera = -direction;
  vec3 shadowOrigin = offsetOrigin(position, geometricNormal, viewZ);

  vec3 radiance = imageLoad(gIn_Emissive, pixel).xyz;

  radiance += directLighting(position, shadowOrigin, normal, geometricNormal, toCamera, baseColorMetallic.xyz,
                             baseColorMetallic.w, normalRoughness.w);
  imageStore(gOut_Radiance, pixel, vec4(sanitizeRadiance(radiance), 0.0f));
}
