#version 460
#extension GL_GOOGLE_include_directive : require
// gi.composite: the frame: direct light + base colour * (1 - metallic) *
// indirect diffuse (+ emission when the engine gives it apart). Background
// pixels keep the direct image's sky. This HDR frame is what the next
// frame's gathering samples, so what it stores is finite: non-finite direct
// light or emission counts as none, and the sum saturates at the largest
// half float.
#include "gi/gi_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1, r32f) readonly uniform image2D gIn_ViewZ;
layout(set = 0, binding = 2, rgba16f) readonly uniform image2D gIn_Direct;
layout(set = 0, binding = 3, rgba8) readonly uniform image2D gIn_BaseColorMetallic;
layout(set = 0, binding = 4, rgba16f) readonly uniform image2D gIn_Emissive;
layout(set = 0, binding = 5, rgba16f) readonly uniform image2D gIn_IndirectDiffuse;
layout(set = 0, binding = 6, rgba16f) writeonly uniform image2D gOut_Composite;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  vec3 radiance = sanitizeRadiance(imageLoad(gIn_Direct, pixel).xyz);
  if (usableViewZ(imageLoad(gIn_ViewZ, pixel).x) > 0.0f) {
    vec4 baseColorMetallic = imageLoad(gIn_BaseColorMetallic, pixel);
    radiance += baseColorMetallic.xyz * (1.0f - baseColorMetallic.w) * imageLoad(gIn_IndirectDiffuse, pixel).xyz;
    if (gIn_Frame.frame.options.y != 0u) radiance += sanitizeRadiance(imageLoad(gIn_Emissive, pixel).xyz);
  }
  imageStore(gOut_Composite, pixel, vec4(sanitizeRadiance(radiance), 1.0f));
}
