#version 460
#extension GL_GOOGLE_include_directive : require
// viewer.display: the frame as the window shows it. Linear HDR radiance
// (the GI library's composite, or the direct light with GI off) through
// the exposure and the same ACES fit and sRGB encoding the PNGs get
// (shared/color.glsl displayEncode); a pixel that is not finite shows
// magenta, as in the PNGs. Split screen: columns from splitColumn on show
// gIn_Right instead (GI off, or the progressive reference), with a
// one-pixel grey line between. The window then blits this image.
#include "shared/color.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D gIn_Frame;
layout(set = 0, binding = 1) uniform sampler2D gIn_Right;
layout(set = 0, binding = 2, rgba8) writeonly uniform image2D gOut_Display;

layout(push_constant) uniform DisplayParams {
  uint width;
  uint height;
  float exposure;
  uint splitColumn;  // width: no split
} gParams;

// As the PNG writer: radiance above this (times the exposure) is clamped
// first, so the ACES fit never sees an overflowing square.
const float kTonemapInputLimit = 1.0e6f;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= int(gParams.width) || pixel.y >= int(gParams.height)) return;
  if (pixel.x == int(gParams.splitColumn) && gParams.splitColumn < gParams.width) {
    imageStore(gOut_Display, pixel, vec4(0.5f, 0.5f, 0.5f, 1.0f));
    return;
  }
  vec3 radiance = pixel.x > int(gParams.splitColumn) ? texelFetch(gIn_Right, pixel, 0).xyz
                                                      : texelFetch(gIn_Frame, pixel, 0).xyz;
  bool finite = !any(isnan(radiance)) && !any(isinf(radiance));
  vec3 shown = finite ? displayEncode(min(radiance, vec3(kTonemapInputLimit / gParams.exposure)), gParams.exposure)
                      : vec3(1.0f, 0.0f, 1.0f);
  imageStore(gOut_Display, pixel, vec4(shown, 1.0f));
}
