#version 460
#extension GL_GOOGLE_include_directive : require
// gi.light_change.tiles: how much of the light the engine hands over
// changed since last frame, per 16x16 tile. Each surface pixel's direct
// light (emission included) is compared, as luminance, with what last
// frame's direct light was where the surface was then (the motion vector;
// only where last frame showed the same surface there). The differences
// are summed with their signs over 4x4 blocks first, so that the noise of
// a stochastic direct light, and the edges and texture detail a moving
// camera shifts by a fraction of a pixel, cancel within a block, while
// light that came, went or moved does not; and a block counts only the
// part of its change beyond kBlockNoise of its light (what reprojection
// cannot help: a bright emitter's edge, a highlight that moves with the
// view). The tile holds the sum of the blocks' counted changes (x), of the
// larger of the two lights (y), and the pixels compared (z). Every pixel's
// luminance is kept for the next frame (gOut_Direct). Sums run in a fixed
// order (a tree in shared memory): the same bits every run.
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "shared/color.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(set = 0, binding = 4) uniform sampler2D gIn_Direct;
layout(set = 0, binding = 5) uniform sampler2D gIn_Emissive;
layout(set = 0, binding = 6) uniform sampler2D gIn_Motion;
layout(set = 0, binding = 7, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 8, r32f) readonly uniform image2D gPrev_Direct;
layout(set = 0, binding = 9, r32f) writeonly uniform image2D gOut_Direct;
layout(set = 0, binding = 10, rgba32f) writeonly uniform image2D gOut_Tiles;
layout(set = 0, binding = 11, rg32ui) readonly uniform uimage2D gIn_Surface;

#include "gi/motion.glsl"
#include "gi/history_taps.glsl"

// Last frame's surface counts as this one within these (a looser match
// than reuse needs: a miss here only leaves a pixel uncompared).
const float kDepthTolerance = 0.05f;
const float kCosNormalTolerance = 0.9f;

const uint kBlockSide = 4u;
const float kBlockNoise = 0.15f;
const uint kBlockPixels = kBlockSide * kBlockSide;
const uint kTilePixels = 16u * 16u;
shared vec4 sums[kTilePixels];

float directLuminance(ivec2 pixel) {
  vec3 light = sanitizeRadiance(texelFetch(gIn_Direct, pixel, 0).xyz);
  if (gIn_Frame.frame.hasEmissive != 0u) light += sanitizeRadiance(texelFetch(gIn_Emissive, pixel, 0).xyz);
  return luminance(light);
}

// This pixel's change: (signed difference, the larger light, 1) where last
// frame showed its surface, else 0. Last frame's light is interpolated
// bilinearly at where the surface was, over the taps that showed it, of
// the same material (a nearest tap, or one of a neighbouring material,
// would read a neighbour's shading, or a lamp's edge, as a change wherever
// the camera moves; history_taps.glsl's weights): a pixel with less than
// kLeastTapWeight of such taps is not compared.
const float kLeastTapWeight = 0.5f;

vec4 pixelChange(ivec2 pixel, Surface x, float now) {
  if (!historyUsable()) return vec4(0.0f);
  vec2 motion = motionAt(pixel);
  if (!usableMotion(motion)) return vec4(0.0f);
  float expectedViewZ = projectToScreen(gIn_Frame.frame.previousView, x.position, fullSize()).z;
  if (expectedViewZ <= 0.0f) return vec4(0.0f);
  ExpectedSurface expected = ExpectedSurface(x.position, x.normal, expectedViewZ, kDepthTolerance,
                                             kCosNormalTolerance, materialOf(imageLoad(gIn_Surface, pixel).xy));
  ivec2 corner;
  vec4 weights = historyTapWeights(vec2(pixel) + motion, expected, corner);
  float weight = dot(weights, vec4(1.0f));
  if (weight < kLeastTapWeight) return vec4(0.0f);
  float light = 0.0f;
  for (int i = 0; i < 4; ++i)
    if (weights[i] > 0.0f) light += weights[i] * imageLoad(gPrev_Direct, corner + ivec2(i & 1, i >> 1)).x;
  float before = light / weight;
  return vec4(now - before, max(now, before), 1.0f, 0.0f);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  vec4 own = vec4(0.0f);
  if (insideFull(pixel)) {
    Surface x = gbufferSurface(pixel);
    float now = x.viewZ > 0.0f ? finiteOr(directLuminance(pixel), 0.0f) : 0.0f;
    imageStore(gOut_Direct, pixel, vec4(now));
    if (x.viewZ > 0.0f) own = pixelChange(pixel, x, now);
  }
  // Lanes of one 4x4 block sit together: block b holds lanes 16b..16b+15.
  uvec2 local = gl_LocalInvocationID.xy;
  uint block = (local.y / kBlockSide) * (16u / kBlockSide) + local.x / kBlockSide;
  uint lane = block * kBlockPixels + (local.y % kBlockSide) * kBlockSide + local.x % kBlockSide;
  sums[lane] = own;
  barrier();
  for (uint width = kBlockPixels / 2u; width > 0u; width /= 2u) {
    if (lane % kBlockPixels < width) sums[lane] += sums[lane + width];
    barrier();
  }
  if (lane % kBlockPixels == 0u)
    sums[lane].x = max(abs(sums[lane].x) - kBlockNoise * sums[lane].y, 0.0f) / (1.0f - kBlockNoise);
  barrier();
  for (uint width = kTilePixels / 2u; width >= kBlockPixels; width /= 2u) {
    if (lane < width && lane % kBlockPixels == 0u) sums[lane] += sums[lane + width];
    barrier();
  }
  if (lane == 0u) imageStore(gOut_Tiles, ivec2(gl_WorkGroupID.xy), sums[0]);
}
