// What every pass of the denoiser (gi/denoise, after NVIDIA's REBLUR, as the
// REBLUR analysis reads it) shares: its constants (binding 3,
// gIn_DenoiseConstants), filled from gi::DenoiseSettings by
// src/gi/denoise/denoiser.cpp and laid out alike in GLSL (std140) and C++;
// the signals a pass runs for (push constants: per slot the signal's kind,
// which sets the weights, radii and motion, its flags and its index; each
// signal radiance in xyz, hit distance in world units in w, 0 where
// unknown) and the per-signal images of a pass (DENOISE_SLOT_IMAGES);
// REBLUR's hit-distance normalisation and the edge-stopping weights of its
// spatial passes (shared/denoise_weights.glsl); which pixels of a
// checkerboarded signal hold samples (shared/checkerboard.glsl); with
// DENOISE_READS_TILES, the tiles and the packed surfaces the passes read
// in place of the engine's G-buffer. The including shader includes
// gi/gi_common.glsl first (and gi/gbuffer.glsl where it reads the
// engine's G-buffer: the validation view); its own resources start at
// binding 5 (4: the tiles, 15: the packed surfaces, 16: the light change),
// its per-signal images at 20, four bindings each.
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
// The signals one dispatch of a stage takes (the push constants' slots).
const uint kDenoiseSlots = 4u;
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
// Each stage runs once for all the signals (but the validation view, which
// defines DENOISE_VIEW_PASS): one dispatch takes up to kDenoiseSlots of
// them (the denoiser batches more), each in a slot of the pass's
// per-signal images (DENOISE_SLOT_IMAGES), and every invocation works its
// pixel of each signal in turn, sharing what the signals share (the
// pixel's surface, the reprojection's taps); temporal accumulation instead
// gives each signal its own workgroups. Per slot: the signal's kind,
// flags and index; for the pass, the count of slots in use and the blur
// passes' radius scale.
layout(push_constant) uniform SignalParams {
  uvec4 kinds;        // kSignalKindDiffuse or kSignalKindSpecular
  uvec4 flags;        // kSignalHasHistory, kSignalCheckerboard
  uvec4 indices;      // the signal's index among the denoiser's: its kernels rotate apart from the others'
  uint count;         // slots in use, 1..kDenoiseSlots
  float radiusScale;  // of the blur passes' radius
} gSignals;

bool specularKind(uint slot) { return gSignals.kinds[slot] == kSignalKindSpecular; }
// Whether last frame's history of this signal may be reprojected: not on a
// cut or the first frame, nor on the first frame an engine gives a signal
// after a frame without it.
bool signalHasHistory(uint slot) { return (gSignals.flags[slot] & kSignalHasHistory) != 0u; }

// Checkerboard mode (gi.denoise.checkerboard, an engine's signal only):
// whether this slot's signal came with every other pixel, and whether
// `pixel` holds a sample of it this frame (the others the pre-pass
// reconstructs). The parity follows the kind and FrameInputs::frameIndex,
// as the engine's does. Any other signal has a sample everywhere.
bool signalCheckerboarded(uint slot) { return (gSignals.flags[slot] & kSignalCheckerboard) != 0u; }
bool pixelHasSample(uint slot, ivec2 pixel) {
  if (!signalCheckerboarded(slot)) return true;
  return checkerboardHasData(uvec2(pixel), gIn_Frame.frame.frameIndex, checkerboardParityOfKind(specularKind(slot)));
}

// A per-signal image of a pass: NAME0..NAME3 (rgba16f), one binding per
// slot from FIRST on. A slot not in use is bound to a 1x1 filler image the
// pass never touches. NAME##At(slot, pixel) loads (DENOISE_SLOT_LOAD) and
// NAME##Store(slot, pixel, value) stores (DENOISE_SLOT_STORE) the slot's.
#define DENOISE_SLOT_IMAGES(QUALIFIER, NAME, FIRST)                                    \
  layout(set = 0, binding = FIRST, rgba16f) QUALIFIER uniform image2D NAME##0;       \
  layout(set = 0, binding = FIRST + 1, rgba16f) QUALIFIER uniform image2D NAME##1;   \
  layout(set = 0, binding = FIRST + 2, rgba16f) QUALIFIER uniform image2D NAME##2;   \
  layout(set = 0, binding = FIRST + 3, rgba16f) QUALIFIER uniform image2D NAME##3;
