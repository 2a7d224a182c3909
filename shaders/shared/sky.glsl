// The procedural sky: A. J. Preetham, P. Shirley, B. Smits, "A Practical
// Analytic Model for Daylight" (SIGGRAPH 1999), and the sun's disk. One
// source for GLSL and C++ (lang.glsl); see docs/environment.md.
//
// Preetham gives the clear sky's absolute luminance (cd/m^2) and CIE xy
// chromaticity per direction: each of x, y and Y is its zenith value times
// the Perez distribution F(theta, gamma) / F(0, theta_sun), with theta the
// view direction's zenith angle and gamma its angle to the sun. The turbidity
// T (haze: 2 very clear, 3 clear, 6 hazy) sets the coefficients. The sky here
// holds no sun disk: the renderer adds the sun as a directional light, and
// sunDiskRadiance() draws its disk for background pixels if wanted.
#ifndef BOUNCE_SHARED_SKY_GLSL
#define BOUNCE_SHARED_SKY_GLSL
#include "shared/lang.glsl"

BOUNCE_SHARED_BEGIN

// The sun's mean angular radius seen from the earth (0.2666 degrees), its
// cosine and the solid angle of its disk, 2 pi (1 - cos r).
const float kSunAngularRadius = 0.004653f;
const float kSunCosAngularRadius = 0.99998918f;
const float kSunSolidAngle = 6.8017e-5f;

// The turbidities the model is used for. Below about 1.2 the Perez B
// coefficient of luminance turns positive (the sky would brighten without
// bound towards the horizon); Preetham et al. fitted T from 2 to 10.
const float kMinTurbidity = 1.7f;
const float kMaxTurbidity = 10.0f;

// F(theta, gamma) = (1 + A exp(B / cos theta)) (1 + C exp(D gamma) + E cos^2 gamma).
struct PerezCoefficients {
  float a;
  float b;
  float c;
  float d;
  float e;
};

// The paper's Appendix A.2: each coefficient is linear in the turbidity.
PerezCoefficients preethamLuminanceCoefficients(float turbidity) {
  PerezCoefficients k;
  k.a = 0.1787f * turbidity - 1.4630f;
  k.b = -0.3554f * turbidity + 0.4275f;
  k.c = -0.0227f * turbidity + 5.3251f;
  k.d = 0.1206f * turbidity - 2.5771f;
  k.e = -0.0670f * turbidity + 0.3703f;
  return k;
}

PerezCoefficients preethamChromaticityXCoefficients(float turbidity) {
  PerezCoefficients k;
  k.a = -0.0193f * turbidity - 0.2592f;
  k.b = -0.0665f * turbidity + 0.0008f;
  k.c = -0.0004f * turbidity + 0.2125f;
  k.d = -0.0641f * turbidity - 0.8989f;
  k.e = -0.0033f * turbidity + 0.0452f;
  return k;
}

PerezCoefficients preethamChromaticityYCoefficients(float turbidity) {
  PerezCoefficients k;
  k.a = -0.0167f * turbidity - 0.2608f;
  k.b = -0.0950f * turbidity + 0.0092f;
  k.c = -0.0079f * turbidity + 0.2102f;
  k.d = -0.0441f * turbidity - 1.6537f;
  k.e = -0.0109f * turbidity + 0.0529f;
  return k;
}

// cosTheta is clamped away from 0: B < 0, so exp(B / cosTheta) goes to 0 at
// the horizon, and the clamp keeps the division finite on every compiler.
float perezDistribution(PerezCoefficients k, float cosTheta, float gamma, float cosGamma) {
  return (1.0f + k.a * exp(k.b / max(cosTheta, 1e-3f))) * (1.0f + k.c * exp(k.d * gamma) + k.e * cosGamma * cosGamma);
}

// Zenith luminance in cd/m^2 (the paper's formula gives kcd/m^2) for the sun
// at zenith angle thetaSun (radians, 0 to pi/2).
float preethamZenithLuminance(float turbidity, float thetaSun) {
  float chi = (4.0f / 9.0f - turbidity / 120.0f) * (kPi - 2.0f * thetaSun);
  return 1000.0f * ((4.0453f * turbidity - 4.9710f) * tan(chi) - 0.2155f * turbidity + 2.4192f);
}

// Zenith chromaticity (CIE x, y): the paper's cubic in thetaSun, quadratic in T.
vec2 preethamZenithChromaticity(float turbidity, float thetaSun) {
  float t = turbidity;
  float s = thetaSun;
  float s2 = s * s;
  float s3 = s2 * s;
  float x = t * t * (0.00166f * s3 - 0.00375f * s2 + 0.00209f * s) +
            t * (-0.02903f * s3 + 0.06377f * s2 - 0.03202f * s + 0.00394f) +
            (0.11693f * s3 - 0.21196f * s2 + 0.06052f * s + 0.25886f);
  float y = t * t * (0.00275f * s3 - 0.00610f * s2 + 0.00317f * s) +
            t * (-0.04214f * s3 + 0.08970f * s2 - 0.04153f * s + 0.00516f) +
            (0.15346f * s3 - 0.26756f * s2 + 0.06670f * s + 0.26688f);
  return vec2(x, y);
}

// Everything about the sky that does not depend on the view direction.
struct PreethamSky {
  PerezCoefficients luminance;
  PerezCoefficients chromaticityX;
  PerezCoefficients chromaticityY;
  vec3 zenithOverPerez;  // (x, y, Y) at the zenith divided by F(0, thetaSun)
  vec3 toSun;            // the sun the model is evaluated for (never below the horizon)
};

