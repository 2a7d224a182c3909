// A camera as the GI library sees it: the matrices an engine has, plus the
// tangents of the half field of view and the frame's jitter. One source for
// GLSL and C++ (lang.glsl), tested on the CPU against the renderer's camera
// in tests/test_reservoir.cpp.
//
// Conventions (docs/conventions.md): right-handed view space, the camera
// looks down -Z with +Y up; viewZ is the positive distance along the view
// axis; pixel coordinates are continuous with (0,0) the top-left corner of
// the image, so pixel (i, j)'s centre is (i + 0.5, j + 0.5); the G-buffer's
// sample of that pixel lies at its centre plus the frame's jitter.
#ifndef BOUNCE_SHARED_SCREEN_VIEW_GLSL
#define BOUNCE_SHARED_SCREEN_VIEW_GLSL

#include "shared/lang.glsl"

#ifdef __cplusplus
namespace bounce::shared {
#endif

struct ScreenView {
  mat4 worldToView;
  mat4 viewToWorld;
  vec4 projection;  // x = tan(horizontal fov / 2), y = tan(vertical fov / 2), zw = jitter in pixels
};

#ifdef __cplusplus
}  // namespace bounce::shared
#endif

BOUNCE_SHARED_BEGIN

vec3 viewPosition(ScreenView view) {
  return vec3(view.viewToWorld[3].x, view.viewToWorld[3].y, view.viewToWorld[3].z);
}

// The world position of the surface a G-buffer pixel saw at depth viewZ.
vec3 reconstructPosition(ScreenView view, vec2 pixel, float viewZ, vec2 imageSize) {
  float ndcX = 2.0f * (pixel.x + 0.5f + view.projection.z) / imageSize.x - 1.0f;
  float ndcY = 1.0f - 2.0f * (pixel.y + 0.5f + view.projection.w) / imageSize.y;
  vec4 local = vec4(ndcX * view.projection.x * viewZ, ndcY * view.projection.y * viewZ, -viewZ, 1.0f);
  vec4 world = view.viewToWorld * local;
  return vec3(world.x, world.y, world.z);
}

// The unit direction from the camera through a G-buffer pixel's sample.
vec3 pixelRayDirection(ScreenView view, vec2 pixel, vec2 imageSize) {
  return normalize(reconstructPosition(view, pixel, 1.0f, imageSize) - viewPosition(view));
}

// A world point in view space (affine: points along a world segment are
// the same mix of its ends in view space, so marches transform twice only).
vec3 toViewSpace(ScreenView view, vec3 world) {
  vec4 local = view.worldToView * vec4(world, 1.0f);
  return vec3(local.x, local.y, local.z);
}

// Continuous pixel coordinates (without jitter) and viewZ of a view-space
// point; z <= 0 means behind the camera.
vec3 projectViewPoint(ScreenView view, vec3 local, vec2 imageSize) {
  float viewZ = -local.z;
  if (viewZ <= 0.0f) return vec3(-1.0f, -1.0f, viewZ);
  float ndcX = local.x / (viewZ * view.projection.x);
  float ndcY = local.y / (viewZ * view.projection.y);
  return vec3((ndcX * 0.5f + 0.5f) * imageSize.x, (0.5f - ndcY * 0.5f) * imageSize.y, viewZ);
}

// The same for a world point.
vec3 projectToScreen(ScreenView view, vec3 world, vec2 imageSize) {
  return projectViewPoint(view, toViewSpace(view, world), imageSize);
}

// The world area one pixel covers on a surface at viewZ whose normal makes
// angle theta (cosSurface = |cos theta|) with the camera ray, for a pixel
// whose ray makes angle alpha (cosAxis) with the view axis:
// (2 tanX / w)(2 tanY / h) viewZ^2 cos(alpha) / |cos theta|.
float pixelFootprintArea(ScreenView view, float viewZ, float cosAxis, float cosSurface, vec2 imageSize) {
  float pixelPlaneArea = (4.0f * view.projection.x * view.projection.y) / (imageSize.x * imageSize.y);
  return pixelPlaneArea * viewZ * viewZ * cosAxis / max(cosSurface, 1e-4f);
}

BOUNCE_SHARED_END
#endif
