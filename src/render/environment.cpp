#include "render/environment.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "gi/environment_prefilter.h"
#include "gpu/constants_layout.h"
#include "gpu/error.h"
#include "gpu/timing.h"
#include "gpuio/gpu_images.h"
#include "render/gi_bridge.h"
#include "render/render_shaders.h"
#include "shared/finite.glsl"
#include "shared/sky.glsl"

namespace bounce::render {
namespace {

// --- The sun's spectrum and the atmosphere's transmittance (Preetham et al.
// 1999, Table 2 and Appendix A.1, after Iqbal, "An Introduction to Solar
// Radiation", 1983), sampled every 10 nm from 380 to 750 nm: the band where
// the eye's sensitivity is not negligible.
constexpr int kSpectrumSamples = 38;
constexpr double kFirstWavelengthNm = 380.0;
constexpr double kWavelengthStepNm = 10.0;

// Extraterrestrial solar spectral radiance, W / (m^2 sr nm) (the paper's
// Table 2 gives W / (cm^2 um sr), ten times smaller numbers).
constexpr std::array<double, kSpectrumSamples> kSolarRadiance = {
    16559.0, 16233.7, 21127.5, 25888.2, 25829.1, 24232.3, 26760.5, 29658.3, 30545.4, 30057.5, 30663.7, 28830.4, 28712.1,
    27825.0, 27100.6, 27233.6, 26361.3, 25503.8, 25060.2, 25311.6, 25355.9, 25134.2, 24631.5, 24173.2, 23685.3, 23212.1,
    22827.7, 22339.8, 21970.2, 21526.7, 21097.9, 20728.3, 20240.4, 19870.8, 19427.2, 19072.4, 18628.9, 18259.2};

// Ozone absorption coefficient k_o (1/cm). Iqbal's table has no entries
// between 355 nm (0) and 445 nm (0.003); those are interpolated linearly.
constexpr std::array<double, kSpectrumSamples> kOzoneAbsorption = {
    0.00083, 0.00117, 0.0015, 0.00183, 0.00217, 0.0025, 0.00283, 0.003, 0.006, 0.009, 0.014, 0.021, 0.03,
    0.04,    0.048,   0.063,  0.075,   0.085,   0.103,  0.12,    0.12,  0.115, 0.125, 0.12,  0.105, 0.09,
    0.079,   0.067,   0.057,  0.048,   0.036,   0.028,  0.023,   0.018, 0.014, 0.011, 0.010, 0.009};

// Water-vapour absorption coefficient k_wa (1/cm) from 690 to 750 nm; zero
// below. (The mixed gases' k_g absorbs only at 760 nm, outside this band.)
constexpr int kFirstWaterVapourSample = 31;  // 690 nm
constexpr std::array<double, kSpectrumSamples - kFirstWaterVapourSample> kWaterVapourAbsorption = {
    0.016, 0.024, 0.0125, 1.0, 0.87, 0.061, 0.001};

// CIE 1924 photopic luminous efficiency V(lambda).
constexpr std::array<double, kSpectrumSamples> kPhotopicEfficiency = {
    0.000039, 0.00012, 0.000396, 0.00121,  0.004,    0.0116,  0.023,    0.038,   0.06,  0.09098,
    0.13902,  0.20802, 0.323,    0.503,    0.71,     0.862,   0.954,    0.99495, 0.995, 0.952,
    0.87,     0.757,   0.631,    0.503,    0.381,    0.265,   0.175,    0.107,   0.061, 0.032,
    0.017,    0.00821, 0.004102, 0.002091, 0.001047, 0.00052, 0.000249, 0.00012};

constexpr double kLumensPerWatt = 683.0;
constexpr double kOzoneThicknessCm = 0.35;
constexpr double kPrecipitableWaterCm = 2.0;

// The sky's brightness is tied to a sun no dimmer than this share of its
// light outside the atmosphere. The renderer's sun keeps the E its user
// chose at every elevation, while the real sun's illuminance falls by orders
// of magnitude near the horizon (to 2 lux at sunset for T = 3, and below
// 10 % already under 8 degrees for T = 3 and under 15 degrees for T = 6), so
// the exact ratio would make a fixed-E low-sun sky tens to thousands of
// times brighter than its sun (docs/environment.md).
constexpr double kMinSunTransmittanceForScale = 0.1;

// The black environment is one small level: nothing to prefilter.
constexpr std::uint32_t kBlackWidth = 16;

shared::SkyParams toShared(const SkyParameters& p) { return {p.toSunTurbidity, p.scale, p.groundRadiance}; }

gpu::PassDesc skyBakeDesc() {
  return {.name = "render.sky_bake",
          .shader = "render/sky_bake",
          .shaders = shaders(),
          .resources = {{"gOut_Sky", gpu::Access::Write, VK_FORMAT_R16G16B16A16_SFLOAT,
                         "procedural sky radiance: the environment the library prefilters"}},
          .constants = {BOUNCE_CONSTANTS_LAYOUT("", shared::SkyParams, toSunTurbidity, scale, groundRadiance)}};
}

bool finite(float value) { return std::isfinite(value); }

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

void validate(const EnvironmentDesc& desc) {
  const auto fail = [](const std::string& why) { return gpu::GpuError("environment: " + why); };
  if (!finite(desc.intensity) || desc.intensity < 0.0f)
    throw fail("intensity " + std::to_string(desc.intensity) + " is not a finite value >= 0");
  if (const std::string problem = environmentIntensityProblem(desc); !problem.empty())
    throw fail("intensity " + number(desc.intensity) + " " + problem);
  if (!finite(desc.rotationDegrees)) throw fail("rotation is not finite");
  if (!finite(desc.turbidity)) throw fail("turbidity is not finite");
  if (!finite(desc.groundAlbedo) || desc.groundAlbedo < 0.0f || desc.groundAlbedo > 1.0f)
    throw fail("ground albedo " + std::to_string(desc.groundAlbedo) + " is outside [0, 1]");
  if (!finite(desc.sun.elevationDegrees) || !finite(desc.sun.azimuthDegrees) || !finite(desc.sun.illuminance) ||
      desc.sun.illuminance < 0.0f || !finite(desc.sun.color.x + desc.sun.color.y + desc.sun.color.z))
    throw fail("the sun has a non-finite direction or colour, or a negative illuminance");
  const glm::vec3& sunColour = desc.sun.color;
  if (const std::string problem =
          scene::lightStrengthProblem(double(desc.sun.illuminance) * std::max({sunColour.x, sunColour.y, sunColour.z}));
      desc.hasSun && !problem.empty())
    throw fail("the sun's illuminance " + number(desc.sun.illuminance) + " (times its colour) is " + problem);
  if (desc.skyWidth < 8 || desc.skyWidth > 16384)
    throw fail("sky width " + std::to_string(desc.skyWidth) + " is outside 8..16384");
  if (desc.maxMapWidth < 8) throw fail("maximum map width " + std::to_string(desc.maxMapWidth) + " is below 8");
  if (desc.maxMipCount < 1 || desc.maxMipCount > 16)
    throw fail("maximum mip count " + std::to_string(desc.maxMipCount) + " is outside 1..16");
  if (desc.prefilterSamples < 1 || desc.prefilterSamples > 65536)
    throw fail("prefilter sample count " + std::to_string(desc.prefilterSamples) + " is outside 1..65536");
}

}  // namespace

std::string environmentIntensityProblem(const EnvironmentDesc& desc) {
  if (const std::string problem = scene::lightStrengthProblem(desc.intensity); !problem.empty()) return "is " + problem;
  if (!desc.map.empty() || !desc.hasSun) return {};
  // The sky's ground takes the sun's colour, its sky does not: at least 1.
  const glm::vec3& colour = desc.sun.color;
  const double sky =
      double(desc.intensity) * double(desc.sun.illuminance) * std::max({colour.x, colour.y, colour.z, 1.0f});
  if (const std::string problem = scene::lightStrengthProblem(sky); !problem.empty())
    return "times the sun's illuminance " + number(desc.sun.illuminance) + " (" + number(sky) + ") is " + problem;
  return {};
}

namespace {

// The exact solid angle of the latitude band between fractional rows a and b
// of an image `height` rows tall, up to the constant 2 pi / width.
double bandWeight(double a, double b, double height) {
  return std::cos(std::numbers::pi * a / height) - std::cos(std::numbers::pi * b / height);
}

// Area-weighted resampling to a smaller size: each output texel averages the
// input area it covers, rows weighted by their solid angle, so the map keeps
// its integral over the sphere. texel(x, y) gives the input's RGB, so that a
// large map is read where it lies rather than copied first.
template <typename Texel>
io::ImageF shrink(const Texel& texel, int inWidth, int inHeight, int width, int height) {
  io::ImageF out(width, height, {"R", "G", "B"});
  const double scaleX = double(inWidth) / width;
  const double scaleY = double(inHeight) / height;
  // Horizontal pass into rows of the input's height, then vertical.
  io::ImageF rows(width, inHeight, {"R", "G", "B"});
  for (int y = 0; y < inHeight; ++y)
    for (int x = 0; x < width; ++x) {
      const double x0 = x * scaleX, x1 = (x + 1) * scaleX;
      glm::dvec3 sum(0.0);
      for (int sx = int(x0); sx < std::min(inWidth, int(std::ceil(x1))); ++sx)
        sum += glm::dvec3(texel(sx, y)) * (std::min(x1, sx + 1.0) - std::max(x0, double(sx)));
      for (int c = 0; c < 3; ++c) rows.at(x, y, c) = float(sum[c] / scaleX);
    }
  for (int y = 0; y < height; ++y) {
    const double y0 = y * scaleY, y1 = (y + 1) * scaleY;
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) {
        double sum = 0.0, weightSum = 0.0;
        for (int sy = int(y0); sy < std::min(inHeight, int(std::ceil(y1))); ++sy) {
          const double weight = bandWeight(std::max(y0, double(sy)), std::min(y1, sy + 1.0), inHeight);
          sum += rows.at(x, sy, c) * weight;
          weightSum += weight;
        }
        out.at(x, y, c) = float(weightSum > 0.0 ? sum / weightSum : 0.0);
      }
  }
  return out;
}

// The width a map of `width` is kept at: maps wider than maxWidth are
// shrunk to it (an even number, for the 2:1 shape).
int preparedWidth(int width, std::uint32_t maxWidth) {
  return std::uint32_t(width) > maxWidth ? int(maxWidth & ~1u) : width;
}

// The Preetham sun's illuminance (lux) at normal incidence through
// `airMass` atmospheres (0: outside the atmosphere).
double sunIlluminanceThroughAirMass(double airMass, float turbidity) {
  const double t = std::clamp(double(turbidity), double(shared::kMinTurbidity), double(shared::kMaxTurbidity));
  const double beta = 0.04608 * t - 0.04586;  // Angstrom turbidity coefficient
  const double alpha = 1.3;                   // Angstrom wavelength exponent
  double luminance = 0.0;
  for (int i = 0; i < kSpectrumSamples; ++i) {
    const double micrometres = (kFirstWavelengthNm + kWavelengthStepNm * i) * 1e-3;
    const double rayleigh = std::exp(-0.008735 * std::pow(micrometres, -4.08) * airMass);
    const double aerosol = std::exp(-beta * std::pow(micrometres, -alpha) * airMass);
    const double ozone = std::exp(-kOzoneAbsorption[i] * kOzoneThicknessCm * airMass);
    const double waterAbsorption =
        i >= kFirstWaterVapourSample ? kWaterVapourAbsorption[std::size_t(i - kFirstWaterVapourSample)] : 0.0;
    const double waterPath = waterAbsorption * kPrecipitableWaterCm * airMass;
    const double water = std::exp(-0.2385 * waterPath / std::pow(1.0 + 20.07 * waterPath, 0.45));
    luminance += kPhotopicEfficiency[i] * kSolarRadiance[i] * rayleigh * aerosol * ozone * water * kWavelengthStepNm;
  }
  return kLumensPerWatt * luminance * double(shared::kSunSolidAngle);
}

}  // namespace

