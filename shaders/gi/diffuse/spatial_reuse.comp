#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.spatial_reuse: merges each pixel's reservoir with those of a
// few neighbours picked in a disk around its surface point, in the surface's
// tangent plane (so the disk follows the surface on screen). Neighbours on
// another surface (normal or plane distance too different) are skipped.
// A neighbour's sample is re-weighed by its p-hat here and, with the
// Jacobian on, by how much larger a solid angle its sender covers from
// here than from the neighbour (ReSTIR GI). The chosen sample's W is
// normalised by the M of those reservoirs alone that could have produced it
// (its sender faces them and lies above their tangent plane, and its
// Jacobian from them is not rejected; Bitterli et al. 2020, Algorithm 6): dividing by every M would darken wherever neighbours
// see less of the sky of this pixel (creases, corners). Whether a neighbour
// sees the chosen sample is asked by a world ray where the settings say so;
// those rays are queued here and traced by gi.diffuse.neighbour_visibility,
// and gi.diffuse.spatial_normalize counts their verdicts in
// (gi/diffuse/neighbour_tests.glsl). Run twice (radius and count are push
// constants); the second pass's output is next frame's history.
// The pass whose counters its world rays add to (gi/world_ray_count.glsl).
#define WORLD_RAY_PASS kWorldRayPassSpatialReuse
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "gi/diffuse/diffuse_common.glsl"
#include "gi/diffuse/reuse_visibility.glsl"
#include "shared/reservoir.glsl"
#include "shared/sampling.glsl"
#include "gi/diffuse/neighbour_tests.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 5, rgba32ui) readonly uniform uimage2D gIn_Reservoir1;
layout(set = 0, binding = 6, rgba32ui) writeonly uniform uimage2D gOut_Reservoir0;
layout(set = 0, binding = 7, rgba32ui) writeonly uniform uimage2D gOut_Reservoir1;
layout(set = 0, binding = 8, rgba32f) writeonly uniform image2D gOut_TestSummary;
layout(set = 0, binding = 9, std430) writeonly buffer NeighbourTests { uvec2 items[]; } gOut_NeighbourTests;
layout(set = 0, binding = 10, std430) buffer WorldQueue { uint items[]; } gOut_WorldQueue;
#define WORLD_QUEUE_APPEND
#include "gi/world_queue.glsl"


