#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.spatial_normalize: counts the verdicts of
// gi.diffuse.neighbour_visibility into each reservoir whose spatial merge
// queued tests (gi/diffuse/neighbour_tests.glsl). The merge normalised W as
// if every tested neighbour saw the chosen sample; the neighbours that do
// not, and the untested ones in the proportion of the tested M that did
// not, come out of the confidence Z (W grows by Z_all / Z) and of the M
// handed on, as gi/diffuse/spatial_reuse.comp explains.
#include "gi/gi_common.glsl"
#include "gi/diffuse/neighbour_tests.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 5, rgba32ui) uniform uimage2D gInOut_Reservoir1;
layout(set = 0, binding = 6, rgba32f) uniform image2D gInOut_TestSummary;
layout(set = 0, binding = 7, std430) readonly buffer NeighbourTests { uvec2 items[]; } gIn_NeighbourTests;

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideHalf(halfPixel)) return;
  vec4 summary = imageLoad(gInOut_TestSummary, halfPixel);
  uint tests = uint(summary.x);
  if (tests == 0u) return;
  float testedM = 0.0f, hiddenM = 0.0f;
  for (uint i = 0u; i < tests; ++i) {
    float m = uintBitsToFloat(gIn_NeighbourTests.items[neighbourTestSlot(halfPixel, i)].y);
    testedM += abs(m);
    if (m < 0.0f) hiddenM -= m;
  }
  float untestedM = summary.y;
  float hidden = hiddenM + untestedM * (hiddenM / testedM);
  summary.w = hidden;
  imageStore(gInOut_TestSummary, halfPixel, summary);
  if (!(hidden > 0.0f)) return;
  uvec4 first = imageLoad(gIn_Reservoir0, halfPixel);
  uvec4 second = imageLoad(gInOut_Reservoir1, halfPixel);
  Reservoir r = unpackReservoir(first, second);
  float confidenceAll = summary.z;
  float confidence = confidenceAll - hidden;
  r.W = confidence > 0.0f ? r.W * (confidenceAll / confidence) : 0.0f;
  if (!(r.W > 0.0f) || !isFinite(r.W)) {
    r.W = 0.0f;
    r.flags &= ~kReservoirHasSample;
  }
  r.M -= hidden;
  packReservoir(r, first, second);
  imageStore(gInOut_Reservoir1, halfPixel, second);
}
