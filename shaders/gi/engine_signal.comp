#version 460
#extension GL_GOOGLE_include_directive : require
// gi.engine_signal.SIGNAL: a noisy signal of the engine's own
// (FrameInputs::noisyDiffuse, noisySpecular) taken into the library's
// storage, where the denoiser reads it as it reads a branch's resolved
// signal: rgba16f, full resolution, demodulated radiance in rgb, hit
// distance in alpha. The engine's image is sampled (either format of its
// family) and trusted in nothing: non-finite radiance is no light and
// finite radiance is clamped to [0, largest half] (sanitizeRadiance, as
// every pass reads radiance); a hit distance that is not a finite positive
// number is unknown (0), and one beyond the largest half is that (it reads
// as "far" all the same).
// Checkerboard mode (gi.denoise.checkerboard, gParams.checkerboard): the
// engine's image is half as wide and holds only the pixels of the signal's
// parity (shared/checkerboard.glsl), pixel (x, y) at (x / 2, y). Those are
// unpacked to their place; every other pixel is written as no sample
// (radiance 0, hit distance kCheckerboardNoSample), which the denoiser's
// pre-pass fills from its neighbours.
#include "gi/gi_common.glsl"
#include "shared/checkerboard.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D gIn_Noisy;
layout(set = 0, binding = 2, rgba16f) writeonly uniform image2D gOut_Signal;

layout(push_constant) uniform EngineSignalParams {
  uint checkerboard;  // 1: the engine's image is checkerboarded and packed to half width
  uint dataParity;    // its pixels with samples: kCheckerboardDiffuseParity or kCheckerboardSpecularParity
} gParams;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  ivec2 source = pixel;
  if (gParams.checkerboard != 0u) {
    if (!checkerboardHasData(uvec2(pixel), gIn_Frame.frame.frameIndex, gParams.dataParity)) {
      imageStore(gOut_Signal, pixel, vec4(vec3(0.0f), kCheckerboardNoSample));
      return;
    }
    source.x = int(checkerboardPackedColumn(uint(pixel.x)));
  }
  vec4 noisy = texelFetch(gIn_Noisy, source, 0);
  float hitDistance = isFinite(noisy.w) && noisy.w > 0.0f ? min(noisy.w, kMaxHalf) : 0.0f;
  imageStore(gOut_Signal, pixel, vec4(sanitizeRadiance(noisy.xyz), hitDistance));
}
