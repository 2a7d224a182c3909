// Scene access for the analytic render passes: the sphere buffer and the
// closest-hit / any-hit queries against it and the ground plane.
#ifndef BOUNCE_RENDER_ANALYTIC_SCENE_GLSL
#define BOUNCE_RENDER_ANALYTIC_SCENE_GLSL
#include "shared/intersect.glsl"
#include "render/analytic_scene_types.glsl"

layout(std430, set = 0, binding = 0) readonly buffer AnalyticSceneBuffer {
  AnalyticGround ground;
  AnalyticSphere spheres[];
} gIn_Scene;

layout(push_constant) uniform AnalyticScenePush { AnalyticSceneParams params; };

struct AnalyticHit {
  float t;        // kNoHit when nothing was hit
  vec3 normal;
  vec3 baseColor;
  float metallic;
  float roughness;
};

AnalyticHit traceAnalyticScene(vec3 origin, vec3 direction, float tMin) {
  AnalyticHit hit;
  hit.t = intersectPlane(origin, direction, vec3(0.0f, 1.0f, 0.0f), 0.0f, tMin);
  hit.normal = vec3(0.0f, 1.0f, 0.0f);
  hit.baseColor = gIn_Scene.ground.baseColor.xyz;
  hit.metallic = gIn_Scene.ground.baseColor.w;
  hit.roughness = gIn_Scene.ground.material.x;
  uint count = uint(params.cameraUp.w);
  for (uint i = 0u; i < count; ++i) {
    AnalyticSphere s = gIn_Scene.spheres[i];
    float t = intersectSphere(origin, direction, s.centerRadius.xyz, s.centerRadius.w, tMin);
    if (t < hit.t) {
      hit.t = t;
      hit.normal = normalize(origin + t * direction - s.centerRadius.xyz);
      hit.baseColor = s.baseColor.xyz;
      hit.metallic = s.baseColor.w;
      hit.roughness = s.material.x;
    }
  }
  return hit;
}

bool occludedAnalyticScene(vec3 origin, vec3 direction, float tMin) {
  if (intersectPlane(origin, direction, vec3(0.0f, 1.0f, 0.0f), 0.0f, tMin) < kNoHit) return true;
  uint count = uint(params.cameraUp.w);
  for (uint i = 0u; i < count; ++i) {
    vec4 s = gIn_Scene.spheres[i].centerRadius;
    if (intersectSphere(origin, direction, s.xyz, s.w, tMin) < kNoHit) return true;
  }
  return false;
}

// World-space ray through the centre of a pixel (no jitter yet).
vec3 analyticCameraRay(uvec2 pixel) {
  vec2 ndc = (vec2(pixel) + 0.5f) / vec2(params.cameraPosition.w, params.cameraRight.w) * 2.0f - 1.0f;
  return normalize(params.cameraForward.xyz + ndc.x * params.cameraRight.xyz - ndc.y * params.cameraUp.xyz);
}
#endif
