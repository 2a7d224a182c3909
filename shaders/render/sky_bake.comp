#version 460
#extension GL_GOOGLE_include_directive : require
// render.sky_bake: the procedural sky (shared/sky.glsl) into the top level of
// the environment's source image, one equirect texel per thread, evaluated
// at the texel's centre. No sun disk: the sun is a directional light. A sky
// brighter than a half float saturates at its largest finite value.
#include "shared/equirect.glsl"
#include "shared/finite.glsl"
#include "shared/sky.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, rgba16f) writeonly uniform image2D gOut_Sky;

layout(push_constant) uniform Params { SkyParams sky; } params;

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(gOut_Sky);
  if (texel.x >= size.x || texel.y >= size.y) return;
  vec3 direction = equirectDirection((vec2(texel) + 0.5f) / vec2(size));
  imageStore(gOut_Sky, texel, vec4(sanitizeRadiance(skyRadiance(params.sky, direction)), 1.0f));
}
