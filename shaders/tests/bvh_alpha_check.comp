#version 460
#extension GL_GOOGLE_include_directive : require
// tests.bvh_alpha_check: render.bvh_trace_rays with an alpha-test hook that
// makes every alpha-masked triangle transparent, so tests/test_bvh.cpp can
// check that masked triangles reach the hook and that rays then pass them.
#define BVH_FIRST_BINDING 2
#define BVH_ALPHA_TEST(instance, triangle, barycentrics) false
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
  result.ids = uvec4(hit.instance, hit.triangle, 0u, 0u);
  gOut_Results.items[index] = result;
}
