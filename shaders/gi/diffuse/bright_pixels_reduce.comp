#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.bright_pixels_reduce: one more 2x2 -> 1 step of the
// bright-pixel pyramid: each tile keeps the brightest of its four entries.
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, rgba32f) readonly uniform image2D gIn_Brightest;
layout(set = 0, binding = 1, rgba32f) writeonly uniform image2D gOut_Brightest;

void main() {
  ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
  ivec2 outSize = imageSize(gOut_Brightest);
  if (tile.x >= outSize.x || tile.y >= outSize.y) return;
  ivec2 inSize = imageSize(gIn_Brightest);
  vec4 best = vec4(0.0f);
  for (int i = 0; i < 4; ++i) {
    ivec2 entry = tile * 2 + ivec2(i & 1, i >> 1);
    if (entry.x >= inSize.x || entry.y >= inSize.y) continue;
    vec4 candidate = imageLoad(gIn_Brightest, entry);
    if (candidate.w > 0.0f && candidate.x > best.x) best = candidate;
  }
  imageStore(gOut_Brightest, tile, best);
}
