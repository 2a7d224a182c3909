// Push constants of the reference path tracer's passes, laid out identically
// in GLSL and C++ (scalars only, 4 bytes each, no padding rules to differ).
#ifndef BOUNCE_RENDER_REFERENCE_TYPES_GLSL
#define BOUNCE_RENDER_REFERENCE_TYPES_GLSL

#include "shared/lang.glsl"

#ifdef __cplusplus
namespace bounce::shared {
#endif

// Which lobes of the material the path tracer follows. kLobesAll is the
// material; the single lobes make closed-form tests possible (a furnace of
// pure Lambert or pure mirror reflection).
const uint kLobeDiffuse = 1u;
const uint kLobeSpecular = 2u;
const uint kLobesAll = 3u;

// The hit distance a path's first ray that escaped to the environment
// counts as: beyond any scene, and within a half float (the GI library
// reads hit distances from rgba16f images).
const float kEscapedHitDistance = 1.0e4f;

struct ReferencePathParams {
  uint sampleBase;          // samples drawn before the sums were last cleared (ReferenceRenderer::restart)
  uint firstSample;         // index of this dispatch's first sample since then (its parity: the half it adds to);
                            // sampleBase + firstSample numbers the sample, which decorrelates every one
  uint sampleCount;         // samples per pixel in this dispatch
  uint seed;                // the user's seed: another seed, other (independent) noise
  uint maxBounces;          // surfaces a path may bounce off after the primary hit
  uint rouletteBounces;     // Russian roulette from this bounce on
  uint lobes;               // kLobeDiffuse | kLobeSpecular
  uint environmentWidth;    // environment distribution cells; 0 = no environment light
  uint environmentHeight;
  uint emissiveCount;       // emissive triangles; 0 = none
  float emissivePower;      // their summed luminance * area
};

struct ReferenceResolveParams {
  float weightA;  // 1 / samples, for the accumulators of half A (0: leave the half out)
  float weightB;  // the same for half B
};

#ifdef __cplusplus
}  // namespace bounce::shared
#endif

#endif
