// The denoiser's checkerboard input (gi.denoise.checkerboard; NRD REBLUR's
// checkerboard mode, the REBLUR analysis, §3.2.2): an engine traces every other pixel
// of each row, alternating from row to row and from frame to frame, and
// hands the samples packed into an image half as wide. Which pixel holds a
// sample, and where it is stored, are decided here once for the library's
// shaders, the bounce command's packing pass and the tests (one source for
// GLSL and C++, lang.glsl; tests/test_shared_math.cpp checks it on the CPU).
#ifndef BOUNCE_SHARED_CHECKERBOARD_GLSL
#define BOUNCE_SHARED_CHECKERBOARD_GLSL

#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

// The parity of pixel (x, y) in frame `frameIndex`: REBLUR's
// CheckerBoard(samplePos, frameIndex) = ((x ^ y) ^ frameIndex) & 1, the
// parity of x + y + frameIndex.
uint checkerboardParity(uvec2 pixel, uint frameIndex) { return ((pixel.x ^ pixel.y) ^ frameIndex) & 1u; }

// Which parity holds each signal's samples: NRD's CheckerboardMode::WHITE
// (diffCheckerboard 1, specCheckerboard 0). The two signals take opposite
// pixels, so an engine that traces one ray a pixel for either signal
// covers every pixel each frame.
const uint kCheckerboardDiffuseParity = 1u;
const uint kCheckerboardSpecularParity = 0u;

// The parity of a signal by its kind (gi::SignalKind): diffuse-kind
// signals take the diffuse parity, specular-kind the specular one.
uint checkerboardParityOfKind(bool specularKind) {
  return specularKind ? kCheckerboardSpecularParity : kCheckerboardDiffuseParity;
}

// Whether the engine's checkerboarded signal of parity `dataParity` holds a
// sample of pixel (x, y) in frame `frameIndex`.
bool checkerboardHasData(uvec2 pixel, uint frameIndex, uint dataParity) {
  return checkerboardParity(pixel, frameIndex) == dataParity;
}

// The column of the half-width image that holds pixel (x, y)'s sample: x / 2
// (each row's pixels with data are every other one, so no two share it).
uint checkerboardPackedColumn(uint x) { return x >> 1u; }

// The width of the packed image of a frame `width` pixels wide.
uint checkerboardPackedWidth(uint width) { return (width + 1u) >> 1u; }

// The hit distance that marks a pixel without a sample once the library has
// unpacked the signal to full width (gi.engine_signal.SIGNAL's output):
// a real one is never negative.
const float kCheckerboardNoSample = -1.0f;

BOUNCE_SHARED_END
#endif
