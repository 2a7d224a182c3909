#version 460
#extension GL_GOOGLE_include_directive : require
// gi.depth_pyramid: level 0 of the min-max depth pyramid (gi/hiz_trace.glsl
// marches it): this frame's march depth (gi.store_history) as (nearest,
// farthest) viewZ, both the pixel's own viewZ, or (0, 0) for background.
// gi.depth_pyramid_reduce makes the coarser levels from it. Level 0 is kept
// in the pyramid, although it repeats the march depth, so that a trace reads
// every level through one binding with one fetch.
#include "shared/finite.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, r32f) readonly uniform image2D gIn_MarchDepth;
layout(set = 0, binding = 1, rg32f) writeonly uniform image2D gOut_DepthPyramid;

layout(push_constant) uniform Params {
  uvec2 inputSize;   // the render size
  uvec2 outputSize;  // the same: level 0 is the render size
} params;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= int(params.outputSize.x) || pixel.y >= int(params.outputSize.y)) return;
  // The march depth is the library's own, but no pass trusts what it reads.
  float viewZ = imageLoad(gIn_MarchDepth, pixel).x;
  float surface = isFinite(viewZ) && viewZ > 0.0f ? viewZ : 0.0f;
  imageStore(gOut_DepthPyramid, pixel, vec4(surface, surface, 0.0f, 0.0f));
}