std::uint32_t prefilteredMipCount(std::uint32_t height, std::uint32_t maxMipCount) {
  return gi::prefilteredMipCount(height, maxMipCount);
}

float preethamSunIlluminance(float elevationDegrees, float turbidity) {
  const double zenithDegrees = 90.0 - std::clamp(double(elevationDegrees), 0.0, 90.0);
  // Relative optical air mass (Kasten 1966), finite at the horizon.
  const double airMass =
      1.0 / (std::cos(zenithDegrees * std::numbers::pi / 180.0) + 0.15 * std::pow(93.885 - zenithDegrees, -1.253));
  return float(sunIlluminanceThroughAirMass(airMass, turbidity));
}

float twilightFactor(float elevationDegrees) {
  if (elevationDegrees >= 0.0f) return 1.0f;
  if (elevationDegrees <= -12.0f) return 0.0f;
  return std::pow(10.0f, 0.5f * elevationDegrees);
}

glm::vec3 skyHorizontalIrradiance(const SkyParameters& params) {
  const shared::SkyParams sky = toShared(params);
  // Midpoint rule in (cos theta, phi), where the measure is dmu dphi and the
  // cosine factor is mu: smooth integrand, 64 x 128 points are plenty.
  constexpr int kRings = 64, kSegments = 128;
  glm::dvec3 sum(0.0);
  for (int i = 0; i < kRings; ++i) {
    const float mu = (float(i) + 0.5f) / float(kRings);
    const float sinTheta = std::sqrt(1.0f - mu * mu);
    for (int j = 0; j < kSegments; ++j) {
      const float phi = (float(j) + 0.5f) / float(kSegments) * 2.0f * std::numbers::pi_v<float>;
      const glm::vec3 direction(sinTheta * std::sin(phi), mu, sinTheta * std::cos(phi));
      sum += glm::dvec3(shared::skyRadiance(sky, direction)) * double(mu);
    }
  }
  return glm::vec3(sum * (2.0 * std::numbers::pi / (double(kRings) * kSegments)));
}

