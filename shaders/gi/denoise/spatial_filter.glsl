// The blur of gi.denoise.blur and .post_blur (REBLUR's blur and post-blur,
// one kernel at two radii): 8 taps of a disk rotated per frame
// (diskRotation), its radius set by the pixel's history length, roughness
// and hit distance (blurRadius), each tap weighed by neighbourWeight
// (plane, lobe, roughness). The including shader declares the slot
// gIn_Filtered (rgba16f: radiance, history length) with its loader, and
// includes gi/denoise/denoise_common.glsl with DENOISE_READS_TILES; it
// hands over the pixel's hit distance (the pre-passed signal's).
#ifndef BOUNCE_GI_DENOISE_SPATIAL_FILTER_GLSL
#define BOUNCE_GI_DENOISE_SPATIAL_FILTER_GLSL

// A slot's filtered value at `pixel` (surface x, a surface; alpha: its
// history length, unchanged).
vec4 spatialFilter(uint slot, ivec2 pixel, Surface x, float roughness, float hitDistance) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  vec4 center = gIn_FilteredAt(slot, pixel);
  float normalizedHit = normalizedHitDistance(d.hitDistanceParameters, hitDistance, x.viewZ, roughness);
  float radius = blurRadius(slot, center.w, roughness, normalizedHit);
  float rotation =
      diskRotation(d.frameIndex, 2u * gSignals.indices[slot] + (gSignals.radiusScale < 1.0f ? 1u : 0u));
  NeighbourWeighting weighting = neighbourWeighting(slot, x, roughness, center.w, 1.0f);
  vec3 sum = center.xyz;
  float weightSum = 1.0f;
  for (uint i = 0u; i < 8u; ++i) {
    ivec2 tap = pixel + ivec2(round(diskTap(i, rotation) * radius));
    if (!insideFull(tap) || tap == pixel) continue;
    float tapRoughness;
    Surface y = denoiseSurfaceRoughness(tap, tapRoughness);
    float w = neighbourWeight(weighting, y, tapRoughness);
    if (w <= 0.0f) continue;
    sum += gIn_FilteredAt(slot, tap).xyz * w;
    weightSum += w;
  }
  return vec4(sanitizeRadiance(sum / weightSum), center.w);
}

#endif
