// The equirectangular (latitude-longitude) mapping between world directions
// and environment-image coordinates, one source for GLSL and C++.
//
// Convention (docs/environment.md): +Y up, so v = 0 is the zenith (the top
// row) and v = 1 the nadir. u runs along the horizon so that the image's
// centre (u = 0.5) is -Z, the direction a camera with the default view
// looks, and u grows to the viewer's right when looking down -Z: u = 0.75 is
// +X, u = 0.25 is -X. The seam u = 0 = 1 is +Z, behind that camera. In terms
// of scene::Sun's azimuth phi (from +Z towards +X), u = 1 - phi / 360 deg,
// so turning a map by +a degrees about +Y moves every feature by -a / 360 in u.
#ifndef BOUNCE_SHARED_EQUIRECT_GLSL
#define BOUNCE_SHARED_EQUIRECT_GLSL
#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

// uv in [0,1]^2 for a unit direction. At the poles, where every u is the same
// direction, u = 0.5 (atan2(0, 0) is undefined in GLSL). The polar angle
// comes from atan2 rather than acos(y), which loses half its digits near
// the poles.
vec2 equirectUv(vec3 direction) {
  float horizontal = sqrt(direction.x * direction.x + direction.z * direction.z);
  float u = horizontal > 0.0f ? 0.5f + atan(direction.x, -direction.z) * (0.5f * kInvPi) : 0.5f;
  float v = atan(horizontal, direction.y) * kInvPi;
  return vec2(u, v);
}

// The unit direction at uv; u may lie outside [0,1] (it wraps).
vec3 equirectDirection(vec2 uv) {
  float phi = (uv.x - 0.5f) * (2.0f * kPi);
  float theta = uv.y * kPi;
  float sinTheta = sin(theta);
  return vec3(sinTheta * sin(phi), cos(theta), -sinTheta * cos(phi));
}

// Solid angle (sr) of one texel in row `row` of a width x height equirect
// image: rows near the poles cover less of the sphere than those at the equator.
float equirectTexelSolidAngle(float row, float width, float height) {
  float thetaTop = row * kPi / height;
  float thetaBottom = (row + 1.0f) * kPi / height;
  return (2.0f * kPi / width) * (cos(thetaTop) - cos(thetaBottom));
}

BOUNCE_SHARED_END
#endif