SkyParameters skyParams(const EnvironmentDesc& desc) {
  SkyParameters params;
  if (!desc.hasSun) return params;
  const scene::Sun& sun = desc.sun;
  const float turbidity = std::clamp(desc.turbidity, shared::kMinTurbidity, shared::kMaxTurbidity);
  params.toSunTurbidity = glm::vec4(sun.direction(), turbidity);
  // Preetham's sky is in cd/m^2 and its sun in lux; the renderer's sun has
  // illuminance E, so one cd/m^2 of sky is E / E_preetham in renderer units.
  const float sunLux = std::max(preethamSunIlluminance(sun.elevationDegrees, turbidity),
                                float(kMinSunTransmittanceForScale * sunIlluminanceThroughAirMass(0.0, turbidity)));
  params.scale.x = desc.intensity * twilightFactor(sun.elevationDegrees) * sun.illuminance / sunLux;
  // The ground is Lambert: albedo / pi times the irradiance from the sky
  // above it and from the sun (when up).
  const glm::vec3 sunIrradiance = sun.color * (sun.illuminance * std::max(sun.direction().y, 0.0f) * desc.intensity);
  params.groundRadiance = glm::vec4(
      (skyHorizontalIrradiance(params) + sunIrradiance) * (desc.groundAlbedo * std::numbers::inv_pi_v<float>), 0.0f);
  return params;
}

