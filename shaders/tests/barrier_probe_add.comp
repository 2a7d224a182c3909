#version 460
// tests.barrier_probe_add: adds a constant to an image in place (a
// read-write binding), so that a later read must wait for its write.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform image2D gInOut_Value;
layout(push_constant) uniform Params { vec4 value; } params;
void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  imageStore(gInOut_Value, pixel, imageLoad(gInOut_Value, pixel) + params.value);
}
