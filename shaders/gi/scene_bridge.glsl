// The scene bridge: what the library's shaders may ask of the scene they
// never see (the pattern of RTXDI's application bridge). The engine writes
// the answers in GLSL, in a file named scene_bridge_impl.glsl that its build
// puts first on the include path when it compiles the library's shaders
// (CMake: bounce_embed_shaders(... SCENE_BRIDGE); the library's own build uses
// shaders/gi/bridge_none/, which traces nothing). docs/integration.md, "A
// scene bridge", walks through writing one; shaders/render/scene_bridge/ is
// the renderer's, over its BVH.
//
// The including shader includes gi/gi_common.glsl first. The bridge's
// resources take set 0 from SCENE_BRIDGE_FIRST_BINDING up (32, above every
// library pass's own bindings; the host finds them by name,
// SceneBridge::resources).
// The implementation defines
//   const bool kSceneBridgeTraces            false: every function below is a stub the
//                                            library never calls (screen space only)
//   SceneHit sceneTraceClosest(vec3 origin, vec3 direction, float tMax)
//       the first surface along origin + t * direction, 0 < t < tMax (direction
//       unit length); hit = false when there is none
//   bool sceneTraceAny(vec3 origin, vec3 direction, float tMax)
//       whether anything blocks the segment (0, tMax): shadow and visibility rays
//   vec3 sceneDirectRadiance(SceneHit hit, vec3 toOrigin)
//       the radiance `hit` reflects towards toOrigin (unit) from the direct
//       light of the engine's lights, shadows included; not its emission
// The functions must return finite values for finite arguments. The rays
// the library asks for are counted by the library; rays the bridge traces
// on its own (shadow rays in sceneDirectRadiance) it counts by calling
// countBridgeShadowRay() once per ray, so the ray budget sees them.
#ifndef BOUNCE_GI_SCENE_BRIDGE_GLSL
#define BOUNCE_GI_SCENE_BRIDGE_GLSL

#define SCENE_BRIDGE_FIRST_BINDING 32

// What a closest-hit ray found.
struct SceneHit {
  bool hit;
  float t;                // distance along the ray
  vec3 position;
  vec3 geometricNormal;   // unit, facing the ray's origin
  vec3 normal;            // shading normal, unit, facing the ray's origin
  vec3 diffuseAlbedo;     // what the surface's diffuse lobe reflects: base colour * (1 - metallic)
  vec3 emission;          // radiance it emits towards the ray's origin
  bool isLight;           // an emitter the engine also samples as a light
  vec3 baseColor;         // the material, for sceneDirectRadiance
  float metallic;
  float roughness;
};

SceneHit sceneMiss() {
  SceneHit hit;
  hit.hit = false;
  hit.t = 0.0f;
  hit.position = vec3(0.0f);
  hit.geometricNormal = vec3(0.0f, 0.0f, 1.0f);
  hit.normal = vec3(0.0f, 0.0f, 1.0f);
  hit.diffuseAlbedo = vec3(0.0f);
  hit.emission = vec3(0.0f);
  hit.isLight = false;
  hit.baseColor = vec3(0.0f);
  hit.metallic = 0.0f;
  hit.roughness = 1.0f;
  return hit;
}

#include "gi/world_ray_count.glsl"

// For the bridge: one shadow ray it traces to light a hit (see above).
void countBridgeShadowRay() { countWorldRay(kWorldRaysHitShadows); }

#include "scene_bridge_impl.glsl"

#endif
