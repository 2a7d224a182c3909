#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// gi.denoise.temporal_accumulation: each signal's pre-passed noisy value
// blended into last frame's denoised history of it (the post-blur's output),
// reprojected by the surface motion with a Catmull-Rom filter where all 12
// of its taps showed the same surface, bilinear over the taps that did
// where some did not (gi/temporal_history.glsl), so a disocclusion starts
// over. A tap shows the same surface when its depth lies within REBLUR's
// disocclusion threshold (wider at grazing angles, and for a still camera)
// and its normal and material id agree. Specular-kind light also fetches the reflection's
// (virtual) history and blends the two as the specular branch's filter
// does (virtual for smooth lobes, each weighed by its agreement with this
// frame's neighbourhood); the virtual share goes to the moments' alpha for
// the validation view. The history length (REBLUR's accumulation speed)
// grows by one a frame up to gi.denoise.max_accumulated_frames, and for
// specular up to fewer frames on smooth lobes, whose reflection moves with
// the view (roughness-responsive accumulation). The history's luminance is
// clamped to the fast history (about 6 frames) +- clamp_sigma sigma, and
// where the fast history has left the long one the history counts as fewer
// frames (anti-lag), so lighting changes come through within a few frames.
// A change of the frame's direct light (gi.light_change) shortens every
// pixel's history at once, before the fast history could notice.
// Checkerboard mode: a pixel without a sample of its own this frame (the
// pre-pass filled it from its neighbours) trusts its history more, as
// REBLUR's checkerboard resolve does (kCheckerboardResolveAccumSpeed).
// Output alpha: the history length; the moments are the next frame's.
// Pixels without a surface (and empty tiles) store 0. One dispatch for
// every signal, a workgroup for one signal: the dispatch's rows hold the
// slots' frames one under another, each rounded up to whole 16x16 tiles.
// (Working every signal in one invocation, as the other stages do, made
// this pass 0.49 -> 0.72 ms on Sponza, H100, 1080p, two signals: the
// Catmull-Rom and virtual histories of both at once overflow the
// registers.)
#include "gi/gi_common.glsl"
#define DENOISE_READS_TILES
#include "gi/denoise/denoise_common.glsl"
#include "shared/color.glsl"

// 16x16 pixels a workgroup (one denoiser tile): the neighbourhood below is
// read into shared memory once for them all.
const int kGroupSize = 16;
layout(local_size_x = kGroupSize, local_size_y = kGroupSize) in;

#include "shared/sampling.glsl"
layout(set = 0, binding = 5) uniform sampler2D gIn_Motion;
layout(set = 0, binding = 7, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 12, rg32ui) readonly uniform uimage2D gIn_Surface;
DENOISE_SLOT_IMAGES(readonly, gIn_Signal, 20)
DENOISE_SLOT_TEXTURES(gPrev_Filtered, 24)
DENOISE_SLOT_IMAGES(readonly, gPrev_Moments, 28)
DENOISE_SLOT_IMAGES(writeonly, gOut_Accumulated, 32)
DENOISE_SLOT_IMAGES(writeonly, gOut_Moments, 36)
DENOISE_SLOT_LOAD(gIn_Signal)
DENOISE_SLOT_SAMPLE(gPrev_Filtered)
DENOISE_SLOT_LOAD(gPrev_Moments)
DENOISE_SLOT_STORE(gOut_Accumulated)
DENOISE_SLOT_STORE(gOut_Moments)

#include "gi/motion.glsl"
#define HISTORY_FILTERED(slot, tap) gPrev_FilteredAt(slot, tap)
#define HISTORY_FILTERED_LINEAR(slot, position) gPrev_FilteredLinear(slot, position)
#define HISTORY_MOMENTS(slot, tap) gPrev_MomentsAt(slot, tap)
#include "gi/temporal_history.glsl"
#define LIGHT_CHANGE_BINDING 16
#include "gi/light_change/light_change.glsl"

// The longest history a specular lobe keeps: a mirror's reflection moves
// with the view and keeps few frames, a rough lobe's barely does.
float maxFrames(uint slot, float roughness) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  if (!specularKind(slot)) return d.maxAccumulatedFrames;
  return max(1.0f, d.maxAccumulatedFrames * clamp(roughness * roughness * 4.0f, 0.1f, 1.0f));
}

