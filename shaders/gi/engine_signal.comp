#version 460
#extension GL_GOOGLE_include_directive : require
// gi.engine_signal.SIGNAL: a noisy signal of the engine's own
// (FrameInputs::noisyDiffuse, noisySpecular) taken into the library's
// storage, where the denoiser reads it as it reads a branch's resolved
// signal: rgba16f, demodulated radiance in rgb, hit distance in alpha. The
// engine's image is sampled (either format of its family) and trusted in
// nothing: non-finite radiance is no light and finite radiance is clamped
// to [0, largest half] (sanitizeRadiance, as every pass reads radiance); a
// hit distance that is not a finite positive number is unknown (0), and
// one beyond the largest half is that (it reads as "far" all the same).
#include "gi/gi_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1) uniform sampler2D gIn_Noisy;
layout(set = 0, binding = 2, rgba16f) writeonly uniform image2D gOut_Signal;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  vec4 noisy = texelFetch(gIn_Noisy, pixel, 0);
  float hitDistance = isFinite(noisy.w) && noisy.w > 0.0f ? min(noisy.w, kMaxHalf) : 0.0f;
  imageStore(gOut_Signal, pixel, vec4(sanitizeRadiance(noisy.xyz), hitDistance));
}
