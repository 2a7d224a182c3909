#version 460
#extension GL_GOOGLE_include_directive : require
// render.bvh_trace_rays: traces a buffer of rays against the scene BVH, one
// thread per ray, closest-hit or any-hit as the push constants say. Used by
// the BVH tests (against the CPU) and by benchmarks (rays per second).
// Every triangle is opaque here (no alpha-test hook).
#include "render/bvh_trace_rays.glsl"
