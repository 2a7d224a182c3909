// The analytic test scene's parameters, shared by the host (C++) and the
// render/analytic_* shaders, so both always agree on the layout. Every member
// is a vec4, which has the same layout in C++ and in push constants/std430.
#ifndef BOUNCE_RENDER_ANALYTIC_SCENE_TYPES_GLSL
#define BOUNCE_RENDER_ANALYTIC_SCENE_TYPES_GLSL
#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

struct AnalyticSceneParams {
  vec4 cameraPosition;   // xyz world position, w = image width in pixels
  vec4 cameraRight;      // xyz unit right * tan(fovY/2) * aspect, w = image height in pixels
  vec4 cameraUp;         // xyz unit up * tan(fovY/2), w = sphere count
  vec4 cameraForward;    // xyz unit view direction (view space -Z), w unused
  vec4 sunDirection;     // xyz unit direction towards the sun, w = sun illuminance E (W/m^2 at normal incidence)
  vec4 sunColor;         // rgb relative sun colour (luminance 1), w unused
  vec4 skyRadiance;      // rgb constant sky radiance seen by primary rays, w unused
};

struct AnalyticSphere {
  vec4 centerRadius;     // xyz centre, w radius
  vec4 baseColor;        // rgb linear base colour, w metallic
  vec4 material;         // x perceptual roughness, yzw unused
};

// The ground is the plane y = 0 with this material.
struct AnalyticGround {
  vec4 baseColor;        // rgb, w metallic
  vec4 material;         // x perceptual roughness
};

BOUNCE_SHARED_END
#endif
