#version 460
#extension GL_GOOGLE_include_directive : require
// tests.bvh_alpha_check: render.bvh_trace_rays with an alpha-test hook that
// makes every alpha-masked triangle transparent, so tests/test_bvh.cpp can
// check that masked triangles reach the hook and that rays then pass them.
#define BVH_ALPHA_TEST(instance, triangle, barycentrics) false
#include "render/bvh_trace_rays.glsl"
