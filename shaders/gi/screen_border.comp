#version 460
#extension GL_GOOGLE_include_directive : require
// gi.screen_border: what screen-only mode gives this frame's rays that
// turn towards the camera (gi/screen_only_policy.glsl): over the pixels of
// the screen's outermost ring, the mean direct light of those that show a
// surface (rgb) and the share that show the sky (a). One workgroup for the
// whole ring; every invocation sums a fixed set of pixels in a fixed order,
// then the workgroup sums them (gi/workgroup_sum.glsl): the same bits every run.
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"

layout(local_size_x = 256) in;

layout(set = 0, binding = 4) uniform sampler2D gIn_Direct;
layout(set = 0, binding = 5, rgba32f) writeonly uniform image2D gOut_Border;

const uint kInvocations = 256u;
#define WORKGROUP_SUM_LANES kInvocations
#include "gi/workgroup_sum.glsl"

// The ring's pixels in the top and bottom rows (one row if the screen is
// one pixel high).
uint ringRowPixels(ivec2 size) { return uint(size.x) * (size.y > 1 ? 2u : 1u); }

// How many pixels the ring has.
uint ringPixels(ivec2 size) {
  return ringRowPixels(size) + uint(max(size.y - 2, 0)) * (size.x > 1 ? 2u : 1u);
}

// Pixel i of the ring: the top and bottom rows, then the left and right
// columns without their corners.
ivec2 ringPixel(uint i, ivec2 size) {
  uint rowPixels = ringRowPixels(size);
  if (i < rowPixels) return ivec2(int(i) % size.x, i < uint(size.x) ? 0 : size.y - 1);
  uint j = i - rowPixels;
  int rows = max(size.y - 2, 1);
  return ivec2(j < uint(rows) ? 0 : size.x - 1, 1 + int(j) % rows);
}

void main() {
  uint lane = gl_LocalInvocationIndex;
  ivec2 size = ivec2(fullSize());
  uint count = ringPixels(size);
  vec4 own = vec4(0.0f);  // direct light summed over surface pixels, their count
  for (uint i = lane; i < count; i += kInvocations) {
    ivec2 pixel = ringPixel(i, size);
    if (gbufferDepth(pixel) > 0.0f) own += vec4(sanitizeRadiance(texelFetch(gIn_Direct, pixel, 0).xyz), 1.0f);
  }
  vec4 total = workgroupSum(own);
  if (lane != 0u) return;
  vec3 mean = total.a > 0.0f ? total.rgb / total.a : vec3(0.0f);
  float skyShare = 1.0f - total.a / float(count);  // count >= 1: the render size is at least 1x1
  imageStore(gOut_Border, ivec2(0), vec4(mean, skyShare));
}
