// Packing of normals and pixel coordinates.
#ifndef BOUNCE_SHARED_PACKING_GLSL
#define BOUNCE_SHARED_PACKING_GLSL
#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

float signNotZero(float v) { return v >= 0.0f ? 1.0f : -1.0f; }

// Octahedral mapping of a unit vector to [-1,1]^2 (Cigolle et al. 2014,
// "A Survey of Efficient Representations for Independent Unit Vectors").
vec2 encodeOctahedral(vec3 n) {
  float l1 = abs(n.x) + abs(n.y) + abs(n.z);
  vec2 p = vec2(n.x, n.y) * (1.0f / max(l1, 1e-20f));
  if (n.z < 0.0f) {
    p = vec2((1.0f - abs(p.y)) * signNotZero(p.x), (1.0f - abs(p.x)) * signNotZero(p.y));
  }
  return p;
}

vec3 decodeOctahedral(vec2 e) {
  vec3 n = vec3(e.x, e.y, 1.0f - abs(e.x) - abs(e.y));
  if (n.z < 0.0f) {
    n = vec3((1.0f - abs(e.y)) * signNotZero(e.x), (1.0f - abs(e.x)) * signNotZero(e.y), n.z);
  }
  return normalize(n);
}

// A unit normal in 32 bits (16-bit snorm per axis): worst-case angular error
// about 0.005 degrees, far below what shading can show.
uint packNormalOct32(vec3 n) { return packSnorm2x16(encodeOctahedral(n)); }
vec3 unpackNormalOct32(uint packed) { return decodeOctahedral(unpackSnorm2x16(packed)); }

// A unit normal in 24 bits (12-bit unorm per octahedral axis: worst case
// about 0.06 degrees, far below any history test's tolerance) and a
// material id in the top 8 bits: the second word of the library's history
// surface (gi.history_surface), which lets reprojection compare both in one
// load. Only the id's low 8 bits are kept.
const uint kMaterialIdMask = 0xFFu;
const float kOct12Scale = 4095.0f;

uint packNormalMaterial(vec3 n, uint material) {
  uvec2 q = uvec2(round(clamp(encodeOctahedral(n) * 0.5f + 0.5f, 0.0f, 1.0f) * kOct12Scale));
  return q.x | (q.y << 12u) | ((material & kMaterialIdMask) << 24u);
}

vec3 unpackNormalOfNormalMaterial(uint packed) {
  vec2 q = vec2(float(packed & 0xFFFu), float((packed >> 12u) & 0xFFFu));
  return decodeOctahedral(q * (2.0f / kOct12Scale) - 1.0f);
}

uint unpackMaterialOfNormalMaterial(uint packed) { return packed >> 24u; }

// A unit normal in 22 bits (11-bit unorm per octahedral axis: worst case
// about 0.12 degrees, a tenth of the narrowest cone the denoiser's normal
// weight grants) and a perceptual roughness in the top 10 bits (steps of
// 1/1023): the second word of the denoiser's surface image
// (gi.denoise.surface), so that a tap reads depth, normal and roughness in
// one load.
const float kOct11Scale = 2047.0f;
const float kRoughness10Scale = 1023.0f;

uint packNormalRoughness(vec3 n, float roughness) {
  uvec2 q = uvec2(round(clamp(encodeOctahedral(n) * 0.5f + 0.5f, 0.0f, 1.0f) * kOct11Scale));
  uint r = uint(round(clamp(roughness, 0.0f, 1.0f) * kRoughness10Scale));
  return q.x | (q.y << 11u) | (r << 22u);
}

vec3 unpackNormalOfNormalRoughness(uint packed) {
  vec2 q = vec2(float(packed & 0x7FFu), float((packed >> 11u) & 0x7FFu));
  return decodeOctahedral(q * (2.0f / kOct11Scale) - 1.0f);
}

float unpackRoughnessOfNormalRoughness(uint packed) { return float(packed >> 22u) / kRoughness10Scale; }

// Row-major linear index of a pixel, and back.
uint pixelToIndex(uvec2 pixel, uint width) { return pixel.y * width + pixel.x; }
uvec2 indexToPixel(uint index, uint width) { return uvec2(index % width, index / width); }

// Pixel centre to [0,1]^2 uv and back (uv (0,0) is the top-left corner of the
// top-left pixel).
vec2 pixelToUv(uvec2 pixel, vec2 size) { return (vec2(pixel) + vec2(0.5f)) / size; }
uvec2 uvToPixel(vec2 uv, vec2 size) { return uvec2(clamp(floor(uv * size), vec2(0.0f), size - vec2(1.0f))); }

BOUNCE_SHARED_END
#endif
