// One level of the min-max depth pyramid from the level below it, what
// gi.depth_pyramid (from the march depth: level 1) and
// gi.depth_pyramid_reduce (from the pyramid's level below: levels 2 and
// up) share. A texel holds, over the pixels it covers:
//   x: the nearest surface's viewZ, 0 when every pixel is background;
//   y: the farthest surface's viewZ, 0 when any pixel is background,
// so that a trace can tell a tile it may step over (surfaces only) from
// one where it may meet the sky. Levels halve rounding down, as Vulkan's
// mip levels do: the last texel of a row or column of an odd-sized level
// takes the odd texel out too, so every level covers the whole render size
// and the last cell of a row reaches to the screen's edge
// (gi/hiz_trace.glsl steps by that rule). The images are sized for the
// largest render size; the push constants say how much of them this
// frame's render size fills, so texels an earlier, larger frame left
// beyond it are never read. The including shader defines
// vec2 finerTexel(ivec2 texel): (nearest, farthest) of the level below.
#ifndef BOUNCE_GI_DEPTH_PYRAMID_REDUCE_GLSL
#define BOUNCE_GI_DEPTH_PYRAMID_REDUCE_GLSL

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1, rg32f) writeonly uniform image2D gOut_DepthPyramid;

layout(push_constant) uniform Params {
  uvec2 inputSize;   // texels of the level below at this render size
  uvec2 outputSize;  // texels of this level: max(1, inputSize / 2)
} params;

vec2 finerTexel(ivec2 texel);

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 outSize = ivec2(params.outputSize);
  if (texel.x >= outSize.x || texel.y >= outSize.y) return;
  ivec2 inSize = ivec2(params.inputSize);
  ivec2 first = texel * 2;
  ivec2 last = min(mix(first + 1, inSize - 1, equal(texel, outSize - 1)), inSize - 1);
  float nearest = 0.0f;
  float farthest = 0.0f;
  bool open = true;  // no background pixel below
  for (int y = first.y; y <= last.y; ++y) {
    for (int x = first.x; x <= last.x; ++x) {
      vec2 finer = finerTexel(ivec2(x, y));
      if (finer.x > 0.0f) nearest = nearest > 0.0f ? min(nearest, finer.x) : finer.x;
      if (finer.y > 0.0f)
        farthest = max(farthest, finer.y);
      else
        open = false;
    }
  }
  imageStore(gOut_DepthPyramid, texel, vec4(nearest, open ? farthest : 0.0f, 0.0f, 0.0f));
}

#endif