// Luminance mean and mean square over the pixel's 5x5 neighbourhood at
// stride 2, on its plane: the moments the clamp is built from. The blurs
// spread a bright sample over its neighbours' histories; moments of the
// pixel alone would clamp those shares away (measured: cornell's diffuse
// 7 % darker).
const int kMomentsStride = 2;
// The fast history averages about 6 frames of 25 taps; anti-lag acts past
// this many standard errors of it. (3x3 taps raise the error by a fifth:
// measured, H100, 640x360 and 1080p.)
const float kMomentsSamples = 150.0f;
const float kAntiLagSigmas = 3.0f;

// Checkerboard mode: on a pixel the pre-pass filled from its neighbours,
// this frame's weight 1 / frames shrinks by up to this share, the more the
// longer the history (REBLUR's gCheckerboardResolveAccumSpeed:
// w *= mix(1 - k, 1, w)); a history just begun (w = 1) keeps all of it.
// The filled value is an interpolation, not a sample; the pixel's own
// sample of the frame before is in its history. REBLUR sets k from the
// frame rate, 0.88 at 30 frames a second with a still jitter.
const float kCheckerboardResolveAccumSpeed = 0.88f;

// The workgroup's pixels and the moments' reach around them, read once
// into shared memory (each pixel is a tap of up to 25 others): world
// position (w: 1 with a surface, -1 without) and the workgroup's signal's
// luminance.
const int kMomentsReach = 2 * kMomentsStride;
const int kTileSize = kGroupSize + 2 * kMomentsReach;
shared vec4 sPosition[kTileSize][kTileSize];
shared float sLuminance[kTileSize][kTileSize];

// Each workgroup works one slot: the dispatch's rows are the slots' frames
// one under another, each rounded up to whole workgroups.
uint rowsPerSlot() { return (uint(fullSize().y) + uint(kGroupSize) - 1u) / uint(kGroupSize) * uint(kGroupSize); }
uint workgroupSlot() { return gl_WorkGroupID.y * uint(kGroupSize) / rowsPerSlot(); }
ivec2 workgroupOrigin() {
  return ivec2(gl_WorkGroupID.x, gl_WorkGroupID.y - workgroupSlot() * (rowsPerSlot() / uint(kGroupSize))) * kGroupSize;
}

void loadNeighbourhood(uint slot) {
  ivec2 origin = workgroupOrigin() - kMomentsReach;
  for (uint k = gl_LocalInvocationIndex; k < uint(kTileSize * kTileSize); k += uint(kGroupSize * kGroupSize)) {
    ivec2 local = ivec2(int(k) % kTileSize, int(k) / kTileSize);
    ivec2 tap = origin + local;
    vec4 position = vec4(0.0f, 0.0f, 0.0f, -1.0f);
    float l = 0.0f;
    if (insideFull(tap)) {
      Surface y = denoiseSurface(tap);
      if (y.viewZ > 0.0f) {
        position = vec4(y.position, 1.0f);
        l = luminance(sanitizeRadiance(gIn_SignalAt(slot, tap).xyz));
      }
    }
    sPosition[local.y][local.x] = position;
    sLuminance[local.y][local.x] = l;
  }
  barrier();
}

// Which of the 5x5 taps around the pixel lie on its plane: bit i + 5 j
// (i, j in 0..4).
uint neighbourhoodOnPlane(Surface x) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  ivec2 centre = ivec2(gl_LocalInvocationID.xy) + kMomentsReach;
  uint onPlane = 0u;
  for (int j = -2; j <= 2; ++j)
    for (int i = -2; i <= 2; ++i) {
      ivec2 local = centre + ivec2(i, j) * kMomentsStride;
      vec4 y = sPosition[local.y][local.x];
      if (y.w < 0.0f || planeWeight(x.normal, x.position, y.xyz, x.viewZ, d.planeDistanceSensitivity) <= 0.0f)
        continue;
      onPlane |= 1u << uint((i + 2) + 5 * (j + 2));
    }
  return onPlane;
}

vec2 neighbourhoodMoments(uint slot, uint onPlane) {
  ivec2 centre = ivec2(gl_LocalInvocationID.xy) + kMomentsReach;
  vec2 sum = vec2(0.0f);
  float count = 0.0f;
  for (int j = -2; j <= 2; ++j)
    for (int i = -2; i <= 2; ++i) {
      if ((onPlane & (1u << uint((i + 2) + 5 * (j + 2)))) == 0u) continue;
      ivec2 local = centre + ivec2(i, j) * kMomentsStride;
      float l = sLuminance[local.y][local.x];
      sum += vec2(l, l * l);
      count += 1.0f;
    }
  return sum / max(count, 1.0f);
}

