#version 460
// For tests/test_gpu_host.cpp only: a uniform block, which the passes do not
// use (they read their constants from storage buffers; gi/gi_common.glsl
// says why), so that reflecting one stays tested.
layout(local_size_x = 1) in;

layout(set = 0, binding = 0, std140) uniform ProbeBlock { vec4 value; } gIn_Probe;
layout(set = 0, binding = 1, std430) writeonly buffer ProbeOut { vec4 value; } gOut_Probe;

void main() { gOut_Probe.value = gIn_Probe.value; }