void checkEnvironmentMapShape(int width, int height, const std::vector<std::string>& channels,
                              const std::string& name) {
  if (channels.size() != 1 && channels.size() < 3)
    throw io::ImageIoError(name + ": an environment map needs 1, 3 or 4 channels, not " +
                           std::to_string(channels.size()));
  // A lone alpha channel (an EXR of "A" only) is coverage, not light: read
  // as grey it lit the scene with a uniform white sky, without a word.
  if (channels.size() == 1 && (channels[0] == "A" || channels[0].ends_with(".A")))
    throw io::ImageIoError(name + ": holds only an alpha channel (" + channels[0] +
                           "), no light: an environment map needs colour channels (R, G, B) or one grey channel");
  if (width < 8)
    throw io::ImageIoError(name + ": " + std::to_string(width) + "x" + std::to_string(height) +
                           " is too small for an environment map (at least 8x4)");
  if (std::abs(width - 2 * height) > std::max(1, width / 100))
    throw io::ImageIoError(name + ": " + std::to_string(width) + "x" + std::to_string(height) +
                           " is not an equirectangular map (width = 2 x height)");
}

std::uint64_t environmentMapWorkingBytes(int width, int height, std::uint32_t maxWidth) {
  const std::uint64_t outWidth = std::uint64_t(preparedWidth(width, maxWidth));
  const std::uint64_t outHeight = std::uint64_t(width) > outWidth ? outWidth / 2 : std::uint64_t(height);
  const std::uint64_t rgb = 3 * sizeof(float);
  // Shrinking: the horizontal pass's rows (the output's width, the input's
  // height) and the shrunk map; else a sanitised copy. Then the RGBA result.
  const std::uint64_t sanitised = std::uint64_t(width) > outWidth
                                      ? outWidth * std::uint64_t(height) * rgb + outWidth * outHeight * rgb
                                      : std::uint64_t(width) * std::uint64_t(height) * rgb;
  return sanitised + outWidth * outHeight * 4 * sizeof(float);
}