// How far (a fraction of viewZ) last frame's depth may lie from where this
// frame's surface was: REBLUR's threshold (a fraction of the frustum's
// width, plus a pixel and the jitter's change), wider where the surface is
// seen at a grazing angle and where the camera barely moves
// (shared/denoise_weights.glsl, disocclusionReach).
float disocclusionTolerance(Surface x) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  ScreenView view = gIn_Frame.frame.view, previous = gIn_Frame.frame.previousView;
  vec2 size = fullSize();
  vec3 camera = viewPosition(view);
  // The camera's parallax: where last frame's camera saw the point, against
  // where it would have from this frame's position.
  vec3 fromHere = x.position + (viewPosition(previous) - camera);
  float parallax = length(vec2(projectToScreen(previous, fromHere, size)) - vec2(projectToScreen(previous, x.position, size)));
  vec2 jitterChange = abs(view.projection.zw - previous.projection.zw);
  float threshold = d.disocclusionThreshold + (1.0f + max(jitterChange.x, jitterChange.y)) / size.y;
  float cosView = dot(x.normal, normalize(camera - x.position));
  float frustumWidth = 2.0f * view.projection.y * min(size.x, size.y) / size.y;  // per unit of viewZ
  return frustumWidth * disocclusionReach(threshold, cosView, parallax);
}

// The surface's curvature along its motion (REBLUR's estimate): from the
// neighbour as many pixels along the motion as the surface moved (at most
// kCurvatureReach), where that neighbour lies on the surface (depth within
// kCurvatureDepthError), else from the next pixel along it; 0 where
// neither does. A still surface looks along x.
const float kCurvatureReach = 8.0f;
const float kCurvatureDepthError = 0.1f;

float curvatureAlongMotion(Surface x, ivec2 pixel, vec2 motion) {
  float moved = length(motion);
  vec2 direction = moved > 1e-3f ? motion / moved : vec2(1.0f, 0.0f);
  for (int attempt = 0; attempt < 2; ++attempt) {
    float reach = attempt == 0 ? clamp(moved, 1.0f, kCurvatureReach) : 1.0f;
    ivec2 tap = pixel + ivec2(round(direction * reach));
    if (!insideFull(tap) || tap == pixel) continue;
    Surface y = denoiseSurface(tap);
    if (y.viewZ > 0.0f && abs(y.viewZ - x.viewZ) < kCurvatureDepthError * max(x.viewZ, y.viewZ))
      return surfaceCurvature(x.position, x.normal, y.position, y.normal);
  }
  return 0.0f;
}

// Where last frame's camera saw this pixel's reflection (REBLUR's virtual
// motion): through the thin lens of the surface's curvature, at the GGX
// lobe's dominant factor. Where the curved estimate travels more than 3x
// the surface's own motion (a curvature misread at an edge, or a surface
// too curved for one estimate), the flat mirror's point is used, as
// REBLUR's curvature correction does.
vec3 reflectionReprojection(Surface x, ivec2 pixel, vec2 motion, float curvature, float roughness,
                            float hitDistance) {
  float dominantFactor = ggxDominantFactor(roughness * roughness);
  vec3 projected = virtualReprojection(x, hitDistance, curvature, dominantFactor);
  vec2 surfaceThere = vec2(pixel) + 0.5f + motion;
  if (curvature != 0.0f && length(projected.xy - surfaceThere) > 3.0f * length(motion) + 0.01f)
    projected = virtualReprojection(x, hitDistance, 0.0f, dominantFactor);
  return projected;
}

// Where last frame's surface history lies for the pixel: the Catmull-Rom
// footprint's taps that show the surface (none where the pixel cannot be
// reprojected), and what the reflection's reprojection of a specular
// signal needs.
struct Reprojection {
  bool usable;  // the motion is usable
  bool surfaceSeen;  // the previous camera saw the surface in front of it: the footprint holds
  HistoryFootprint footprint;
  vec2 motion;
  uint material;
  bool curvatureKnown;
  float curvature;
};

