// Deterministic randomness: every random number is a pure function of
// (pixel, frame, pass, draw index), so the same command renders the same bits
// on every device and in CPU tests.
#ifndef BOUNCE_SHARED_RNG_GLSL
#define BOUNCE_SHARED_RNG_GLSL
#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

// PCG hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 2020):
// the best quality-per-instruction 32-bit hash in their survey.
uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Seed for one (pixel, frame, pass): nesting the hash decorrelates each input,
// which a plain sum or xor would not (pixel (1,0) would equal pixel (0,1)).
uint rngSeed(uvec2 pixel, uint frame, uint passId) {
  return pcgHash(pixel.x + pcgHash(pixel.y + pcgHash(frame + pcgHash(passId))));
}

// Advances the state (a PCG-RXS-M-XS step) and returns 32 random bits.
uint rngNext(INOUT(uint) state) {
  state = state * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Uniform float in [0, 1): the top 24 bits, so every value is exact in float
// and 1.0 is never returned.
float rngUniform(INOUT(uint) state) {
  return float(rngNext(state) >> 8u) * (1.0f / 16777216.0f);
}

BOUNCE_SHARED_END
#endif
