#version 460
#extension GL_GOOGLE_include_directive : require
// tests.hiz_trace_check: hizTrace (gi/hiz_trace.glsl) of a list of rays
// through the depth pyramid a test built, one ray a thread, for
// tests/test_depth_pyramid.cpp to compare with known answers and with a
// march through every pixel.
#include "gi/gi_common.glsl"

layout(local_size_x = 64) in;

struct HizQuery {
  vec4 origin;     // w: thickness
  vec4 direction;  // w: maxSteps
};
struct HizAnswer {
  uvec4 outcome;        // outcome, texel x, texel y (as int bits)
  vec4 lastFreeDistance;  // lastFree, distance
};

layout(set = 0, binding = 1, std430) readonly buffer Queries { HizQuery items[]; } gIn_Queries;
layout(set = 0, binding = 2, std430) writeonly buffer Answers { HizAnswer items[]; } gOut_Answers;
#define HIZ_BINDING 3
#define HIZ_LEVEL0_BINDING 4
#include "gi/hiz_trace.glsl"

layout(push_constant) uniform Params { uint count; } params;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= params.count) return;
  HizQuery query = gIn_Queries.items[i];
  HizRay ray = hizTrace(query.origin.xyz, query.direction.xyz, query.origin.w, uint(query.direction.w));
  gOut_Answers.items[i].outcome = uvec4(ray.outcome, uint(ray.texel.x), uint(ray.texel.y), 0u);
  gOut_Answers.items[i].lastFreeDistance = vec4(ray.lastFree, ray.distance);
}
