// Ray-primitive intersections for the analytic scene (and later tests).
#ifndef BOUNCE_SHARED_INTERSECT_GLSL
#define BOUNCE_SHARED_INTERSECT_GLSL
#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

const float kNoHit = 3.0e38f;

// Distance along the ray (unit direction) to the nearest hit of the sphere in
// (tMin, kNoHit), or kNoHit. The geometric form (project the centre on the
// ray first) keeps precision when the sphere is small and far away.
float intersectSphere(vec3 origin, vec3 direction, vec3 center, float radius, float tMin) {
  vec3 toCenter = center - origin;
  float along = dot(toCenter, direction);
  vec3 closest = toCenter - along * direction;
  float h2 = radius * radius - dot(closest, closest);
  if (h2 < 0.0f) return kNoHit;
  float h = sqrt(h2);
  float t = along - h;
  if (t > tMin) return t;
  t = along + h;
  return t > tMin ? t : kNoHit;
}

// Distance to the plane dot(p, normal) = offset, hit from either side.
float intersectPlane(vec3 origin, vec3 direction, vec3 normal, float offset, float tMin) {
  float denom = dot(direction, normal);
  if (abs(denom) < 1e-12f) return kNoHit;
  float t = (offset - dot(origin, normal)) / denom;
  return t > tMin ? t : kNoHit;
}

BOUNCE_SHARED_END
#endif
