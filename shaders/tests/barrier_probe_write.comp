#version 460
// tests.barrier_probe_write: writes a constant into an image. With its
// partner tests.barrier_probe_read it forms the smallest read-after-write
// pair, used to prove missing barriers are caught.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) writeonly uniform image2D gOut_Value;
layout(push_constant) uniform Params { vec4 value; } params;
void main() { imageStore(gOut_Value, ivec2(gl_GlobalInvocationID.xy), params.value); }