void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideHalf(halfPixel)) return;
  uvec4 first = imageLoad(gIn_Reservoir0, halfPixel);
  uvec4 second = imageLoad(gIn_Reservoir1, halfPixel);
  ivec2 pixel = reservoirSurfacePixel(halfPixel);
  Surface x = gbufferSurface(pixel);
  float viewZ = x.viewZ;
  vec4 summary = vec4(0.0f);
  if (viewZ > 0.0f && params.samples > 0u) {
    DiffuseConstants d = gIn_DiffuseConstants.diffuse;
    uint target = d.targetFunction;
    uint rng = giSeed(uvec2(halfPixel), kSaltSpatial + 16u * params.passIndex);
    Reservoir own = unpackReservoir(first, second);
    Reservoir merged = emptyReservoir();
    reservoirStream(merged, own.position, own.normal, own.radiance, own.flags,
                    targetPdf(own, x.position, x.normal, target) * own.W * own.M, own.M, rngUniform(rng));
    // The disk's radius in world units: half-resolution pixels are two full ones.
    float pixelSize = 2.0f * gIn_Frame.frame.view.projection.y * viewZ / fullSize().y;
    float worldRadius = params.radius * 2.0f * pixelSize;
    vec3 tangent, bitangent;
    buildOrthonormalBasis(x.normal, tangent, bitangent);
    bool jacobian = d.jacobian != 0u;
    // The surfaces and confidences of the neighbours merged, to normalise by later.
    vec3 neighbourPositions[kMaxSpatialNeighbours];
    vec3 neighbourNormals[kMaxSpatialNeighbours];
    float neighbourM[kMaxSpatialNeighbours];
    uint neighbourPixels[kMaxSpatialNeighbours];
    uint neighbours = 0u;
    for (uint i = 0u; i < min(params.samples, kMaxSpatialNeighbours); ++i) {
      float ux = rngUniform(rng);
      float uy = rngUniform(rng);
      float choice = rngUniform(rng);
      vec2 disk = sampleConcentricDisk(vec2(ux, uy)) * worldRadius;
      vec3 onPlane = x.position + tangent * disk.x + bitangent * disk.y;
      vec3 projected = projectToScreen(gIn_Frame.frame.view, onPlane, fullSize());
      if (projected.z <= 0.0f) continue;
      ivec2 neighbourHalf = ivec2(floor(projected.xy * 0.5f));
      if (!insideHalf(neighbourHalf) || neighbourHalf == halfPixel) continue;
      Surface neighbour = gbufferSurface(reservoirSurfacePixel(neighbourHalf));
      if (neighbour.viewZ <= 0.0f) continue;
      if (dot(neighbour.normal, x.normal) < d.spatialCosNormalTolerance) continue;
      if (abs(dot(x.normal, neighbour.position - x.position)) > d.spatialPlaneTolerance * viewZ) continue;
      Reservoir candidate = unpackReservoir(imageLoad(gIn_Reservoir0, neighbourHalf), imageLoad(gIn_Reservoir1, neighbourHalf));
      float scale = reuseJacobian(candidate, neighbour.position, x.position, kMaxSpatialJacobian, jacobian) *
                    reuseVisibility(candidate, x);
      reservoirStream(merged, candidate.position, candidate.normal, candidate.radiance, candidate.flags,
                      targetPdf(candidate, x.position, x.normal, target) * candidate.W * candidate.M * scale,
                      candidate.M, choice);
      neighbourPositions[neighbours] = neighbour.position;
      neighbourNormals[neighbours] = neighbour.normal;
      neighbourM[neighbours] = candidate.M;
      neighbourPixels[neighbours] = uint(neighbourHalf.x) | (uint(neighbourHalf.y) << 16);
      ++neighbours;
    }
    // Own M always counts: the chosen sample has p-hat > 0 here.
    float confidence = own.M;
    // A neighbour counts only if it could have held the chosen sample: it sees
    // it (tested for sky samples by default, for all with the unbiased option;
    // gi/diffuse/reuse_visibility.glsl says why). Sky tests are rays into the
    // open, the longest there are: at most neighbourVisibilityRays() of the
    // neighbours are tested, and the rest count with the fraction of the
    // tested ones' M that saw the sample (a neighbour's visibility estimated
    // from its tested peers; with none tested, all count, as with the test
    // off). The tests are queued; until gi.diffuse.spatial_normalize has
    // their verdicts, every neighbour counts as seeing the sample.
    bool tested = neighbourVisibilityTested(merged);
    uint tests = min(neighbourVisibilityRays(), params.slotsPerPixel);
    uint queued = 0u;
    float untestedM = 0.0f;
    for (uint i = 0u; i < neighbours; ++i) {
      if (!canHandOver(merged, neighbourPositions[i], neighbourNormals[i], x.position, kMaxSpatialJacobian, jacobian,
                       target))
        continue;
      confidence += neighbourM[i];
      if (!tested || !(neighbourM[i] > 0.0f)) continue;
      if (queued == tests) {
        untestedM += neighbourM[i];
        continue;
      }
      uint slot = neighbourTestSlot(halfPixel, queued);
      gOut_NeighbourTests.items[slot] = uvec2(neighbourPixels[i], floatBitsToUint(neighbourM[i]));
      enqueue(slot);
      ++queued;
    }
    reservoirFinalize(merged, targetPdf(merged, x.position, x.normal, target), confidence);
    // The confidence handed on (to the next pass and the next frame) is every
    // M merged, not Z: Z depends on the chosen sample (near creases it is
    // small), and a confidence that does biases every later merge against
    // such samples (tests/test_reservoir.cpp shows the darkening). But the M
    // of neighbours that cannot see the sample is left out (by
    // gi.diffuse.spatial_normalize): handing it on with a W normalised
    // without it makes every later merge weigh the sample up (sun-room,
    // 96x54: +8 % over no spatial reuse with it, +4 % without).
    if (queued > 0u) summary = vec4(float(queued), untestedM, confidence, 0.0f);
    packReservoir(merged, first, second);
  }
  imageStore(gOut_Reservoir0, halfPixel, first);
  imageStore(gOut_Reservoir1, halfPixel, second);
  if (kSceneBridgeTraces) imageStore(gOut_TestSummary, halfPixel, summary);
}
