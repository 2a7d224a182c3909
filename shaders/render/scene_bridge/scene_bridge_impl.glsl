// The renderer's scene bridge (render::bvhSceneBridge(), src/render/scene_bridge.cpp):
// the GI library's rays traced through the renderer's BVH, hits shaded with
// its materials and textures, direct light from its sun and punctual lights
// with shadow rays (directLighting(), as render.direct_light does for the
// pixels on screen). Everything is the renderer's own scene access
// (render/scene_access.glsl), moved to the bridge's bindings.
#define SCENE_FIRST_BINDING SCENE_BRIDGE_FIRST_BINDING
#define SCENE_FRAME gScene_Frame
#define SCENE_FRAME_STORAGE restrict readonly buffer
#include "render/scene_access.glsl"
#define DIRECT_LIGHTS_BINDING (SCENE_BRIDGE_FIRST_BINDING + 16)
#define DIRECT_LIGHT_SHADOW_RAY_COUNTED() countBridgeShadowRay()
#include "render/direct_lighting.glsl"

const bool kSceneBridgeTraces = true;

// Texture detail for GI rays: a cone this many radians wide, the spread of
// a diffuse bounce's neighbourhood; textures at hits are read at its
// footprint (blurrier and cheaper than primary rays' pixel cones).
const float kSceneRaySpread = 0.02f;

SceneHit sceneTraceClosest(vec3 origin, vec3 direction, float tMax) {
  BvhHit found = bvhTraceClosest(origin, direction, 0.0f, tMax);
  if (found.t >= kNoHit || found.instance == kBvhInvalidIndex) return sceneMiss();
  SceneSurface surface = resolveSurface(found, direction, max(found.t * kSceneRaySpread, 1e-6f));
  SceneHit hit;
  hit.hit = true;
  hit.t = found.t;
  hit.position = surface.position;
  hit.geometricNormal = surface.geometricNormal;
  hit.normal = surface.normal;
  hit.diffuseAlbedo = surface.baseColor * (1.0f - surface.metallic);
  hit.emission = surface.emissive;
  hit.isLight = any(greaterThan(surface.emissive, vec3(0.0f)));
  hit.baseColor = surface.baseColor;
  hit.metallic = surface.metallic;
  hit.roughness = surface.roughness;
  return hit;
}

bool sceneTraceAny(vec3 origin, vec3 direction, float tMax) { return bvhTraceAny(origin, direction, 0.0f, tMax); }

vec3 sceneDirectRadiance(SceneHit hit, vec3 toOrigin) {
  if (!hit.hit) return vec3(0.0f);
  vec3 shadowOrigin = offsetOrigin(hit.position, hit.geometricNormal, hit.t);
  return directLighting(hit.position, shadowOrigin, hit.normal, hit.geometricNormal, toOrigin, hit.baseColor,
                        hit.metallic, hit.roughness);
}