// One signal's value of the frame, history and moments at the pixel.
void accumulate(uint slot, ivec2 pixel, Surface x, float roughness, uint onPlane, INOUT(Reprojection) reprojection) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  vec4 signal = gIn_SignalAt(slot, pixel);
  vec3 current = sanitizeRadiance(signal.xyz);
  vec2 neighbourhood = neighbourhoodMoments(slot, onPlane);

  History history = noHistory();
  float virtualShare = 0.0f;
  if (signalHasHistory(slot) && reprojection.usable) {
    if (reprojection.surfaceSeen) history = catmullRomHistory(slot, reprojection.footprint);
    if (specularKind(slot)) {
      if (!reprojection.curvatureKnown) {
        reprojection.curvature = curvatureAlongMotion(x, pixel, reprojection.motion);
        reprojection.curvatureKnown = true;
      }
      vec3 projected = reflectionReprojection(x, pixel, reprojection.motion, reprojection.curvature, roughness,
                                              max(finiteOr(signal.w, 0.0f), 0.0f));
      History virtualHistory =
          fetchVirtualHistory(slot, x, projected, d.depthTolerance, d.cosNormalTolerance, reprojection.material);
      float deviation = sqrt(max(neighbourhood.y - neighbourhood.x * neighbourhood.x, 0.0f));
      history = blendReflectionHistories(history, virtualHistory, roughness, neighbourhood.x, deviation, virtualShare);
    }
  }
  float historyLength = history.found ? historyAfterLightChange(history.frames) : 0.0f;
  float frames = min(historyLength + 1.0f, maxFrames(slot, roughness));
  float blend = 1.0f / frames;
  vec3 moments = vec3(neighbourhood, neighbourhood.x);
  vec3 previous = vec3(0.0f);
  if (historyLength > 0.0f) {
    moments = history.moments;
    previous = clampToFastHistory(history.radiance, moments, neighbourhood, blend, d.clampSigma);
    // Anti-lag: where the fast history has left the long one by more than
    // its own noise, the light changed (or is still building up, as in the
    // first frames of multi-bounce light): the history counts as fewer
    // frames, so this frame weighs more.
    float sigma = sqrt(max(moments.y - moments.x * moments.x, 0.0f));
    float noise = kAntiLagSigmas * sigma * inversesqrt(kMomentsSamples) + 1e-3f * moments.x + 1e-6f;
    float excess = max(abs(moments.z - moments.x) - noise, 0.0f) / noise;
    frames = max(1.0f, frames / (1.0f + excess));
    blend = 1.0f / frames;
    if (!pixelHasSample(slot, pixel)) blend *= mix(1.0f - kCheckerboardResolveAccumSpeed, 1.0f, blend);
  }
  gOut_AccumulatedStore(slot, pixel, roundedToHalf(vec4(sanitizeRadiance(mix(previous, current, blend)), frames)));
  gOut_MomentsStore(slot, pixel, roundedToHalf(storedMoments(finiteOr(moments, vec3(0.0f)), virtualShare)));
}

void main() {
  uint slot = workgroupSlot();
  ivec2 pixel = workgroupOrigin() + ivec2(gl_LocalInvocationID.xy);
  // A workgroup lies inside one 16x16 tile: an empty tile leaves it whole,
  // before the shared load.
  if (tileEmpty(pixel)) {
    if (insideFull(pixel)) {
      gOut_AccumulatedStore(slot, pixel, vec4(0.0f));
      gOut_MomentsStore(slot, pixel, vec4(0.0f));
    }
    return;
  }
  loadNeighbourhood(slot);
  if (!insideFull(pixel)) return;
  float roughness;
  Surface x = denoiseSurfaceRoughness(pixel, roughness);
  if (x.viewZ <= 0.0f) {
    gOut_AccumulatedStore(slot, pixel, vec4(0.0f));
    gOut_MomentsStore(slot, pixel, vec4(0.0f));
    return;
  }
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  uint onPlane = neighbourhoodOnPlane(x);
  Reprojection reprojection;
  reprojection.motion = signalHasHistory(slot) ? motionAt(pixel) : vec2(0.0f);
  reprojection.usable = signalHasHistory(slot) && usableMotion(reprojection.motion);
  reprojection.surfaceSeen = false;
  reprojection.curvatureKnown = false;
  reprojection.curvature = 0.0f;
  reprojection.material = 0u;
  if (reprojection.usable) {
    reprojection.material = materialOf(imageLoad(gIn_Surface, pixel).xy);
    float expectedViewZ = projectToScreen(gIn_Frame.frame.previousView, x.position, fullSize()).z;
    reprojection.surfaceSeen = expectedViewZ > 0.0f;
    if (reprojection.surfaceSeen)
      reprojection.footprint = catmullRomFootprint(
          vec2(pixel) + reprojection.motion,
          ExpectedSurface(x.position, x.normal, expectedViewZ, disocclusionTolerance(x), d.cosNormalTolerance,
                          reprojection.material));
  }
  accumulate(slot, pixel, x, roughness, onPlane, reprojection);
}