namespace {

// Radiance beyond the brightest light Bounce renders overflows float once it
// is scaled: a map of 1.7e38 (Radiance exponent 255) times intensity 4 became
// infinite, so black, and the whole environment went dark without a word.
// Such texels are refused by position, as readImage refuses NaN ones. An
// intensity below 1 does not excuse them: the map itself is not a picture
// Bounce can light with.
void checkTexelStrength(const io::ImageF& map, const std::string& name, float intensity) {
  const std::size_t channels = map.channelCount();
  const double scale = std::max(1.0, double(intensity));
  std::size_t count = 0, first = 0;  // texels, and the first one's first bright value
  for (std::size_t pixel = 0; pixel < map.pixels.size() / channels; ++pixel) {
    for (std::size_t c = 0; c < std::min<std::size_t>(channels, 3); ++c) {
      const float value = map.pixels[pixel * channels + c];
      if (std::isfinite(value) && !scene::lightStrengthProblem(std::fabs(value) * scale).empty()) {
        if (count == 0) first = pixel * channels + c;
        ++count;
        break;
      }
    }
  }
  if (count == 0) return;
  const std::size_t pixel = first / channels;
  const double value = map.pixels[first];
  std::string strength = number(value);
  if (scale > 1.0) strength += " times the intensity " + number(intensity) + " (" + number(value * scale) + ")";
  throw io::ImageIoError(name + ": " + std::to_string(count) + (count == 1 ? " texel" : " texels") +
                         " too bright, first at pixel (" + std::to_string(pixel % std::size_t(map.width)) + ", " +
                         std::to_string(pixel / std::size_t(map.width)) + ") channel " +
                         map.channels[first % channels] + ": radiance " + strength + " is " +
                         scene::lightStrengthProblem(std::fabs(value) * scale));
}

// Light is never negative. Lossy EXR codecs (DWAA/DWAB) leave small
// negatives where they ring beside a bright edge, which the map drops to 0
// (sanitizeRadiance); but a map of negative texels rendered black, and one
// negative texel amid others lit a hole, without a word. Negatives beyond
// kNegativeShare of the brightest texel (or any, in a map with nothing
// brighter than 0) are refused by position, naming the first and their count.
constexpr double kNegativeShare = 0.1;

void checkNegativeTexels(const io::ImageF& map, const std::string& name) {
  const std::size_t channels = map.channelCount();
  const std::size_t colours = std::min<std::size_t>(channels, 3);
  float brightest = 0.0f;
  for (std::size_t i = 0; i < map.pixels.size(); ++i)
    if (i % channels < colours && std::isfinite(map.pixels[i])) brightest = std::max(brightest, map.pixels[i]);
  const double floor = -kNegativeShare * double(brightest);
  std::size_t count = 0, first = 0;  // texels, and the first one's first negative value
  for (std::size_t pixel = 0; pixel < map.pixels.size() / channels; ++pixel)
    for (std::size_t c = 0; c < colours; ++c)
      if (const float value = map.pixels[pixel * channels + c]; double(value) < floor && value < 0.0f) {
        if (count == 0) first = pixel * channels + c;
        ++count;
        break;
      }
  if (count == 0) return;
  const std::size_t pixel = first / channels;
  throw io::ImageIoError(name + ": " + std::to_string(count) + (count == 1 ? " texel" : " texels") +
                         " of negative radiance, first at pixel (" + std::to_string(pixel % std::size_t(map.width)) +
                         ", " + std::to_string(pixel / std::size_t(map.width)) + ") channel " +
                         map.channels[first % channels] + ": " + number(map.pixels[first]) +
                         "; light is 0 or more (the small negatives a lossy codec leaves, down to -" +
                         number(kNegativeShare * 100.0) + " % of the brightest texel, are drawn as 0)");
}

}  // namespace

