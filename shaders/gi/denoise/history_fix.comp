#version 460
#extension GL_GOOGLE_include_directive : require
// gi.denoise.history_fix: for each signal, a pixel whose history is shorter than
// gi.denoise.history_fix_frames (just disoccluded, or after a cut) is
// rebuilt from a wide neighbourhood: 5x5 taps history_fix_stride pixels
// apart (the stride shrinking as its history grows), on its plane and in
// its lobe, neighbours with longer histories counting more (REBLUR's
// history fix). Then anti-firefly: a pixel brighter than its eight
// neighbours' mean + 2 sigma is brought down to that (REBLUR's anti-firefly
// sigma scale): a single reservoir's outlier would otherwise be spread by
// the blurs; ordinary noise, within 2 sigma, is left to them. For a
// checkerboarded signal, the six neighbours off the pixel's row: its left
// and right neighbours share its samples (the pre-pass's checkerboard
// resolve copies a pixel's sample into both, or theirs into it), and a
// firefly copied beside itself would pass for the neighbourhood's light.
// The output goes to the signal's history image, which temporal
// accumulation has read and post-blur will write: blur reads it from
// there.
#include "gi/gi_common.glsl"
#define DENOISE_READS_TILES
#include "gi/denoise/denoise_common.glsl"
#include "shared/color.glsl"

// 16x16 pixels a workgroup (one denoiser tile), sharing their neighbourhood.
const int kGroupSize = 16;
layout(local_size_x = kGroupSize, local_size_y = kGroupSize) in;

DENOISE_SLOT_IMAGES(readonly, gIn_Accumulated, 20)
DENOISE_SLOT_IMAGES(writeonly, gOut_Fixed, 24)
DENOISE_SLOT_LOAD(gIn_Accumulated)
DENOISE_SLOT_STORE(gOut_Fixed)
#define NEIGHBOURHOOD_AT(slot, pixel) gIn_AccumulatedAt(slot, pixel)
#include "gi/denoise/neighbourhood_tile.glsl"

const float kAntiFireflySigmas = 2.0f;

// The average over the wide neighbourhood, for a pixel of `frames` history.
vec3 rebuiltFromNeighbours(uint slot, ivec2 pixel, Surface x, float roughness, vec3 own, float frames) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  float stride = max(1.0f, d.historyFixStride * (1.0f - frames / d.historyFixFrames));
  NeighbourWeighting weighting = neighbourWeighting(slot, x, roughness, frames, 1.0f);
  vec3 sum = own;
  float weightSum = 1.0f;
  for (int j = -2; j <= 2; ++j)
    for (int i = -2; i <= 2; ++i) {
      ivec2 tap = pixel + ivec2(round(vec2(i, j) * stride));
      if ((i == 0 && j == 0) || !insideFull(tap)) continue;
      float tapRoughness;
      Surface y = denoiseSurfaceRoughness(tap, tapRoughness);
      vec4 value = gIn_AccumulatedAt(slot, tap);
      // A neighbour with a longer history is a better estimate of the surface's light.
      float w = neighbourWeight(weighting, y, tapRoughness) * (1.0f + value.w);
      sum += value.xyz * w;
      weightSum += w;
    }
  return sum / weightSum;
}

// `radiance` brought down to its neighbours' mean + kAntiFireflySigmas sigma
// (checkerboard: its neighbours off its row).
vec3 withoutFirefly(uint slot, vec3 radiance) {
  bool sameRowShares = signalCheckerboarded(slot);
  float mean = 0.0f, meanSquare = 0.0f, count = 0.0f;
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      vec2 texel = neighbourhoodTexel(slot, ivec2(i, j));
      if ((j == 0 && (i == 0 || sameRowShares)) || texel.y == 0.0f) continue;
      float l = texel.x;
      mean += l;
      meanSquare += l * l;
      count += 1.0f;
    }
  if (count == 0.0f) return radiance;
  mean /= count;
  float ceiling = mean + kAntiFireflySigmas * sqrt(max(meanSquare / count - mean * mean, 0.0f));
  float own = luminance(radiance);
  return own > ceiling && own > 0.0f ? radiance * (ceiling / own) : radiance;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  // The group is one tile: it leaves whole, before the shared load.
  if (tileEmpty(pixel)) {
    if (insideFull(pixel))
      for (uint slot = 0u; slot < gSignals.count; ++slot) gOut_FixedStore(slot, pixel, vec4(0.0f));
    return;
  }
  loadNeighbourhoodTile();
  if (!insideFull(pixel)) return;
  float roughness;
  Surface x = denoiseSurfaceRoughness(pixel, roughness);
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  for (uint slot = 0u; slot < gSignals.count; ++slot) {
    if (x.viewZ <= 0.0f) {
      gOut_FixedStore(slot, pixel, vec4(0.0f));
      continue;
    }
    vec4 center = gIn_AccumulatedAt(slot, pixel);
    vec3 radiance = center.xyz;
    if (center.w < d.historyFixFrames) radiance = rebuiltFromNeighbours(slot, pixel, x, roughness, radiance, center.w);
    if (d.antiFirefly != 0u) radiance = withoutFirefly(slot, radiance);
    gOut_FixedStore(slot, pixel, roundedToHalf(vec4(sanitizeRadiance(radiance), center.w)));
  }
}
