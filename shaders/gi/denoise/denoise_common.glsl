// What every pass of the denoiser (gi/denoise, after NVIDIA's REBLUR, as the
// REBLUR analysis reads it) shares: its constants (binding 3, gIn_DenoiseConstants), filled from
// gi::DenoiseSettings by src/gi/denoise/denoiser.cpp and laid out alike in
// GLSL (std140) and C++; the signal a pass runs for (push constants: its
// kind, which sets the weights, radii and motion, and its slot among the
// signals; radiance in xyz, hit distance in world units in w, 0 where
// unknown); REBLUR's hit-distance normalisation and the edge-stopping
// weights of its spatial passes (shared/denoise_weights.glsl); which pixels
// of a checkerboarded signal hold samples (shared/checkerboard.glsl); with
// DENOISE_READS_TILES, the tiles and the packed surfaces the per-signal
// passes read in place of the engine's G-buffer. The including shader
// includes gi/gi_common.glsl first (and gi/gbuffer.glsl where it reads the
// engine's G-buffer: the validation view); its own resources start at
// binding 5 (4: the tiles, 15: the packed surfaces).
#ifndef BOUNCE_GI_DENOISE_COMMON_GLSL
#define BOUNCE_GI_DENOISE_COMMON_GLSL

#ifdef __cplusplus
#include "shared/lang.glsl"
namespace bounce::shared {
#endif

struct DenoiseConstants {
  vec4 hitDistanceParameters;       // REBLUR's A, B, C, D (first: std140 aligns a vec4 to 16 bytes)
  float maxAccumulatedFrames;       // the longest history (REBLUR: 30)
  float historyFixFrames;           // below this history length, history fix rebuilds the pixel (REBLUR: 3)
  float historyFixStride;           // pixels between history fix's taps
  float blurRadius;                 // pixels, at the first frame of a history
  float postBlurRadiusScale;        // post-blur's radius, as a fraction of blur's
  float minBlurRadius;              // pixels, however long the history
  float planeDistanceSensitivity;   // a tap off the pixel's plane by this fraction of viewZ weighs 0
  float lobeAngleFraction;          // the normal weight's reach, as a fraction of the lobe's half angle
  float roughnessFraction;          // the roughness weight's reach, as a fraction of the roughness
  float stabilizationFrames;        // temporal stabilisation's longest history (0: off)
  float clampSigma;                 // history clamping: fast history mean +- this many sigma
  float depthTolerance;             // stabilisation and reflection (virtual) reprojection: fraction of viewZ
  float cosNormalTolerance;         // temporal reprojection
  float disocclusionThreshold;      // temporal accumulation: REBLUR's, a fraction of the frustum's width
  uint frameIndex;                  // rotates the blur kernels
  uint antiFirefly;                 // history fix clamps outliers to their neighbourhood
  float diffusePrePassRadius;       // pixels (scaled with the height); 0: no pre-pass (but in checkerboard mode)
  float specularPrePassRadius;      // the same for signals of kind specular
};

// A signal's kind (gi::SignalKind): which weights, radii and motion apply.
const uint kSignalKindDiffuse = 0u;
const uint kSignalKindSpecular = 1u;
// Bits of a signal's flags (push constants).
const uint kSignalHasHistory = 1u;    // last frame's history of this signal may be reprojected (else: a cut)
const uint kSignalCheckerboard = 2u;  // an engine's signal with samples at every other pixel

#ifdef __cplusplus
}  // namespace bounce::shared
#else
#include "shared/checkerboard.glsl"
#include "shared/denoise_weights.glsl"
#include "shared/packing.glsl"

layout(set = 0, binding = 3, std140) CONSTANT_BLOCK DenoiseBlock { DenoiseConstants denoise; } gIn_DenoiseConstants;

#ifndef DENOISE_VIEW_PASS
// Each pass runs once per signal (but the validation view, which defines
// DENOISE_VIEW_PASS): which one (its kind, its slot among the signals, its
// flags) and the pass's radius scale.
layout(push_constant) uniform SignalParams {
  uint slot;          // the signal's index: its kernels rotate apart from the other signals'
  uint kind;          // kSignalKindDiffuse or kSignalKindSpecular
  uint flags;         // kSignalHasHistory, kSignalCheckerboard
  float radiusScale;  // of the blur passes' radius
} gSignal;

