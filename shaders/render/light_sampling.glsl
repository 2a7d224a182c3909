// Sampling the environment and emissive triangles as lights, with the pdfs
// multiple importance sampling needs for directions and hits found by BSDF
// sampling. The distributions are built on the CPU (src/render/light_sampling.h).
//
// The including shader includes render/scene_access.glsl first and defines
//   #define LIGHT_SAMPLING_FIRST_BINDING n
//     n + 0  gIn_EnvironmentCdf     marginal cdf (height + 1), then per row the conditional cdf (width + 1)
//     n + 1  gIn_EmissiveTriangles  instance, triangle, cumulative power share (float bits), area (float bits)
// and passes a LightSampling describing them (sizes and total power) to every call.
#ifndef BOUNCE_RENDER_LIGHT_SAMPLING_GLSL
#define BOUNCE_RENDER_LIGHT_SAMPLING_GLSL

#include "shared/color.glsl"
#include "shared/equirect.glsl"

layout(set = 0, binding = LIGHT_SAMPLING_FIRST_BINDING + 0, std430) readonly buffer EnvironmentCdf { float values[]; }
gIn_EnvironmentCdf;
layout(set = 0, binding = LIGHT_SAMPLING_FIRST_BINDING + 1, std430) readonly buffer EmissiveTriangles { uvec4 items[]; }
gIn_EmissiveTriangles;

struct LightSampling {
  uint environmentWidth;   // cells of the environment distribution; 0 = no environment light
  uint environmentHeight;
  uint emissiveCount;      // emissive triangles; 0 = none
  float emissivePower;     // sum of luminance(emission) * area over them
};

// The interval i of a cdf stored at first .. first + count (count + 1 values,
// from 0 to 1) with cdf[i] <= u < cdf[i + 1].
uint cdfInterval(uint first, uint count, float u) {
  uint low = 0u;
  uint high = count;
  while (low + 1u < high) {
    uint middle = (low + high) / 2u;
    if (gIn_EnvironmentCdf.values[first + middle] <= u) low = middle;
    else high = middle;
  }
  return low;
}

// The environment distribution's density per unit solid angle for a direction.
float environmentLightPdf(LightSampling lights, vec3 direction) {
  if (lights.environmentWidth == 0u) return 0.0f;
  vec2 uv = equirectUv(direction);
  float sinTheta = sin(uv.y * kPi);
  if (sinTheta <= 0.0f) return 0.0f;
  uint width = lights.environmentWidth;
  uint height = lights.environmentHeight;
  uint row = min(uint(uv.y * float(height)), height - 1u);
  uint column = min(uint(uv.x * float(width)), width - 1u);
  uint conditional = height + 1u + row * (width + 1u);
  float rowShare = gIn_EnvironmentCdf.values[row + 1u] - gIn_EnvironmentCdf.values[row];
  float cellShare = gIn_EnvironmentCdf.values[conditional + column + 1u] - gIn_EnvironmentCdf.values[conditional + column];
  return rowShare * float(height) * cellShare * float(width) / (2.0f * kPi * kPi * sinTheta);
}