io::ImageF prepareEnvironmentMap(const io::ImageF& map, const std::string& name, float intensity, float rotationDegrees,
                                 std::uint32_t maxWidth) {
  const std::size_t channels = map.channelCount();
  checkEnvironmentMapShape(map.width, map.height, map.channels, name);
  checkTexelStrength(map, name, intensity);
  checkNegativeTexels(map, name);

  // A texel with a NaN or infinite channel is black before it is filtered,
  // so that it cannot spread into its neighbours.
  const auto texel = [&](int x, int y) {
    glm::vec3 value;
    for (int c = 0; c < 3; ++c) value[c] = map.at(x, y, channels == 1 ? 0 : c);
    return shared::finiteOr(value, glm::vec3(0.0f));
  };
  io::ImageF rgb;
  if (const int width = preparedWidth(map.width, maxWidth); width < map.width) {
    rgb = shrink(texel, map.width, map.height, width, width / 2);
  } else {
    rgb = io::ImageF(map.width, map.height, {"R", "G", "B"});
    for (int y = 0; y < map.height; ++y)
      for (int x = 0; x < map.width; ++x) {
        const glm::vec3 value = texel(x, y);
        for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = value[c];
      }
  }

  // Turning by +a about +Y moves every feature by -a / 360 of the width
  // (shared/equirect.glsl), so output column x reads input column x + shift.
  const int width = rgb.width;
  double shift = double(rotationDegrees) / 360.0 * width;
  shift -= std::floor(shift / width) * width;
  const int whole = int(std::floor(shift));
  const float fraction = float(shift - whole);
  io::ImageF out(rgb.width, rgb.height, {"R", "G", "B", "A"});
  for (int y = 0; y < rgb.height; ++y)
    for (int x = 0; x < width; ++x) {
      const int x0 = (x + whole) % width, x1 = (x + whole + 1) % width;
      glm::vec3 value;
      for (int c = 0; c < 3; ++c)
        value[c] = (rgb.at(x0, y, c) * (1.0f - fraction) + rgb.at(x1, y, c) * fraction) * intensity;
      value = shared::sanitizeRadiance(value);
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = value[c];
      out.at(x, y, 3) = 1.0f;
    }
  return out;
}

