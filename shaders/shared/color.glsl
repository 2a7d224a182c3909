// Colour: luminance, sRGB transfer, tonemapping. Radiance is linear Rec.709.
#ifndef BOUNCE_SHARED_COLOR_GLSL
#define BOUNCE_SHARED_COLOR_GLSL
#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

// Rec.709 / sRGB primaries luminance.
float luminance(vec3 rgb) { return dot(rgb, vec3(0.2126f, 0.7152f, 0.0722f)); }

// The exact piecewise sRGB transfer functions (IEC 61966-2-1).
float srgbEncode(float linear) {
  float c = clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * pow(c, 1.0f / 2.4f) - 0.055f;
}
float srgbDecode(float encoded) {
  float c = clamp(encoded, 0.0f, 1.0f);
  return c <= 0.04045f ? c / 12.92f : pow((c + 0.055f) / 1.055f, 2.4f);
}
vec3 srgbEncode(vec3 linear) {
  return vec3(srgbEncode(linear.x), srgbEncode(linear.y), srgbEncode(linear.z));
}
vec3 srgbDecode(vec3 encoded) {
  return vec3(srgbDecode(encoded.x), srgbDecode(encoded.y), srgbDecode(encoded.z));
}

// ACES filmic tonemapper, Stephen Hill's fit of the RRT+ODT (the one used by
// many engines): input linear Rec.709 radiance, output linear display values
// in [0,1]. Matrices are written column by column, which is how both GLSL and
// glm construct a mat3.
vec3 tonemapAcesFitted(vec3 color) {
  mat3 inputMat = mat3(0.59719f, 0.07600f, 0.02840f,
                       0.35458f, 0.90834f, 0.13383f,
                       0.04823f, 0.01566f, 0.83777f);
  mat3 outputMat = mat3(1.60475f, -0.10208f, -0.00327f,
                        -0.53108f, 1.10813f, -0.07276f,
                        -0.07367f, -0.00605f, 1.07602f);
  vec3 v = inputMat * max(color, vec3(0.0f));
  vec3 a = v * (v + vec3(0.0245786f)) - vec3(0.000090537f);
  vec3 b = v * (0.983729f * v + vec3(0.4329510f)) + vec3(0.238081f);
  return clamp(outputMat * (a / b), vec3(0.0f), vec3(1.0f));
}

// Linear HDR radiance to an sRGB-encoded display value in [0,1].
vec3 displayEncode(vec3 radiance, float exposure) {
  return srgbEncode(tonemapAcesFitted(radiance * exposure));
}

BOUNCE_SHARED_END
#endif
