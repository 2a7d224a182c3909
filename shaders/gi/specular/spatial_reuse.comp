#version 460
#extension GL_GOOGLE_include_directive : require
// gi.specular.spatial_reuse: merges each pixel's reservoir with a few
// neighbours' (the Jitter gi pass's specular ReSTIR) taken in a disk of the surface's tangent plane
// whose radius is the lobe's footprint: the hit distance times the tangent
// of the cone holding most of the lobe (nothing for a mirror, wide for a
// rough surface far from what it reflects), at most
// gi.specular.spatial_max_radius. The diffuse branch's rejections (normal,
// plane distance) keep neighbours on the same surface; a neighbour's sample
// is re-weighed by its target here and by the reconnection Jacobian. The
// chosen sample's W is normalised by the M of the reservoirs that could have
// produced it (its target is positive there, its Jacobian not rejected).
// The output is this frame's alone (the history is temporal reuse's).
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"

layout(set = 0, binding = 4) uniform sampler2D gIn_BaseColorMetallic;
#define SPECULAR_READS_MATERIAL
#include "gi/specular/specular_common.glsl"
#include "shared/reservoir.glsl"
#include "shared/sampling.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 5, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 6, rgba32ui) readonly uniform uimage2D gIn_Reservoir1;
layout(set = 0, binding = 7, rgba32ui) writeonly uniform uimage2D gOut_Reservoir0;
layout(set = 0, binding = 8, rgba32ui) writeonly uniform uimage2D gOut_Reservoir1;

const uint kSaltSpecularSpatial = 0x7374u + 2u;
const uint kMaxNeighbours = 16u;

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideHalf(halfPixel)) return;
  uvec4 first = imageLoad(gIn_Reservoir0, halfPixel);
  uvec4 second = imageLoad(gIn_Reservoir1, halfPixel);
  ivec2 pixel = reservoirSurfacePixel(halfPixel);
  float roughness;
  Surface x = gbufferSurfaceRoughness(pixel, roughness);
  SpecularConstants c = gIn_SpecularConstants.specular;
  if (x.viewZ > 0.0f && c.spatialSamples > 0u) {
    GlossySurface s = pixelGlossySurface(x, roughness, pixel);
    Reservoir own = unpackReservoir(first, second);
    // Half-resolution pixels at this surface, in world units.
    float halfPixelSize = 4.0f * gIn_Frame.frame.view.projection.y * x.viewZ / fullSize().y;
    float hitDistance = reservoirHasSample(own) && !reservoirIsEnvironment(own) ? distance(own.position, x.position)
                                                                                 : 1.0e4f * x.viewZ;
    float worldRadius = min(specularFootprintRadius(hitDistance, s.alpha), c.spatialMaxRadius * halfPixelSize);
    if (specularReuses(s) && worldRadius >= halfPixelSize) {
      uint rng = giSeed(uvec2(halfPixel), kSaltSpecularSpatial);
      Reservoir merged = emptyReservoir();
      reservoirStream(merged, own.position, own.normal, own.radiance, own.flags,
                      specularTargetPdf(own, s, c.sampling, c.lobeFraction) * own.W * own.M, own.M, rngUniform(rng));
      vec3 tangent, bitangent;
      buildOrthonormalBasis(x.normal, tangent, bitangent);
      bool jacobian = c.jacobian != 0u;
      GlossySurface neighbours[kMaxNeighbours];
      float neighbourM[kMaxNeighbours];
      uint count = 0u;
      for (uint i = 0u; i < min(c.spatialSamples, kMaxNeighbours); ++i) {
        float ux = rngUniform(rng);
        float uy = rngUniform(rng);
        float choice = rngUniform(rng);
        vec2 disk = sampleConcentricDisk(vec2(ux, uy)) * worldRadius;
        vec3 projected = projectToScreen(gIn_Frame.frame.view, x.position + tangent * disk.x + bitangent * disk.y,
                                         fullSize());
        if (projected.z <= 0.0f) continue;
        ivec2 neighbourHalf = ivec2(floor(projected.xy * 0.5f));
        if (!insideHalf(neighbourHalf) || neighbourHalf == halfPixel) continue;
        ivec2 neighbourPixel = reservoirSurfacePixel(neighbourHalf);
        float neighbourRoughness;
        Surface n = gbufferSurfaceRoughness(neighbourPixel, neighbourRoughness);
        if (n.viewZ <= 0.0f || dot(n.normal, x.normal) < c.spatialCosNormalTolerance) continue;
        if (abs(dot(x.normal, n.position - x.position)) > c.spatialPlaneTolerance * x.viewZ) continue;
        GlossySurface neighbour = pixelGlossySurface(n, neighbourRoughness, neighbourPixel);
        if (!specularReuses(neighbour)) continue;
        Reservoir candidate =
            unpackReservoir(imageLoad(gIn_Reservoir0, neighbourHalf), imageLoad(gIn_Reservoir1, neighbourHalf));
        float scale = reuseJacobian(candidate, n.position, x.position, kMaxSpatialJacobian, jacobian);
        reservoirStream(merged, candidate.position, candidate.normal, candidate.radiance, candidate.flags,
                        specularTargetPdf(candidate, s, c.sampling, c.lobeFraction) * candidate.W * candidate.M * scale,
                        candidate.M, choice);
        neighbours[count] = neighbour;
        neighbourM[count] = candidate.M;
        ++count;
      }
      float confidence = own.M;
      for (uint i = 0u; i < count; ++i) {
        if (specularTargetPdf(merged, neighbours[i], c.sampling, c.lobeFraction) > 0.0f &&
            reuseJacobian(merged, neighbours[i].position, x.position, kMaxSpatialJacobian, jacobian) > 0.0f)
          confidence += neighbourM[i];
      }
      reservoirFinalize(merged, specularTargetPdf(merged, s, c.sampling, c.lobeFraction), confidence);
      packReservoir(merged, first, second);
    }
  }
  imageStore(gOut_Reservoir0, halfPixel, first);
  imageStore(gOut_Reservoir1, halfPixel, second);
}
