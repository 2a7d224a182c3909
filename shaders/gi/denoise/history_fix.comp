#version 460
#extension GL_GOOGLE_include_directive : require
// gi.denoise.SIGNAL.history_fix: a pixel whose history is shorter than
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
#include "gi/gi_common.glsl"
#define DENOISE_READS_TILES
#include "gi/denoise/denoise_common.glsl"
#include "shared/color.glsl"

// 16x16 pixels a workgroup (one denoiser tile), sharing their neighbourhood.
const int kGroupSize = 16;
layout(local_size_x = kGroupSize, local_size_y = kGroupSize) in;

layout(set = 0, binding = 5, rgba16f) readonly uniform image2D gIn_Accumulated;
#define NEIGHBOURHOOD_IMAGE gIn_Accumulated
#include "gi/denoise/neighbourhood_tile.glsl"
layout(set = 0, binding = 6, rgba16f) writeonly uniform image2D gOut_Fixed;

const float kAntiFireflySigmas = 2.0f;

// The average over the wide neighbourhood, for a pixel of `frames` history.
vec3 rebuiltFromNeighbours(ivec2 pixel, Surface x, float roughness, vec3 own, float frames) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  float stride = max(1.0f, d.historyFixStride * (1.0f - frames / d.historyFixFrames));
  vec3 sum = own;
  float weightSum = 1.0f;
  for (int j = -2; j <= 2; ++j)
    for (int i = -2; i <= 2; ++i) {
      ivec2 tap = pixel + ivec2(round(vec2(i, j) * stride));
      if ((i == 0 && j == 0) || !insideFull(tap)) continue;
      float tapRoughness;
      Surface y = denoiseSurfaceRoughness(tap, tapRoughness);
      vec4 value = imageLoad(gIn_Accumulated, tap);
      // A neighbour with a longer history is a better estimate of the surface's light.
      float w = neighbourWeight(x, roughness, frames, y, tapRoughness) * (1.0f + value.w);
      sum += value.xyz * w;
      weightSum += w;
    }
  return sum / weightSum;
}

// `radiance` brought down to its neighbours' mean + kAntiFireflySigmas sigma
// (checkerboard: its neighbours off its row).
vec3 withoutFirefly(ivec2 pixel, vec3 radiance) {
  bool sameRowShares = signalCheckerboarded();
  float mean = 0.0f, meanSquare = 0.0f, count = 0.0f;
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      vec2 texel = neighbourhoodTexel(ivec2(i, j));
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
    if (insideFull(pixel)) imageStore(gOut_Fixed, pixel, vec4(0.0f));
    return;
  }
  loadNeighbourhoodTile();
  if (!insideFull(pixel)) return;
  float roughness;
  Surface x = denoiseSurfaceRoughness(pixel, roughness);
  if (x.viewZ <= 0.0f) {
    imageStore(gOut_Fixed, pixel, vec4(0.0f));
    return;
  }
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  vec4 center = imageLoad(gIn_Accumulated, pixel);
  vec3 radiance = center.xyz;
  if (center.w < d.historyFixFrames) radiance = rebuiltFromNeighbours(pixel, x, roughness, radiance, center.w);
  if (d.antiFirefly != 0u) radiance = withoutFirefly(pixel, radiance);
  imageStore(gOut_Fixed, pixel, roundedToHalf(vec4(sanitizeRadiance(radiance), center.w)));
}
