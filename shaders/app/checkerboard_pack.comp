#version 460
#extension GL_GOOGLE_include_directive : require
// denoise.checkerboard_pack.SIGNAL (bounce denoise --checkerboard): what an
// engine in the denoiser's checkerboard mode (gi.denoise.checkerboard)
// hands over, made from a full-resolution signal: in every row the pixels
// of the signal's parity this frame, packed to half width, pixel (x, y) at
// (x / 2, y) (shared/checkerboard.glsl, as the library unpacks them). The
// path tracer traced every pixel; the packed image keeps half of them, the
// samples an engine tracing half the pixels would have.
#include "shared/checkerboard.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, rgba32f) readonly uniform image2D gIn_Full;
layout(set = 0, binding = 1, rgba32f) writeonly uniform image2D gOut_Packed;

layout(push_constant) uniform CheckerboardPackParams {
  uint width;       // of the full signal (the render size)
  uint height;
  uint frameIndex;  // FrameInputs::frameIndex of the frame it is handed over in
  uint dataParity;  // kCheckerboardDiffuseParity or kCheckerboardSpecularParity
} gParams;

void main() {
  uvec2 packedPixel = gl_GlobalInvocationID.xy;
  if (packedPixel.x >= checkerboardPackedWidth(gParams.width) || packedPixel.y >= gParams.height) return;
  // Column c holds pixel 2c or 2c + 1, whichever has the parity (an odd
  // width's last column may hold none: then 0).
  uint x = 2u * packedPixel.x;
  if (!checkerboardHasData(uvec2(x, packedPixel.y), gParams.frameIndex, gParams.dataParity)) x += 1u;
  vec4 value = x < gParams.width ? imageLoad(gIn_Full, ivec2(x, packedPixel.y)) : vec4(0.0f);
  imageStore(gOut_Packed, ivec2(packedPixel), value);
}
