// Direct light from the sun and every punctual light at a surface point,
// each with a ray-traced (alpha-tested) shadow, through the material model.
// Shared by render.direct_light (at G-buffer pixels) and any pass that needs
// next-event estimation at other surfaces.
//
// The including shader includes render/scene_access.glsl first and defines
//   #define DIRECT_LIGHTS_BINDING n   (the GpuLight buffer gIn_Lights)
#ifndef BOUNCE_RENDER_DIRECT_LIGHTING_GLSL
#define BOUNCE_RENDER_DIRECT_LIGHTING_GLSL

#include "shared/brdf.glsl"

layout(set = 0, binding = DIRECT_LIGHTS_BINDING, std430) readonly buffer Lights { GpuLight items[]; } gIn_Lights;

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

// A shader may define DIRECT_LIGHT_SHADOW_RAY_COUNTED() to count every
// shadow ray traced here (the GI scene bridge does: the ray budget).
#ifndef DIRECT_LIGHT_SHADOW_RAY_COUNTED
#define DIRECT_LIGHT_SHADOW_RAY_COUNTED()
#endif

// Whether something blocks the shadow ray (0, tMax) along `toLight`.
bool shadowed(vec3 shadowOrigin, vec3 toLight, float tMax) {
  DIRECT_LIGHT_SHADOW_RAY_COUNTED();
  return bvhTraceAny(shadowOrigin, toLight, 0.0f, tMax);
}

// Reflected radiance towards `toViewer` from the sun and the punctual lights.
// `shadowOrigin` is `position` moved off the surface (offsetOrigin).
vec3 directLighting(vec3 position, vec3 shadowOrigin, vec3 normal, vec3 geometricNormal, vec3 toViewer,
                    vec3 baseColor, float metallic, float roughness) {
  vec3 radiance = vec3(0.0f);
  float sunIlluminance = SCENE_FRAME.frame.sunDirection.w;
  vec3 toSun = SCENE_FRAME.frame.sunDirection.xyz;
  if (sunIlluminance > 0.0f && dot(geometricNormal, toSun) > 0.0f) {
    vec3 f = materialBrdfCosine(normal, toViewer, toSun, baseColor, metallic, roughness);
    if (any(greaterThan(f, vec3(0.0f))) && !shadowed(shadowOrigin, toSun, 1e30f))
      radiance += f * sunIlluminance * SCENE_FRAME.frame.sunColor.xyz;
  }

  uint lightCount = uint(SCENE_FRAME.frame.sunColor.w);
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
    vec3 f = materialBrdfCosine(normal, toViewer, toLight, baseColor, metallic, roughness);
    if (all(equal(f, vec3(0.0f)))) continue;
    if (shadowed(shadowOrigin, toLight, distance * 0.9999f)) continue;
    radiance += f * light.radiantColor.xyz * attenuation;
  }
  return radiance;
}

#endif
