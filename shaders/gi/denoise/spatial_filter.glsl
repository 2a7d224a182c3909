// The blur of gi.denoise.SIGNAL.blur and .post_blur (REBLUR's blur and
// post-blur, one kernel at two radii): 8 taps of a disk rotated per frame
// (diskRotation), its radius set by the pixel's history length, roughness
// and hit distance (blurRadius), each tap weighed by neighbourWeight
// (plane, lobe, roughness). The including shader declares gIn_Filtered (rgba16f:
// radiance, history length), gIn_Signal (the noisy input, for its hit
// distance) and includes gi/denoise/denoise_common.glsl with
// DENOISE_READS_TILES.
#ifndef BOUNCE_GI_DENOISE_SPATIAL_FILTER_GLSL
#define BOUNCE_GI_DENOISE_SPATIAL_FILTER_GLSL

// The filtered value at `pixel` (alpha: its history length, unchanged); 0
// without a surface.
vec4 spatialFilter(ivec2 pixel) {
  float roughness;
  Surface x = denoiseSurfaceRoughness(pixel, roughness);
  if (tileEmpty(pixel) || x.viewZ <= 0.0f) return vec4(0.0f);
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  vec4 center = imageLoad(gIn_Filtered, pixel);
  float normalizedHit =
      normalizedHitDistance(d.hitDistanceParameters, imageLoad(gIn_Signal, pixel).w, x.viewZ, roughness);
  float radius = blurRadius(center.w, roughness, normalizedHit);
  float rotation = diskRotation(d.frameIndex, 2u * gSignal.slot + (gSignal.radiusScale < 1.0f ? 1u : 0u));
  vec3 sum = center.xyz;
  float weightSum = 1.0f;
  for (uint i = 0u; i < 8u; ++i) {
    ivec2 tap = pixel + ivec2(round(diskTap(i, rotation) * radius));
    if (!insideFull(tap) || tap == pixel) continue;
    float tapRoughness;
    Surface y = denoiseSurfaceRoughness(tap, tapRoughness);
    float w = neighbourWeight(x, roughness, center.w, y, tapRoughness);
    if (w <= 0.0f) continue;
    sum += imageLoad(gIn_Filtered, tap).xyz * w;
    weightSum += w;
  }
  return vec4(sanitizeRadiance(sum / weightSum), center.w);
}

#endif
