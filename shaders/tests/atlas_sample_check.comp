#version 460
#extension GL_GOOGLE_include_directive : require
// tests.atlas_sample_check: samples the texture atlas at given (texture, uv,
// footprint) triples, so a test can compare with the CPU's mip chains.
#define TEXTURE_ATLAS_BINDING 0
#include "render/texture_atlas.glsl"

layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 2) readonly buffer Queries { vec4 items[]; } gIn_Queries;  // texture, u, v, footprint
layout(std430, set = 0, binding = 3) writeonly buffer Results { vec4 items[]; } gOut_Results;
layout(push_constant) uniform Params { uint count; } params;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= params.count) return;
  vec4 q = gIn_Queries.items[i];
  gOut_Results.items[i] = sampleAtlas(uint(q.x), vec2(q.y, q.z), q.w);
}
