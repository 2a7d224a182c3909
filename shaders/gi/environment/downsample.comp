#version 460
#extension GL_GOOGLE_include_directive : require
// gi.environment.downsample: one level of an equirect mip chain from the level
// above it. Each output texel averages the input texels it covers, weighted
// by their solid angle, so the chain keeps the environment's integral (a
// plain box would overweight the rows near the poles). The input is bound as
// a single level; when input and output have the same size this is a copy.
#include "shared/equirect.glsl"
#include "shared/finite.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0) uniform sampler2D gIn_Source;
layout(set = 0, binding = 1, rgba16f) writeonly uniform image2D gOut_Destination;

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 outSize = imageSize(gOut_Destination);
  if (texel.x >= outSize.x || texel.y >= outSize.y) return;
  ivec2 inSize = textureSize(gIn_Source, 0);
  // The input texels whose area overlaps this output texel (sizes need not
  // divide: an odd level's last texel is shared).
  ivec2 begin = (texel * inSize) / outSize;
  ivec2 end = max(((texel + 1) * inSize + outSize - 1) / outSize, begin + 1);
  vec4 sum = vec4(0.0f);
  float weightSum = 0.0f;
  for (int y = begin.y; y < end.y; ++y) {
    float weight = equirectTexelSolidAngle(float(y), float(inSize.x), float(inSize.y));
    for (int x = begin.x; x < end.x; ++x) {
      sum += texelFetch(gIn_Source, ivec2(x, y), 0) * weight;
      weightSum += weight;
    }
  }
  imageStore(gOut_Destination, texel, vec4(sanitizeRadiance((sum / weightSum).xyz), 1.0f));
}