// A direction drawn from the environment distribution: a cell by its power,
// then a uniform point in the cell. false when there is no environment light.
bool sampleEnvironmentLight(LightSampling lights, vec2 u, out vec3 direction, out float pdf) {
  direction = vec3(0.0f, 1.0f, 0.0f);
  pdf = 0.0f;
  if (lights.environmentWidth == 0u) return false;
  uint width = lights.environmentWidth;
  uint height = lights.environmentHeight;
  uint row = cdfInterval(0u, height, u.y);
  float rowLow = gIn_EnvironmentCdf.values[row];
  float rowHigh = gIn_EnvironmentCdf.values[row + 1u];
  uint conditional = height + 1u + row * (width + 1u);
  uint column = cdfInterval(conditional, width, u.x);
  float cellLow = gIn_EnvironmentCdf.values[conditional + column];
  float cellHigh = gIn_EnvironmentCdf.values[conditional + column + 1u];
  // Reuse where u fell inside its interval as the position inside the cell.
  vec2 inCell = vec2((u.x - cellLow) / max(cellHigh - cellLow, 1e-30f), (u.y - rowLow) / max(rowHigh - rowLow, 1e-30f));
  vec2 uv = (vec2(float(column), float(row)) + clamp(inCell, 0.0f, 0.99999f)) / vec2(float(width), float(height));
  float sinTheta = sin(uv.y * kPi);
  if (sinTheta <= 0.0f) return false;
  direction = equirectDirection(uv);
  pdf = (rowHigh - rowLow) * float(height) * (cellHigh - cellLow) * float(width) / (2.0f * kPi * kPi * sinTheta);
  return pdf > 0.0f;
}

// A hit emitter's density per unit area under emissive light sampling:
// triangles are chosen by luminance(emission) * area, points uniformly on
// them, so the area terms cancel.
float emissiveLightPdfArea(LightSampling lights, uint material) {
  if (lights.emissiveCount == 0u || !(lights.emissivePower > 0.0f)) return 0.0f;
  return luminance(gIn_Materials.items[material].emissive.xyz) / lights.emissivePower;
}

struct EmissiveSample {
  vec3 position;
  vec3 geometricNormal;  // either side: emitters are two-sided, as surfaces are
  vec3 emission;
  float pdfArea;
};

// A point on an emissive triangle for a receiver at `receiver`, drawn by
// power and then uniformly by area; its emission is what it sends towards
// the receiver (none from the back of a single-sided emitter).
bool sampleEmissiveLight(LightSampling lights, vec3 u, vec3 receiver, out EmissiveSample light) {
  light.position = vec3(0.0f);
  light.geometricNormal = vec3(0.0f, 1.0f, 0.0f);
  light.emission = vec3(0.0f);
  light.pdfArea = 0.0f;
  if (lights.emissiveCount == 0u) return false;
  // The first triangle whose cumulative share exceeds u.z.
  uint low = 0u;
  uint high = lights.emissiveCount - 1u;
  while (low < high) {
    uint middle = (low + high) / 2u;
    if (uintBitsToFloat(gIn_EmissiveTriangles.items[middle].z) <= u.z) low = middle + 1u;
    else high = middle;
  }
  uvec4 entry = gIn_EmissiveTriangles.items[low];
  // Uniform barycentrics (Shirley's square-root warp).
  float s = sqrt(u.x);
  vec2 barycentrics = vec2(s * (1.0f - u.y), s * u.y);
  // Where the point is first, so that it is shaded as seen from the receiver.
  uvec4 triangle = bvhTriangle(entry.y);
  vec3 objectPosition = barycentricMix(bvhVertexPosition(triangle.x), bvhVertexPosition(triangle.y),
                                       bvhVertexPosition(triangle.z), barycentrics);
  vec3 position = transformPoint(gIn_Instances.items[entry.x].objectToWorld, objectPosition);
  vec3 toPoint = position - receiver;
  vec3 direction = dot(toPoint, toPoint) > 0.0f ? normalize(toPoint) : vec3(0.0f, 0.0f, -1.0f);
  SceneSurface surface = resolveSurface(BvhHit(1.0f, entry.x, entry.y, barycentrics), direction, 1e-6f);
  light.position = surface.position;
  light.geometricNormal = surface.geometricNormal;
  light.emission = surface.emissive;
  light.pdfArea = emissiveLightPdfArea(lights, surface.material);
  return light.pdfArea > 0.0f;
}

// Veach's power heuristic (beta = 2) for one sample of each of two strategies.
float powerHeuristic(float pdfThis, float pdfOther) {
  float a = pdfThis * pdfThis;
  float b = pdfOther * pdfOther;
  return a > 0.0f ? a / (a + b) : 0.0f;
}

#endif
