// Sampling the texture atlas (src/render/texture_atlas.h) by hand: bilinear
// inside each texture's own rectangle with REPEAT wrapping, trilinear
// between mip levels, sRGB decoded per texel before filtering.
//
// The including shader declares, before including this file:
//   #define TEXTURE_ATLAS_BINDING n   (uses bindings n and n + 1)
#ifndef BOUNCE_RENDER_TEXTURE_ATLAS_GLSL
#define BOUNCE_RENDER_TEXTURE_ATLAS_GLSL

#include "shared/color.glsl"
#include "shared/finite.glsl"

layout(set = 0, binding = TEXTURE_ATLAS_BINDING) uniform sampler2DArray gIn_TextureAtlas;
// Per texture: x = page, y = x | y << 16, z = log2 width | log2 height << 8 |
// mip count << 16 | sRGB << 24.
layout(set = 0, binding = TEXTURE_ATLAS_BINDING + 1, std430) readonly buffer TextureAtlasEntries {
  uvec4 items[];
} gIn_TextureAtlasEntries;

vec4 atlasTexel(uvec4 entry, ivec2 origin, ivec2 size, ivec2 texel, bool srgb) {
  ivec2 wrapped = ivec2(uvec2(texel + size * 1024) % uvec2(size));
  vec4 value = texelFetch(gIn_TextureAtlas, ivec3(origin + wrapped, int(entry.x)), 0);
  if (srgb) value.xyz = srgbDecode(value.xyz);
  return value;
}

vec4 atlasBilinear(uvec4 entry, int mip, vec2 uv) {
  int log2W = int(entry.z & 0xffu);
  int log2H = int((entry.z >> 8) & 0xffu);
  bool srgb = ((entry.z >> 24) & 1u) != 0u;
  ivec2 base = ivec2(int(entry.y & 0xffffu), int(entry.y >> 16));
  ivec2 size0 = ivec2(1 << log2W, 1 << log2H);
  ivec2 size = max(size0 >> mip, ivec2(1));
  ivec2 origin = base + (mip == 0 ? ivec2(0) : ivec2(size0.x, size0.y - (size0.y >> (mip - 1))));
  vec2 position = fract(uv) * vec2(size) - 0.5f;
  ivec2 corner = ivec2(floor(position));
  vec2 f = position - vec2(corner);
  vec4 a = atlasTexel(entry, origin, size, corner, srgb);
  vec4 b = atlasTexel(entry, origin, size, corner + ivec2(1, 0), srgb);
  vec4 c = atlasTexel(entry, origin, size, corner + ivec2(0, 1), srgb);
  vec4 d = atlasTexel(entry, origin, size, corner + ivec2(1, 1), srgb);
  return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

// uvLog2Footprint: log2 of the sample's footprint in texture-coordinate units
// (a ray cone's width over the surface, mapped to uv); the mip level follows
// from it and the texture's size. Pass -100 for the sharpest level. uv may be
// outside [0,1] (it repeats); a non-finite uv (broken texture coordinates)
// samples (0,0) rather than spreading NaN.
vec4 sampleAtlas(uint textureIndex, vec2 uv, float uvLog2Footprint) {
  uvec4 entry = gIn_TextureAtlasEntries.items[textureIndex];
  int mipCount = int((entry.z >> 16) & 0xffu);
  uv = finiteOr(uv, vec2(0.0f));
  float texelLod = uvLog2Footprint + 0.5f * float(int(entry.z & 0xffu) + int((entry.z >> 8) & 0xffu));
  // clamp() takes an infinite level to an end of the chain; a NaN, which
  // clamp() may pass through, reads the sharpest level.
  float level = finiteOr(clamp(texelLod, 0.0f, float(mipCount - 1)), 0.0f);
  int lower = int(floor(level));
  int upper = min(lower + 1, mipCount - 1);
  vec4 value = atlasBilinear(entry, lower, uv);
  float t = level - float(lower);
  if (t > 0.0f && upper != lower) value = mix(value, atlasBilinear(entry, upper, uv), t);
  return value;
}

#endif