#define DENOISE_SLOT_LOAD(NAME)                     \
  vec4 NAME##At(uint slot, ivec2 pixel) {           \
    switch (slot) {                                 \
      case 0u: return imageLoad(NAME##0, pixel);    \
      case 1u: return imageLoad(NAME##1, pixel);    \
      case 2u: return imageLoad(NAME##2, pixel);    \
      default: return imageLoad(NAME##3, pixel);    \
    }                                               \
  }
// A per-signal image a pass samples (DENOISE_SLOT_TEXTURES: NAME0..NAME3,
// bound with the context's texel-coordinate bilinear sampler,
// gpu::Context::texelLinearSampler): NAME##At(slot, pixel) reads a texel,
// NAME##Linear(slot, position) filters bilinearly at a continuous
// texel-space position (texel centres at integers) in one fetch
// (DENOISE_SLOT_SAMPLE). Texel coordinates keep a fetch the same whatever
// size the image was made for.
#define DENOISE_SLOT_TEXTURES(NAME, FIRST)                             \
  layout(set = 0, binding = FIRST) uniform sampler2D NAME##0;        \
  layout(set = 0, binding = FIRST + 1) uniform sampler2D NAME##1;    \
  layout(set = 0, binding = FIRST + 2) uniform sampler2D NAME##2;    \
  layout(set = 0, binding = FIRST + 3) uniform sampler2D NAME##3;
#define DENOISE_SLOT_SAMPLE(NAME)                                          \
  vec4 NAME##At(uint slot, ivec2 pixel) {                                  \
    switch (slot) {                                                        \
      case 0u: return texelFetch(NAME##0, pixel, 0);                       \
      case 1u: return texelFetch(NAME##1, pixel, 0);                       \
      case 2u: return texelFetch(NAME##2, pixel, 0);                       \
      default: return texelFetch(NAME##3, pixel, 0);                       \
    }                                                                      \
  }                                                                        \
  vec4 NAME##Linear(uint slot, vec2 position) {                            \
    switch (slot) {                                                        \
      case 0u: return textureLod(NAME##0, position + 0.5f, 0.0f);          \
      case 1u: return textureLod(NAME##1, position + 0.5f, 0.0f);          \
      case 2u: return textureLod(NAME##2, position + 0.5f, 0.0f);          \
      default: return textureLod(NAME##3, position + 0.5f, 0.0f);          \
    }                                                                      \
  }
#define DENOISE_SLOT_STORE(NAME)                             \
  void NAME##Store(uint slot, ivec2 pixel, vec4 value) {     \
    switch (slot) {                                          \
      case 0u: imageStore(NAME##0, pixel, value); break;     \
      case 1u: imageStore(NAME##1, pixel, value); break;     \
      case 2u: imageStore(NAME##2, pixel, value); break;     \
      default: imageStore(NAME##3, pixel, value); break;     \
    }                                                        \
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
// How a pixel weighs its neighbours for one signal, worked out once per
// pixel: for a pixel (surface x, its roughness) with `frames` of history,
// a neighbour counts on its plane, inside its lobe (kind diffuse:
// roughness 1), of a like roughness (specular only); the cone and the
// roughness reach `widening` times wider (the pre-pass's 2).
struct NeighbourWeighting {
  Surface x;
  float roughness;
  float halfAngle;       // of the normal cone, radians
  float roughnessReach;  // the roughness weight's reach, a fraction of the roughness
  bool specular;
};

NeighbourWeighting neighbourWeighting(uint slot, Surface x, float roughness, float frames, float widening) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  NeighbourWeighting n;
  n.x = x;
  n.roughness = roughness;
  n.specular = specularKind(slot);
  n.halfAngle =
      lobeHalfAngle(n.specular ? roughness : 1.0f, d.lobeAngleFraction, 1.0f / (1.0f + frames)) * widening;
  n.roughnessReach = d.roughnessFraction * widening;
  return n;
}

// How much neighbour y (its roughness) counts towards the pixel's average.
float neighbourWeight(NeighbourWeighting n, Surface y, float neighbourRoughness) {
  if (y.viewZ <= 0.0f) return 0.0f;
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  float w = planeWeight(n.x.normal, n.x.position, y.position, n.x.viewZ, d.planeDistanceSensitivity) *
            normalWeight(n.x.normal, y.normal, n.halfAngle);
  if (n.specular) w *= roughnessWeight(n.roughness, neighbourRoughness, n.roughnessReach);
  return w;
}

// A pixel's blur radius (REBLUR's): R sqrt(f / (1 + frames)), wide while
// its history is short; for specular f shrinks with the lobe (a mirror is
// not blurred) and with the hit distance (a contact reflection is sharp).
float blurRadius(uint slot, float frames, float roughness, float normalizedHit) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  float f = specularKind(slot) ? clamp(roughness * 2.0f, 0.0f, 1.0f) * normalizedHit : 1.0f;
  float radius = d.blurRadius * gSignals.radiusScale * sqrt(f / (1.0f + frames));
  return max(radius, d.minBlurRadius * gSignals.radiusScale);
}
#endif

#endif


#endif
