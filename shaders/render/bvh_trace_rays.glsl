// The body of render.bvh_trace_rays (bvh_trace_rays.comp) and of its test
// variants, which define an alpha-test hook first: a buffer of rays in, a
// buffer of results out, one thread per ray, closest-hit or any-hit as the
// push constants say.
#ifndef BOUNCE_RENDER_BVH_TRACE_RAYS_GLSL
#define BOUNCE_RENDER_BVH_TRACE_RAYS_GLSL

#define BVH_FIRST_BINDING 2
#include "render/bvh_trace.glsl"

layout(local_size_x = 64) in;

layout(set = 0, binding = 0, std430) readonly buffer Rays { BvhRay items[]; } gIn_Rays;
layout(set = 0, binding = 1, std430) writeonly buffer Results { BvhTraceResult items[]; } gOut_Results;
layout(push_constant) uniform Params { BvhTraceRaysParams params; };

void main() {
  uint index = gl_GlobalInvocationID.x;
  if (index >= params.rayCountMode.x) return;
  BvhRay ray = gIn_Rays.items[index];
  BvhHit hit;
  bool anyHit = params.rayCountMode.y == kBvhTraceAny;
  bool found = bvhTrace(ray.originTMin.xyz, ray.directionTMax.xyz, ray.originTMin.w, ray.directionTMax.w, anyHit, hit);
  BvhTraceResult result;
  result.tBarycentrics = vec4(hit.t, hit.barycentrics, found && anyHit ? 1.0f : 0.0f);
  result.ids = uvec4(hit.instance, hit.triangle, found ? bvhTriangleMaterial(hit.triangle) : kBvhInvalidIndex, 0u);
  gOut_Results.items[index] = result;
}

#endif
