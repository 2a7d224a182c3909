#version 460
// tests.barrier_probe_read: copies gIn_Value to gOut_Copy (see barrier_probe_write).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) readonly uniform image2D gIn_Value;
layout(set = 0, binding = 1, rgba16f) writeonly uniform image2D gOut_Copy;
void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  imageStore(gOut_Copy, pixel, imageLoad(gIn_Value, pixel));
}
