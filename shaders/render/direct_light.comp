#version 460
#extension GL_GOOGLE_include_directive : require
// render.direct_light: direct lighting of the G-buffer's surfaces — the sun
// and every punctual light, each with a ray-traced (alpha-tested) shadow —
// through the GGX + Lambert material, plus the surface's own emission.
// Background pixels show the environment. Linear HDR.
#include "render/scene_access.glsl"
#include "render/environment.glsl"
#include "shared/brdf.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 16, r32f) readonly uniform image2D gIn_ViewZ;
layout(set = 0, binding = 17, rgba16f) readonly uniform image2D gIn_NormalRoughness;
layout(set = 0, binding = 18, rgba16f) readonly uniform image2D gIn_GeometricNormal;
layout(set = 0, binding = 19, rgba8) readonly uniform image2D gIn_BaseColorMetallic;
layout(set = 0, binding = 20, rgba16f) readonly uniform image2D gIn_Emissive;
layout(set = 0, binding = 21, std430) readonly buffer Lights { GpuLight items[]; } gIn_Lights;
layout(set = 0, binding = 22) uniform sampler2D gIn_Environment;
layout(set = 0, binding = 23, rgba16f) writeonly uniform image2D gOut_Radiance;

// Moves a shadow ray's origin off the surface along the geometric normal,
// by an amount that grows with distance so float precision keeps up.
vec3 offsetOrigin(vec3 position, vec3 geometricNormal, float viewZ) {
  return position + geometricNormal * (2e-4f * max(1.0f, viewZ) + 1e-4f * length(position));
}

// glTF's recommended range window: smooth falloff to zero at the range.
float rangeWindow(float distanceSquared, float range) {
  if (range <= 0.0f) return 1.0f;
  float ratio = distanceSquared / (range * range);
  float window = clamp(1.0f - ratio * ratio, 0.0f, 1.0f);
  return window * window;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  vec2 size = gIn_Frame.frame.imageSize.xy;
  if (pixel.x >= int(size.x) || pixel.y >= int(size.y)) return;

  vec3 origin = gIn_Frame.frame.camera.position.xyz;
  vec3 direction = cameraRayDirection(gIn_Frame.frame.camera, vec2(pixel) + 0.5f + gIn_Frame.frame.jitter.xy, size);
  float viewZ = imageLoad(gIn_ViewZ, pixel).x;
  if (viewZ <= 0.0f) {
    imageStore(gOut_Radiance, pixel, vec4(environmentBackground(gIn_Environment, direction), 0.0f));
    return;
  }

  vec3 position = origin + direction * (viewZ / dot(direction, gIn_Frame.frame.camera.forward.xyz));
  vec4 normalRoughness = imageLoad(gIn_NormalRoughness, pixel);
  vec3 normal = normalRoughness.xyz;
  vec3 geometricNormal = imageLoad(gIn_GeometricNormal, pixel).xyz;
  vec4 baseColorMetallic = imageLoad(gIn_BaseColorMetallic, pixel);
  vec3 toCamera = -direction;
  vec3 shadowOrigin = offsetOrigin(position, geometricNormal, viewZ);

  vec3 radiance = imageLoad(gIn_Emissive, pixel).xyz;

  float sunIlluminance = gIn_Frame.frame.sunDirection.w;
  vec3 toSun = gIn_Frame.frame.sunDirection.xyz;
  if (sunIlluminance > 0.0f && dot(geometricNormal, toSun) > 0.0f) {
    vec3 f = materialBrdfCosine(normal, toCamera, toSun, baseColorMetallic.xyz, baseColorMetallic.w, normalRoughness.w);
    if (any(greaterThan(f, vec3(0.0f))) && !bvhTraceAny(shadowOrigin, toSun, 0.0f, 1e30f))
      radiance += f * sunIlluminance * gIn_Frame.frame.sunColor.xyz;
  }

  uint lightCount = uint(gIn_Frame.frame.sunColor.w);
  for (uint i = 0u; i < lightCount; ++i) {
    GpuLight light = gIn_Lights.items[i];
    uint type = uint(light.positionType.w);
    vec3 toLight;
    float distance = 1e30f;
    float attenuation = 1.0f;
    if (type == kLightDirectional) {
      toLight = -light.directionRange.xyz;
    } else {
      // Falloff and angle from the surface itself; only the shadow ray starts
      // from the offset origin.
      vec3 d = light.positionType.xyz - position;
      float distanceSquared = max(dot(d, d), 1e-8f);
      toLight = d / sqrt(distanceSquared);
      distance = length(light.positionType.xyz - shadowOrigin);
      attenuation = rangeWindow(distanceSquared, light.directionRange.w) / distanceSquared;
      if (type == kLightSpot) {
        float cosAngle = dot(-toLight, light.directionRange.xyz);
        float t = clamp((cosAngle - light.cone.x) * light.cone.y, 0.0f, 1.0f);
        attenuation *= t * t;
      }
    }
    if (attenuation <= 0.0f || dot(geometricNormal, toLight) <= 0.0f) continue;
    vec3 f = materialBrdfCosine(normal, toCamera, toLight, baseColorMetallic.xyz, baseColorMetallic.w,
                                normalRoughness.w);
    if (all(equal(f, vec3(0.0f)))) continue;
    if (bvhTraceAny(shadowOrigin, toLight, 0.0f, distance * 0.9999f)) continue;
    radiance += f * light.radiantColor.xyz * attenuation;
  }
  imageStore(gOut_Radiance, pixel, vec4(radiance, 0.0f));
}
