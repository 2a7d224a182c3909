// Data the frame renderer hands its passes, laid out identically in GLSL
// (std140 / std430) and C++ (glm): vec4s and uvec4s only, so no padding rules
// can differ between the two.
#ifndef BOUNCE_RENDER_FRAME_TYPES_GLSL
#define BOUNCE_RENDER_FRAME_TYPES_GLSL

#include "shared/lang.glsl"

// The structs live in a named namespace in C++ (BOUNCE_SHARED_BEGIN's is
// unnamed, one per translation unit), so headers can pass them around.
#ifdef __cplusplus
namespace bounce::shared {
#endif

// A pinhole camera as the passes use it. A pixel's ray direction is
// forward + right * x + up * y with x, y in [-1, 1] across the image
// (right and up are pre-scaled by the image plane's half extents at distance 1).
struct GpuCamera {
  vec4 position;  // xyz, w = tan(fovY / 2)
  vec4 right;     // xyz scaled by tan(fovY / 2) * aspect, w = 0
  vec4 up;        // xyz scaled by tan(fovY / 2), w = 0
  vec4 forward;   // xyz unit, w = 0
};

struct FrameConstants {
  GpuCamera camera;
  GpuCamera previousCamera;  // for motion vectors; equals camera on a cut
  vec4 imageSize;            // width, height, 1/width, 1/height
  vec4 jitter;               // xy: sub-pixel offset of this frame's rays in pixels; z: pixel spread angle; w: frame
  vec4 sunDirection;         // xyz toward the sun, w = illuminance E (0: no sun)
  vec4 sunColor;             // rgb, w = number of punctual lights
  vec4 environment;          // x = mip count of the environment, y = 1 if background shows the sun disk
};

const uint kLightDirectional = 0u;
const uint kLightPoint = 1u;
const uint kLightSpot = 2u;

// KHR_lights_punctual light, in world space at this frame.
struct GpuLight {
  vec4 positionType;     // xyz, w = type (as float)
  vec4 directionRange;   // xyz = direction the light shines, w = range (0 = infinite)
  vec4 radiantColor;     // rgb = colour * intensity
  vec4 cone;             // x = cos(outer), y = 1 / max(cos(inner) - cos(outer), 1e-4)
};

// A material as the passes read it (scene::Material).
struct GpuMaterial {
  vec4 baseColorFactor;
  vec4 emissive;   // rgb = emissive factor * strength, w = alpha cutoff (negative: opaque)
  vec4 factors;    // x = metallic, y = roughness, z = normal scale, w = 1 if double sided
  uvec4 textures;  // base colour, metallic-roughness, normal, emissive; 0xffffffff = none
};

// One placed mesh: the transforms of this and the previous frame.
struct GpuInstance {
  vec4 objectToWorld[3];          // rows of a 3x4 matrix
  vec4 previousObjectToWorld[3];  // for motion vectors
  vec4 normalToWorld[3];          // inverse transpose, rows
  uvec4 ids;                      // x = object id (scene instance index), y = first vertex of its mesh
};

const uint kNoTexture = 0xffffffffu;

#ifdef __cplusplus
}  // namespace bounce::shared
#endif

BOUNCE_SHARED_BEGIN


vec3 transformPoint(vec4 rows[3], vec3 p) {
  return vec3(dot(rows[0], vec4(p, 1.0f)), dot(rows[1], vec4(p, 1.0f)), dot(rows[2], vec4(p, 1.0f)));
}
vec3 transformVector(vec4 rows[3], vec3 v) {
  return vec3(dot(vec3(rows[0].x, rows[0].y, rows[0].z), v), dot(vec3(rows[1].x, rows[1].y, rows[1].z), v),
              dot(vec3(rows[2].x, rows[2].y, rows[2].z), v));
}

// The ray through a point of the image (pixel units, (0,0) = top-left corner).
vec3 cameraRayDirection(GpuCamera camera, vec2 pixelPosition, vec2 imageSize) {
  vec2 ndc = vec2(2.0f * pixelPosition.x / imageSize.x - 1.0f, 1.0f - 2.0f * pixelPosition.y / imageSize.y);
  vec3 d = vec3(camera.forward.x, camera.forward.y, camera.forward.z) +
           vec3(camera.right.x, camera.right.y, camera.right.z) * ndc.x +
           vec3(camera.up.x, camera.up.y, camera.up.z) * ndc.y;
  return normalize(d);
}

// Where a world point lands on the image (pixel units); w of the result
// is the view depth (<= 0: behind the camera).
vec3 projectToPixel(GpuCamera camera, vec3 world, vec2 imageSize) {
  vec3 d = world - vec3(camera.position.x, camera.position.y, camera.position.z);
  vec3 right = vec3(camera.right.x, camera.right.y, camera.right.z);
  vec3 up = vec3(camera.up.x, camera.up.y, camera.up.z);
  float depth = dot(d, vec3(camera.forward.x, camera.forward.y, camera.forward.z));
  float x = dot(d, right) / (dot(right, right) * depth);
  float y = dot(d, up) / (dot(up, up) * depth);
  return vec3((x * 0.5f + 0.5f) * imageSize.x, (0.5f - y * 0.5f) * imageSize.y, depth);
}

BOUNCE_SHARED_END

#endif