bool specularKind() { return gSignal.kind == kSignalKindSpecular; }
// Whether last frame's history of this signal may be reprojected: not on a
// cut or the first frame, nor on the first frame an engine gives a signal
// after a frame without it.
bool signalHasHistory() { return (gSignal.flags & kSignalHasHistory) != 0u; }

// Checkerboard mode (gi.denoise.checkerboard, an engine's signal only):
// whether this pass's signal came with every other pixel, and whether
// `pixel` holds a sample of it this frame (the others the pre-pass
// reconstructs). The parity follows the kind and FrameInputs::frameIndex,
// as the engine's does. Any other signal has a sample everywhere.
bool signalCheckerboarded() { return (gSignal.flags & kSignalCheckerboard) != 0u; }
bool pixelHasSample(ivec2 pixel) {
  if (!signalCheckerboarded()) return true;
  return checkerboardHasData(uvec2(pixel), gIn_Frame.frame.frameIndex, checkerboardParityOfKind(specularKind()));
}
#endif

#ifdef DENOISE_READS_TILES
// 1 where a 16x16 tile holds a surface (gi.denoise.classify_tiles).
layout(set = 0, binding = 4, r16f) readonly uniform image2D gIn_Tiles;
const int kDenoiseTile = 16;
bool tileEmpty(ivec2 pixel) { return imageLoad(gIn_Tiles, pixel / kDenoiseTile).x == 0.0f; }

// This frame's surfaces as gi.denoise.classify_tiles packed them: one load
// a tap (the engine's G-buffer is two). viewZ 0 where the pixel has no
// usable surface (and outside the image).
layout(set = 0, binding = 15, rg32ui) readonly uniform uimage2D gIn_DenoiseSurface;

Surface denoiseSurfaceRoughness(ivec2 pixel, out float roughness) {
  uvec2 packed = imageLoad(gIn_DenoiseSurface, pixel).xy;
  float viewZ = uintBitsToFloat(packed.x);
  bool some = viewZ > 0.0f;
  roughness = some ? unpackRoughnessOfNormalRoughness(packed.y) : 1.0f;
  return surfaceAt(gIn_Frame.frame.view, pixel, some ? viewZ : 0.0f,
                   some ? unpackNormalOfNormalRoughness(packed.y) : vec3(0.0f, 0.0f, 1.0f));
}

Surface denoiseSurface(ivec2 pixel) {
  float roughness;
  return denoiseSurfaceRoughness(pixel, roughness);
}

float denoiseDepth(ivec2 pixel) { return max(uintBitsToFloat(imageLoad(gIn_DenoiseSurface, pixel).x), 0.0f); }
#endif

#ifndef DENOISE_VIEW_PASS
// How much a neighbour (its surface and roughness) counts towards the
// average of a pixel with `frames` of history: on its plane, inside its
// lobe (kind diffuse: roughness 1), of a like roughness (specular only); the
// cone and the roughness reach `widening` times wider (the pre-pass's 2).
float neighbourWeightWidened(Surface x, float roughness, float frames, Surface y, float neighbourRoughness,
                             float widening) {
  if (y.viewZ <= 0.0f) return 0.0f;
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  bool specular = specularKind();
  float halfAngle = lobeHalfAngle(specular ? roughness : 1.0f, d.lobeAngleFraction, 1.0f / (1.0f + frames));
  float w = planeWeight(x.normal, x.position, y.position, x.viewZ, d.planeDistanceSensitivity) *
            normalWeight(x.normal, y.normal, halfAngle * widening);
  if (specular) w *= roughnessWeight(roughness, neighbourRoughness, d.roughnessFraction * widening);
  return w;
}

float neighbourWeight(Surface x, float roughness, float frames, Surface y, float neighbourRoughness) {
  return neighbourWeightWidened(x, roughness, frames, y, neighbourRoughness, 1.0f);
}

// A pixel's blur radius (REBLUR's): R sqrt(f / (1 + frames)), wide while
// its history is short; for specular f shrinks with the lobe (a mirror is
// not blurred) and with the hit distance (a contact reflection is sharp).
float blurRadius(float frames, float roughness, float normalizedHit) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  float f = specularKind() ? clamp(roughness * 2.0f, 0.0f, 1.0f) * normalizedHit : 1.0f;
  float radius = d.blurRadius * gSignal.radiusScale * sqrt(f / (1.0f + frames));
  return max(radius, d.minBlurRadius * gSignal.radiusScale);
}
#endif

#endif


#endif