// toSun is a unit vector. The model's sun never sets: below the horizon it
// is moved up to elevation 0 (the sky keeps its sunset shape; the host dims
// it through twilight, docs/environment.md). The turbidity is clamped to
// [kMinTurbidity, kMaxTurbidity].
PreethamSky preethamSky(vec3 toSun, float turbidity) {
  float t = clamp(turbidity, kMinTurbidity, kMaxTurbidity);
  float horizontalLength = sqrt(toSun.x * toSun.x + toSun.z * toSun.z);
  vec3 sun = toSun;
  if (toSun.y < 0.0f)
    sun = horizontalLength > 0.0f ? vec3(toSun.x / horizontalLength, 0.0f, toSun.z / horizontalLength)
                                  : vec3(0.0f, 0.0f, 1.0f);
  float thetaSun = acos(clamp(sun.y, 0.0f, 1.0f));
  float cosThetaSun = cos(thetaSun);

  PreethamSky sky;
  sky.luminance = preethamLuminanceCoefficients(t);
  sky.chromaticityX = preethamChromaticityXCoefficients(t);
  sky.chromaticityY = preethamChromaticityYCoefficients(t);
  sky.toSun = sun;
  vec2 zenithXy = preethamZenithChromaticity(t, thetaSun);
  sky.zenithOverPerez =
      vec3(zenithXy.x / perezDistribution(sky.chromaticityX, 1.0f, thetaSun, cosThetaSun),
           zenithXy.y / perezDistribution(sky.chromaticityY, 1.0f, thetaSun, cosThetaSun),
           preethamZenithLuminance(t, thetaSun) / perezDistribution(sky.luminance, 1.0f, thetaSun, cosThetaSun));
  return sky;
}

// CIE xyY to linear Rec.709 / sRGB (D65); Y stays the luminance.
vec3 xyYToLinearSrgb(vec3 xyY) {
  float y = max(xyY.y, 1e-6f);
  vec3 xyz = vec3(xyY.x * xyY.z / y, xyY.z, (1.0f - xyY.x - xyY.y) * xyY.z / y);
  mat3 xyzToSrgb = mat3(3.2404542f, -0.9692660f, 0.0556434f,
                        -1.5371385f, 1.8760108f, -0.2040259f,
                        -0.4985314f, 0.0415560f, 1.0572252f);
  return xyzToSrgb * xyz;
}

// The sky's (x, y, Y) towards a direction (Y in cd/m^2); directions below the
// horizon get the horizon's value.
vec3 preethamSkyXyY(PreethamSky sky, vec3 direction) {
  float cosTheta = max(direction.y, 0.0f);
  float cosGamma = clamp(dot(direction, sky.toSun), -1.0f, 1.0f);
  float gamma = acos(cosGamma);
  return vec3(sky.zenithOverPerez.x * perezDistribution(sky.chromaticityX, cosTheta, gamma, cosGamma),
              sky.zenithOverPerez.y * perezDistribution(sky.chromaticityY, cosTheta, gamma, cosGamma),
              sky.zenithOverPerez.z * perezDistribution(sky.luminance, cosTheta, gamma, cosGamma));
}

// The sky's absolute luminance as linear sRGB whose luminance is cd/m^2.
// Colours outside the sRGB gamut are clipped at 0.
vec3 preethamSkyLuminanceRgb(PreethamSky sky, vec3 direction) {
  return max(xyYToLinearSrgb(preethamSkyXyY(sky, direction)), vec3(0.0f));
}

// What the environment bake needs, filled by the host (render::skyParams):
// vec4s only, so C++ and push constants agree on the layout.
struct SkyParams {
  vec4 toSunTurbidity;  // xyz unit direction towards the sun (any elevation), w turbidity
  vec4 scale;           // x: renderer radiance per cd/m^2 of sky (0 = black sky); yzw unused
  vec4 groundRadiance;  // rgb: radiance of the ground below the horizon; w unused
};

// The environment's radiance towards a direction, in renderer units: the
// Preetham sky above the horizon, the uniform ground below it. No sun disk.
vec3 skyRadiance(SkyParams params, vec3 direction) {
  if (direction.y < 0.0f) return vec3(params.groundRadiance.x, params.groundRadiance.y, params.groundRadiance.z);
  vec3 toSun = vec3(params.toSunTurbidity.x, params.toSunTurbidity.y, params.toSunTurbidity.z);
  PreethamSky sky = preethamSky(toSun, params.toSunTurbidity.w);
  return preethamSkyLuminanceRgb(sky, direction) * params.scale.x;
}

// Radiance of the sun's disk towards `direction` (0 outside the disk): a
// uniform disk of kSunSolidAngle whose radiance integrates to
// sunIlluminance (E * colour, what the directional light delivers), so a
// consumer that draws it for background pixels shows the same sun it lights
// with. Values reach E / 6.8e-5: beyond float16 for E > 4.4 (clamp there).
vec3 sunDiskRadiance(vec3 direction, vec3 toSun, vec3 sunIlluminance) {
  return dot(direction, toSun) >= kSunCosAngularRadius ? sunIlluminance * (1.0f / kSunSolidAngle) : vec3(0.0f);
}

BOUNCE_SHARED_END
#endif
