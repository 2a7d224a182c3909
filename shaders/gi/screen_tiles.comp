#version 460
#extension GL_GOOGLE_include_directive : require
// gi.screen_tiles: what screen-only mode gives this frame's rays that
// leave the screen before screen space can decide them, away from the
// camera (gi/screen_only_policy.glsl): per 16x16 tile, the mean direct
// light (the engine's direct image, emission included) of the pixels that
// show a surface (rgb) and how many do (a).
// Each workgroup is one tile and sums it in a fixed order
// (gi/workgroup_sum.glsl): the same bits every run.
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 0, binding = 4) uniform sampler2D gIn_Direct;
layout(set = 0, binding = 5, rgba32f) writeonly uniform image2D gOut_Tiles;

#define WORKGROUP_SUM_LANES 256
#include "gi/workgroup_sum.glsl"

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  vec4 own = vec4(0.0f);
  if (insideFull(pixel) && gbufferDepth(pixel) > 0.0f)
    own = vec4(sanitizeRadiance(texelFetch(gIn_Direct, pixel, 0).xyz), 1.0f);
  vec4 tile = workgroupSum(own);
  if (gl_LocalInvocationIndex != 0u) return;
  imageStore(gOut_Tiles, ivec2(gl_WorkGroupID.xy), vec4(tile.a > 0.0f ? tile.rgb / tile.a : vec3(0.0f), tile.a));
}
