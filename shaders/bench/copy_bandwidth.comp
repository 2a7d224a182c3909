#version 460
// bench.copy_bandwidth: copies one buffer of vec4 into another. It does nothing
// else, so its time measures the memory bandwidth compute passes can reach.
layout(local_size_x = 256, local_size_y = 1) in;

layout(std430, set = 0, binding = 0) readonly buffer Source { vec4 values[]; } gIn_Source;
layout(std430, set = 0, binding = 1) writeonly buffer Destination { vec4 values[]; } gOut_Destination;

layout(push_constant) uniform CopyParams {
  uint rowLength;  // vec4 per dispatch row (the dispatch is 2D to stay under the group-count limit)
  uint count;      // vec4 in all
} params;

void main() {
  uint index = gl_GlobalInvocationID.y * params.rowLength + gl_GlobalInvocationID.x;
  if (gl_GlobalInvocationID.x >= params.rowLength || index >= params.count) return;
  gOut_Destination.values[index] = gIn_Source.values[index];
}
