#version 460
#extension GL_GOOGLE_include_directive : require
// tests.shared_math_check: runs runSharedMathCheck over every input, so the
// GPU results can be compared with the same source compiled as C++.
#include "tests/shared_math_check.glsl"

layout(local_size_x = 64, local_size_y = 1) in;

layout(std430, set = 0, binding = 0) readonly buffer Inputs { SharedMathCheckInput items[]; } gIn_Inputs;
layout(std430, set = 0, binding = 1) writeonly buffer Outputs { SharedMathCheckOutput items[]; } gOut_Outputs;

layout(push_constant) uniform Params { uint count; } params;

void main() {
  uint index = gl_GlobalInvocationID.x;
  if (index >= params.count) return;
  gOut_Outputs.items[index] = runSharedMathCheck(gIn_Inputs.items[index]);
}
