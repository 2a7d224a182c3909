#version 460
#extension GL_GOOGLE_include_directive : require
// gi.depth_pyramid: level 1 of the min-max depth pyramid (gi/hiz_trace.glsl
// marches it), straight from this frame's march depth (gi.store_history),
// which is level 0 itself: each pixel's (nearest, farthest) is its own
// viewZ, or (0, 0) for background. The pyramid image holds levels 1 and up
// only (the march depth would repeat at full resolution, 16 MiB at 1080p);
// gi.depth_pyramid_reduce makes the coarser levels from this one.
#include "shared/finite.glsl"

layout(set = 0, binding = 0, r32f) readonly uniform image2D gIn_MarchDepth;

#include "gi/depth_pyramid_reduce.glsl"

vec2 finerTexel(ivec2 pixel) {
  // The march depth is the library's own, but no pass trusts what it reads.
  float viewZ = imageLoad(gIn_MarchDepth, pixel).x;
  float surface = isFinite(viewZ) && viewZ > 0.0f ? viewZ : 0.0f;
  return vec2(surface);
}
