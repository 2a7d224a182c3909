#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.bright_pixels_reduce: one more 2x2 -> 1 step of the
// bright-pixel pyramid: each tile keeps the brightest of its four entries.
// The levels' images are sized for the largest render size; the push
// constants say how much of them this frame's render size fills, so
// entries an earlier, larger frame left beyond it are never read.
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, rgba32f) readonly uniform image2D gIn_Brightest;
layout(set = 0, binding = 1, rgba32f) writeonly uniform image2D gOut_Brightest;

layout(push_constant) uniform Params {
  uvec2 inputSize;   // entries of the level below at this render size
  uvec2 outputSize;  // entries of this level
} params;

void main() {
  ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
  ivec2 outSize = ivec2(params.outputSize);
  if (tile.x >= outSize.x || tile.y >= outSize.y) return;
  ivec2 inSize = ivec2(params.inputSize);
  vec4 best = vec4(0.0f);
  for (int i = 0; i < 4; ++i) {
    ivec2 entry = tile * 2 + ivec2(i & 1, i >> 1);
    if (entry.x >= inSize.x || entry.y >= inSize.y) continue;
    vec4 candidate = imageLoad(gIn_Brightest, entry);
    if (candidate.w > 0.0f && candidate.x > best.x) best = candidate;
  }
  imageStore(gOut_Brightest, tile, best);
}