Environment::Environment(gpu::Context& context, const EnvironmentDesc& desc) : context_(context), desc_(desc) {
  validate(desc);
  std::uint32_t width = desc.skyWidth, height = desc.skyWidth / 2;
  io::ImageF map;
  if (!desc.map.empty()) {
    kind_ = Kind::Map;
    // The header first: a map of the wrong shape, or one too large to
    // prepare, is refused before it is decoded.
    const io::ImageInfo info = io::readImageInfo(desc.map);
    checkEnvironmentMapShape(info.width, info.height, info.channelNames, desc.map.string());
    io::refuseOverMemoryLimit(
        desc.map,
        std::max(info.readBytes(),
                 info.imageBytes() + environmentMapWorkingBytes(info.width, info.height, desc.maxMapWidth)),
        "preparing a " + std::to_string(info.width) + "x" + std::to_string(info.height) + " environment map");
    map = prepareEnvironmentMap(io::readImage(desc.map), desc.map.string(), desc.intensity, desc.rotationDegrees,
                                desc.maxMapWidth);
    width = std::uint32_t(map.width);
    height = std::uint32_t(map.height);
  } else if (!desc.hasSun) {
    kind_ = Kind::Black;
    width = kBlackWidth;
    height = kBlackWidth / 2;
  } else {
    sky_ = skyParams(desc);
  }

  source_ = std::make_unique<gpu::Image>(context, gpu::ImageDesc{.name = "environment.source",
                                                                 .width = width,
                                                                 .height = height,
                                                                 .format = VK_FORMAT_R16G16B16A16_SFLOAT,
                                                                 .visualize = gpu::Visualize::Radiance});
  if (kind_ == Kind::Map) gpuio::uploadImage(context, *source_, map);
  if (kind_ == Kind::Sky) skyBakePass_ = std::make_unique<gpu::ComputePass>(context, skyBakeDesc());
  // The black environment is one level: nothing to prefilter.
  prefilter_ = std::make_unique<gi::EnvironmentPrefilter>(
      giDevice(context), gi::PrefilterDesc{.width = width,
                                           .height = height,
                                           .maxMipLevels = kind_ == Kind::Black ? 1u : desc.maxMipCount,
                                           .samplesPerTexel = desc.prefilterSamples});
  const gi::ImageRef output = prefilter_->output();
  radiance_ = std::make_unique<gpu::Image>(context, gpu::ExternalImage{.image = output.image,
                                                                       .view = output.view,
                                                                       .desc = {.name = "environment.radiance",
                                                                                .width = output.width,
                                                                                .height = output.height,
                                                                                .format = output.format,
                                                                                .visualize = gpu::Visualize::Radiance,
                                                                                .mipLevels = output.mipLevels}});
}

Environment::~Environment() = default;

VkSampler Environment::sampler() const { return prefilter_->sampler(); }

void Environment::setSun(const scene::Sun& sun) {
  EnvironmentDesc moved = desc_;
  moved.sun = sun;
  validate(moved);
  desc_ = moved;
  if (kind_ == Kind::Sky) {
    sky_ = skyParams(desc_);
    recorded_ = false;
  }
}

void Environment::record(gpu::Recorder& recorder) {
  if (recorded_) return;
  recorded_ = true;
  if (kind_ == Kind::Black)
    recorder.clearImage(*source_, VkClearColorValue{{0.0f, 0.0f, 0.0f, 1.0f}});
  else if (kind_ == Kind::Sky)
    recorder.dispatch(*skyBakePass_, source_->width(), source_->height(), {{"gOut_Sky", *source_}},
                      toShared(sky_));
  recorder.flush();
  // The library prefilters in this command buffer, as it would an engine's environment.
  const gi::ImageRef given = imageRef(*source_);
  prefilter_->record(recorder.commandBuffer(), given, recorder.capturing());
  tookBack(*source_, given);
  // Its pass times and stage copies join the renderer's once the command buffer is done.
  recorder.onCompleted([prefilter = prefilter_.get(), frame = recorder.captureFrame()](
                           gpu::TimingStats* timings, std::vector<gpu::CapturedStage>* captures) {
    gi::FrameResults results = prefilter->collect();
    if (timings)
      for (const gi::PassTiming& timing : results.timings) timings->add(timing.pass, timing.milliseconds);
    if (captures)
      for (gi::CapturedStage& stage : results.stages) captures->push_back(capturedStage(std::move(stage), frame));
  });
  const gi::ImageRef output = prefilter_->output();
  gpu::SyncState& state = radiance_->sync();
  state = {};
  state.writeStage = output.stage;
  state.writeAccess = output.access;
  state.layout = output.layout;
}

}  // namespace bounce::render
