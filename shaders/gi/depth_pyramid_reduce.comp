#version 460
#extension GL_GOOGLE_include_directive : require
// gi.depth_pyramid_reduce: one level of the min-max depth pyramid (levels
// 2 and up) from the level below it, one dispatch per level
// (gi/depth_pyramid_reduce.glsl says what a texel holds).
layout(set = 0, binding = 0, rg32f) readonly uniform image2D gIn_Finer;

#include "gi/depth_pyramid_reduce.glsl"

vec2 finerTexel(ivec2 texel) { return imageLoad(gIn_Finer, texel).xy; }
