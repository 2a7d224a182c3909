// The settings layer of gi_settings.h: one table of every settable field
// (key, member, range, description) from which the key list, the parser, the
// printer and the validator are all derived, so a new field is added in one
// place and cannot be parsed but not validated, or listed but not parsed.
#include "bounce/gi_settings.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <unordered_set>
#include <utility>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "gi/cache/cache_types.glsl"
#include "gi/diffuse/diffuse_common.glsl"
#include "util/edit_distance.h"
#include "util/json_error.h"
#include "util/json_parse.h"

namespace bounce::gi {
namespace {

constexpr std::string_view kKeyPrefix = "gi.";

// A field is in DiffuseSettings, SpecularSettings, CacheSettings, InputSettings, DenoiseSettings or directly in Settings;
// keeping the pointer-to-member (not a lambda) lets validate() find a key
// from its field.
template <typename T>
struct Member {
  T DiffuseSettings::*diffuse = nullptr;
  T SpecularSettings::*specular = nullptr;
  T CacheSettings::*cache = nullptr;
  T InputSettings::*input = nullptr;
  T DenoiseSettings::*denoise = nullptr;
  T Settings::*top = nullptr;

  T& of(Settings& settings) const {
    return diffuse    ? settings.diffuse.*diffuse
           : specular ? settings.specular.*specular
           : cache    ? settings.cache.*cache
           : input      ? settings.input.*input
           : denoise    ? settings.denoise.*denoise
                        : settings.*top;
  }
  const T& of(const Settings& settings) const {
    return diffuse    ? settings.diffuse.*diffuse
           : specular ? settings.specular.*specular
           : cache    ? settings.cache.*cache
           : input      ? settings.input.*input
           : denoise    ? settings.denoise.*denoise
                        : settings.*top;
  }
};

template <typename T>
constexpr Member<T> inDiffuse(T DiffuseSettings::*member) {
  return {member, nullptr, nullptr, nullptr, nullptr, nullptr};
}

template <typename T>
constexpr Member<T> inSpecular(T SpecularSettings::*member) {
  return {nullptr, member, nullptr, nullptr, nullptr, nullptr};
}

template <typename T>
constexpr Member<T> inCache(T CacheSettings::*member) {
  return {nullptr, nullptr, member, nullptr, nullptr, nullptr};
}

template <typename T>
constexpr Member<T> inInput(T InputSettings::*member) {
  return {nullptr, nullptr, nullptr, member, nullptr, nullptr};
}

template <typename T>
constexpr Member<T> inDenoise(T DenoiseSettings::*member) {
  return {nullptr, nullptr, nullptr, nullptr, member, nullptr};
}

template <typename T>
constexpr Member<T> inSettings(T Settings::*member) {
  return {nullptr, nullptr, nullptr, nullptr, nullptr, member};
}

// The alternative held also says the field's type, so type and member cannot disagree.
using Field = std::variant<Member<bool>, Member<std::uint32_t>, Member<float>, Member<TargetFunction>,
                           Member<MotionUnits>, Member<Visibility>, Member<SpecularSampling>,
                           Member<SpecularReprojection>>;

// Numeric range; unused for bool and enum fields.
struct Bounds {
  double min = 0.0;
  double max = 0.0;
  bool excludeMin = false;
  bool excludeMax = false;

  bool contains(double value) const {
    const bool aboveMin = excludeMin ? value > min : value >= min;
    const bool belowMax = excludeMax ? value < max : value <= max;
    return aboveMin && belowMax;
  }
};

constexpr Bounds closed(double min, double max) { return {min, max, false, false}; }
constexpr Bounds aboveUpTo(double min, double max) { return {min, max, true, false}; }
constexpr Bounds open(double min, double max) { return {min, max, true, true}; }
constexpr Bounds kNoBounds{};
constexpr Bounds kAnyUint = closed(0.0, std::numeric_limits<std::uint32_t>::max());

struct Entry {
  std::string_view key;  // relative to "gi."
  Field field;
  Bounds bounds;
  std::string_view description;
};

// The names an enum setting takes, in the order its help lists them.
template <typename E>
struct EnumName {
  E value;
  std::string_view name;
};

template <typename E>
constexpr auto kEnumNames = 0;  // every enum field's type has its list below
template <>
constexpr std::array kEnumNames<TargetFunction>{
    EnumName<TargetFunction>{TargetFunction::Luminance, "luminance"},
    EnumName<TargetFunction>{TargetFunction::ColorLength, "color-length"},
};
template <>
constexpr std::array kEnumNames<Visibility>{
    EnumName<Visibility>{Visibility::Screen, "screen"},
    EnumName<Visibility>{Visibility::World, "world"},
    EnumName<Visibility>{Visibility::Hybrid, "hybrid"},
};
template <>
constexpr std::array kEnumNames<SpecularSampling>{
    EnumName<SpecularSampling>{SpecularSampling::Vndf, "vndf"},
    EnumName<SpecularSampling>{SpecularSampling::Uniform, "uniform"},
};
template <>
constexpr std::array kEnumNames<SpecularReprojection>{
    EnumName<SpecularReprojection>{SpecularReprojection::Surface, "surface"},
    EnumName<SpecularReprojection>{SpecularReprojection::Virtual, "virtual"},
    EnumName<SpecularReprojection>{SpecularReprojection::Dual, "dual"},
};
template <>
constexpr std::array kEnumNames<MotionUnits>{
    EnumName<MotionUnits>{MotionUnits::Pixels, "pixels"},
    EnumName<MotionUnits>{MotionUnits::Uv, "uv"},
};

// The single source of truth, in the order of the structs in gi_settings.h.
// The ranges keep every value inside what the passes are written for (loop
// counts that fit a frame, angles that leave some neighbours, fractions of viewZ).
constexpr std::array kEntries{
    Entry{"diffuse.enabled", inDiffuse(&DiffuseSettings::enabled), kNoBounds,
          "compute indirect diffuse at all (off: the frame has direct light only)"},
    Entry{"diffuse.screen_candidates", inDiffuse(&DiffuseSettings::screenCandidates), closed(0, 64),
          "initial candidates per pixel from random pixels of the previous composited frame"},
    Entry{"diffuse.bright_candidates", inDiffuse(&DiffuseSettings::brightCandidates), closed(0, 64),
          "initial candidates per pixel picked among the brightest pixels of the previous frame"},
    Entry{"diffuse.environment_candidates", inDiffuse(&DiffuseSettings::environmentCandidates), closed(0, 64),
          "initial candidates per pixel from uniform hemisphere directions into the environment (without a scene "
          "bridge; with one, ray candidates take their place)"},
    Entry{"diffuse.ray_candidates", inDiffuse(&DiffuseSettings::rayCandidates), closed(0, 64),
          "with a scene bridge: initial candidates per pixel from cosine-distributed rays, marched through the "
          "depth buffer, then traced through the bridge where the screen cannot decide"},
    Entry{"diffuse.ray_screen_steps", inDiffuse(&DiffuseSettings::rayScreenSteps), closed(0, 64),
          "with a scene bridge: depth-buffer march steps of a ray candidate before it continues through the bridge "
          "(0: straight to the bridge)"},
    Entry{"diffuse.bright_pixels", inDiffuse(&DiffuseSettings::brightPixels), closed(1, 4096),
          "the brightness reduction pyramid stops at about this many pixels to pick bright candidates from"},
    Entry{"diffuse.environment_mip", inDiffuse(&DiffuseSettings::environmentMip), closed(0, 16),
          "level of the prefiltered environment that environment samples read (higher: blurrier, less noise)"},
    Entry{"diffuse.target", inDiffuse(&DiffuseSettings::target), kNoBounds,
          "scalar weight of a sample's radiance in the target function (times the cosine)"},
    Entry{"diffuse.temporal_max_m", inDiffuse(&DiffuseSettings::temporalMaxM), closed(1, 1000),
          "temporal reuse: the history counts as at most this many frames of samples"},
    Entry{"diffuse.temporal_depth_tolerance", inDiffuse(&DiffuseSettings::temporalDepthTolerance), aboveUpTo(0, 1),
          "temporal reuse: reprojected depth may differ by this fraction of viewZ"},
    Entry{"diffuse.temporal_normal_tolerance_degrees", inDiffuse(&DiffuseSettings::temporalNormalToleranceDegrees),
          open(0, 180), "temporal reuse: reprojected normal may differ by this many degrees"},
    Entry{"diffuse.spatial_radius", inDiffuse(&DiffuseSettings::spatialRadius), closed(0, 256),
          "first spatial reuse pass: radius of the disk its neighbours are taken from, in half-resolution pixels"},
    Entry{"diffuse.spatial_samples", inDiffuse(&DiffuseSettings::spatialSamples), closed(0, 64),
          "first spatial reuse pass: neighbours merged per pixel"},
    Entry{"diffuse.spatial2_radius", inDiffuse(&DiffuseSettings::spatial2Radius), closed(0, 256),
          "second spatial reuse pass: radius of the disk its neighbours are taken from, in half-resolution pixels"},
    Entry{"diffuse.spatial2_samples", inDiffuse(&DiffuseSettings::spatial2Samples), closed(0, 64),
          "second spatial reuse pass: neighbours merged per pixel"},
    Entry{"diffuse.spatial_normal_tolerance_degrees", inDiffuse(&DiffuseSettings::spatialNormalToleranceDegrees),
          open(0, 180), "spatial reuse: neighbours whose normal differs by more degrees are rejected"},
    Entry{"diffuse.spatial_plane_tolerance", inDiffuse(&DiffuseSettings::spatialPlaneTolerance), aboveUpTo(0, 1),
          "spatial reuse: neighbours farther from the tangent plane than this fraction of viewZ are rejected"},
    Entry{"diffuse.jacobian", inDiffuse(&DiffuseSettings::jacobian), kNoBounds,
          "apply ReSTIR GI's reconnection Jacobian to reused samples"},
    Entry{"diffuse.spatial_feedback", inDiffuse(&DiffuseSettings::spatialFeedback), kNoBounds,
          "the next frame's temporal reuse starts from the spatially reused reservoirs (the Jitter gi pass's "
          "diffuse ReSTIR) instead of the temporal ones"},
    Entry{"diffuse.resolve_reservoirs", inDiffuse(&DiffuseSettings::resolveReservoirs), closed(1, 4),
          "resolve: neighbouring half-resolution reservoirs each full-resolution pixel evaluates"},
    Entry{"diffuse.visibility_steps", inDiffuse(&DiffuseSettings::visibilitySteps), closed(0, 256),
          "resolve: screen-space ray-march steps from the pixel to each sample (0: no visibility test)"},
    Entry{"diffuse.visibility", inDiffuse(&DiffuseSettings::visibility), kNoBounds,
          "resolve: how a sample's visibility is tested: screen (depth-buffer march), world (an any-hit ray through "
          "the scene bridge) or hybrid (the march, and a world ray where it cannot decide); without a bridge, screen"},
    Entry{"diffuse.reuse_visibility", inDiffuse(&DiffuseSettings::reuseVisibility), kNoBounds,
          "temporal and spatial reuse test each reused sample's visibility with an any-hit ray through the scene "
          "bridge (unbiased reuse; without a bridge, ignored)"},
    Entry{"diffuse.sky_reuse_visibility", inDiffuse(&DiffuseSettings::skyReuseVisibility), kNoBounds,
          "spatial reuse counts a neighbour towards a sky sample's normalisation only if an any-hit ray finds the sky "
          "open from it (less darkening under windows and arches; costs rays; without a bridge, ignored)"},
    Entry{"diffuse.sky_reuse_rays", inDiffuse(&DiffuseSettings::skyReuseRays), closed(0, 64),
          "spatial reuse: neighbours per pass whose view of a sky sample is tested with a ray, at most (16: all); the "
          "others count with the tested ones' share that saw it, which brightens sky light"},
    Entry{"diffuse.visibility_thickness", inDiffuse(&DiffuseSettings::visibilityThickness), aboveUpTo(0, 1),
          "resolve: surfaces are assumed this fraction of their viewZ thick"},
    Entry{"diffuse.variance_clipping_gamma", inDiffuse(&DiffuseSettings::varianceClippingGamma), aboveUpTo(0, 100),
          "temporal filter: history is clamped to the pixel's fast history +- gamma * its temporal sigma"},
    Entry{"diffuse.temporal_filter_frames", inDiffuse(&DiffuseSettings::temporalFilterFrames), closed(1, 1024),
          "temporal filter: the longest history it accumulates, in frames"},
    Entry{"specular.enabled", inSpecular(&SpecularSettings::enabled), kNoBounds,
          "compute indirect specular at all (off: metals and glossy surfaces reflect only direct light)"},
    Entry{"specular.sampling", inSpecular(&SpecularSettings::sampling), kNoBounds,
          "how each pixel's ray is drawn: vndf (GGX visible normals, target BRDF * cos * radiance) or uniform (a cone "
          "around the lobe's dominant direction, view-independent target = radiance, resampled with the BRDF at the "
          "resolve; Zyanide's uniform-lobe reservoirs)"},
    Entry{"specular.lobe_fraction", inSpecular(&SpecularSettings::lobeFraction), open(0, 1),
          "uniform sampling: the cone holds this fraction of the lobe's microfacet normals"},
    Entry{"specular.reuse_min_roughness", inSpecular(&SpecularSettings::reuseMinRoughness), closed(0, 1),
          "below this perceptual roughness no reservoir is reused in time or space: each pixel keeps its own ray"},
    Entry{"specular.trace_steps", inSpecular(&SpecularSettings::traceSteps), closed(0, 512),
          "screen-space march steps of a ray through the depth buffer before it continues through the scene bridge (0: the "
          "bridge at once)"},
    Entry{"specular.trace_thickness", inSpecular(&SpecularSettings::traceThickness), aboveUpTo(0, 1),
          "trace: depth-buffer surfaces are assumed this fraction of their viewZ thick"},
    Entry{"specular.temporal_max_m", inSpecular(&SpecularSettings::temporalMaxM), closed(1, 1000),
          "temporal reuse: the history counts as at most this many frames of samples (short: reflections react fast)"},
    Entry{"specular.temporal_depth_tolerance", inSpecular(&SpecularSettings::temporalDepthTolerance), aboveUpTo(0, 1),
          "temporal reuse and filter: reprojected depth may differ by this fraction of viewZ"},
    Entry{"specular.temporal_normal_tolerance_degrees", inSpecular(&SpecularSettings::temporalNormalToleranceDegrees),
          open(0, 180), "temporal reuse and filter: reprojected normal may differ by this many degrees"},
    Entry{"specular.spatial_samples", inSpecular(&SpecularSettings::spatialSamples), closed(0, 16),
          "spatial reuse: neighbours merged per pixel"},
    Entry{"specular.spatial_max_radius", inSpecular(&SpecularSettings::spatialMaxRadius), closed(0, 256),
          "spatial reuse: the largest radius, in half-resolution pixels (the lobe's footprint at the hit sets it "
          "below that)"},
    Entry{"specular.spatial_normal_tolerance_degrees", inSpecular(&SpecularSettings::spatialNormalToleranceDegrees),
          open(0, 180), "spatial reuse: neighbours whose normal differs by more degrees are rejected"},
    Entry{"specular.spatial_plane_tolerance", inSpecular(&SpecularSettings::spatialPlaneTolerance), aboveUpTo(0, 1),
          "spatial reuse: neighbours farther from the tangent plane than this fraction of viewZ are rejected"},
    Entry{"specular.jacobian", inSpecular(&SpecularSettings::jacobian), kNoBounds,
          "apply ReSTIR GI's reconnection Jacobian to reused samples"},
    Entry{"specular.resolve_max_samples", inSpecular(&SpecularSettings::resolveMaxSamples), closed(1, 16),
          "resolve: reservoirs a pixel evaluates at resolve_full_roughness and above (one for a mirror)"},
    Entry{"specular.resolve_full_roughness", inSpecular(&SpecularSettings::resolveFullRoughness), aboveUpTo(0, 1),
          "resolve: the perceptual roughness at which a pixel evaluates resolve_max_samples reservoirs (linear from "
          "one at 0)"},
    Entry{"specular.resolve_max_radius", inSpecular(&SpecularSettings::resolveMaxRadius), closed(0, 64),
          "resolve: the largest radius neighbours are taken from, in full-resolution pixels (the lobe's footprint "
          "at the hit sets it below that)"},
    Entry{"specular.reprojection", inSpecular(&SpecularSettings::reprojection), kNoBounds,
          "temporal filter: history reprojected with the surface's motion, the reflection's (virtual) motion, or "
          "both blended by roughness and agreement with this frame"},
    Entry{"specular.variance_clipping_gamma", inSpecular(&SpecularSettings::varianceClippingGamma),
          aboveUpTo(0, 100), "temporal filter: history clamped to the fast history +- gamma * temporal sigma"},
    Entry{"specular.temporal_filter_frames", inSpecular(&SpecularSettings::temporalFilterFrames), closed(1, 1024),
          "temporal filter: the longest history, for rough surfaces (smooth ones keep fewer frames)"},
    Entry{"denoise.enabled", inDenoise(&DenoiseSettings::enabled), kNoBounds,
          "denoise both branches' signals with the REBLUR-class denoiser (off: each branch's own temporal filter)"},
    Entry{"denoise.max_accumulated_frames", inDenoise(&DenoiseSettings::maxAccumulatedFrames), closed(1, 255),
          "temporal accumulation: the longest history, in frames (specular: fewer on smooth lobes)"},
    Entry{"denoise.history_fix_frames", inDenoise(&DenoiseSettings::historyFixFrames), closed(0, 32),
          "history fix: pixels with a shorter history are rebuilt from a wide neighbourhood (0: off)"},
    Entry{"denoise.diffuse_pre_pass_radius", inDenoise(&DenoiseSettings::diffusePrePassRadius), closed(0, 128),
          "pre-pass: the widest radius in pixels of the diffuse pre-blur, for light from far away; 0: no pre-pass "
          "(at 1080 rows; scaled with the height)"},
    Entry{"denoise.specular_pre_pass_radius", inDenoise(&DenoiseSettings::specularPrePassRadius), closed(0, 128),
          "pre-pass: the same for specular, also scaled by the roughness and cut to the lobe's footprint; 0: no "
          "pre-pass (at 1080 rows; scaled with the height)"},
    Entry{"denoise.history_fix_stride", inDenoise(&DenoiseSettings::historyFixStride), closed(1, 64),
          "history fix: pixels between its 5x5 taps at a history of 0 frames (at 1080 rows; scaled with the height)"},
    Entry{"denoise.blur_radius", inDenoise(&DenoiseSettings::blurRadius), closed(0, 128),
          "blur: radius in pixels at the first frame of a history, shrinking as sqrt(1 / (1 + history length)) (at "
          "1080 rows; scaled with the height)"},
    Entry{"denoise.min_blur_radius", inDenoise(&DenoiseSettings::minBlurRadius), closed(0, 128),
          "blur: the smallest radius in pixels, however long the history (at 1080 rows; scaled with the height)"},
    Entry{"denoise.post_blur_radius_scale", inDenoise(&DenoiseSettings::postBlurRadiusScale), closed(0, 4),
          "post-blur: its radius as a fraction of blur's"},
    Entry{"denoise.plane_distance_sensitivity", inDenoise(&DenoiseSettings::planeDistanceSensitivity),
          aboveUpTo(0, 1), "spatial passes: a neighbour this fraction of viewZ off the pixel's plane weighs 0"},
    Entry{"denoise.lobe_angle_fraction", inDenoise(&DenoiseSettings::lobeAngleFraction), aboveUpTo(0, 1),
          "spatial passes: the normal weight's cone holds 0.75 * this^2 of the lobe once the history is long (0.75 "
          "at its start)"},
    Entry{"denoise.roughness_fraction", inDenoise(&DenoiseSettings::roughnessFraction), aboveUpTo(0, 4),
          "spatial passes (specular): a neighbour's roughness may differ by this fraction of the pixel's"},
    Entry{"denoise.stabilization_frames", inDenoise(&DenoiseSettings::stabilizationFrames), closed(0, 255),
          "temporal stabilisation: its longest history, in frames (0: off)"},
    Entry{"denoise.disocclusion_threshold", inDenoise(&DenoiseSettings::disocclusionThreshold), aboveUpTo(0, 1),
          "temporal accumulation: last frame's depth may differ by this fraction of the frustum's width seen "
          "head-on (plus a pixel; wider at grazing angles and for a still camera)"},
    Entry{"denoise.normal_tolerance_degrees", inDenoise(&DenoiseSettings::normalToleranceDegrees), open(0, 180),
          "temporal passes: a reprojected history's normal may differ from the pixel's by this many degrees"},
    Entry{"denoise.depth_tolerance", inDenoise(&DenoiseSettings::depthTolerance), aboveUpTo(0, 1),
          "temporal stabilisation and the reflection's (virtual) history (specular kind): reprojected depth may "
          "differ by this fraction of viewZ"},
    Entry{"denoise.clamp_sigma", inDenoise(&DenoiseSettings::clampSigma), aboveUpTo(0, 100),
          "history clamping (accumulation and stabilisation): mean +- this many sigma"},
    Entry{"denoise.anti_firefly", inDenoise(&DenoiseSettings::antiFirefly), kNoBounds,
          "history fix brings a pixel above its neighbours' mean + 2 sigma down to it"},
    Entry{"denoise.checkerboard", inDenoise(&DenoiseSettings::checkerboard), kNoBounds,
          "the engine's noisy signals (FrameInputs::noisy) are checkerboarded, as REBLUR's checkerboard mode: "
          "ceil(width / 2) x height, pixel (x, y) stored at (x / 2, y) where x + y + frameIndex is odd (kind "
          "diffuse) or even (kind specular); the pre-pass fills the other pixels. Ignored for the branches' own "
          "signals, which are full resolution"},
    Entry{"cache.enabled", inCache(&CacheSettings::enabled), kNoBounds,
          "the world-space radiance cache lights what world rays hit off screen (more bounces; needs a scene bridge)"},
    Entry{"cache.memory_mib", inCache(&CacheSettings::memoryMib), closed(1, 128),
          "radiance cache: device memory for its cells at most, in MiB"},
    Entry{"cache.cell_size", inCache(&CacheSettings::cellSize), closed(0.0005, 0.5),
          "radiance cache: a cell's edge as a fraction of its distance to the camera (rounded to a power of two)"},
    Entry{"cache.update_rays", inCache(&CacheSettings::updateRays), closed(0, 1 << 21),
          "radiance cache: closest-hit rays per frame of its update paths, at most"},
    Entry{"cache.update_bounces", inCache(&CacheSettings::updateBounces), closed(1, shared::kCacheMaxBounces),
          "radiance cache: surfaces each update path bounces off at most (bounces of light carried in one frame)"},
    Entry{"cache.history_samples", inCache(&CacheSettings::historySamples), closed(1, 4096),
          "radiance cache: a cell's value averages at most this many samples (fewer: follows light changes faster)"},
    Entry{"cache.max_age", inCache(&CacheSettings::maxAge), closed(1, 1 << 20),
          "radiance cache: cells nobody used for this many frames are evicted"},
    Entry{"cache.inject_stride", inCache(&CacheSettings::injectStride), closed(1, 64),
          "radiance cache: the screen fills cells from one pixel of every stride x stride block of the last frame"},
    Entry{"cache.direct_light", inCache(&CacheSettings::directLight), kNoBounds,
          "radiance cache: cells also hold the direct light at their point, and the diffuse ray candidates' hits "
          "take theirs from there instead of a shadow ray each"},
    Entry{"input.motion_units", inInput(&InputSettings::motionUnits), kNoBounds,
          "what the engine's motion vectors are in: pixels, or uv (fractions of the render size)"},
    Entry{"input.motion_scale_x", inInput(&InputSettings::motionScaleX), closed(-1e6, 1e6),
          "multiplies the motion vectors' x (after the units): -1 for engines whose x points the other way"},
    Entry{"input.motion_scale_y", inInput(&InputSettings::motionScaleY), closed(-1e6, 1e6),
          "multiplies the motion vectors' y (after the units): -1 for engines whose y points up, or that store "
          "current - previous"},
    Entry{"restir", inSettings(&Settings::restir), kNoBounds,
          "temporal and spatial reuse (off: the no-reuse baseline; gathering, resolve and filters stay)"},
    Entry{"seed", inSettings(&Settings::seed), kAnyUint, "random seed; another seed gives other, independent noise"},
    Entry{"world_ray_budget", inSettings(&Settings::worldRayBudget), aboveUpTo(0, 64),
          "world rays per pixel and frame the library may cast through a scene bridge, at most: after what the "
          "settings fix and one ray candidate, sky tests in spatial reuse, then the other ray candidates are cut to "
          "fit (cache updates and the bridge's shadow rays not counted)"},
};

std::string lowercase(std::string_view text) {
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c); });
  return lower;
}

template <typename Number>
std::string formatNumber(Number value) {
  // to_chars without a precision gives the shortest text that parses back to the same value.
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

template <typename E>
std::string_view enumName(E value) {
  for (const EnumName<E>& entry : kEnumNames<E>) {
    if (entry.value == value) return entry.name;
  }
  return {};
}

template <typename E>
std::string enumList(std::string_view separator, std::string_view lastSeparator) {
  std::string text;
  for (std::size_t i = 0; i < kEnumNames<E>.size(); ++i) {
    if (i > 0) text += i + 1 == kEnumNames<E>.size() ? lastSeparator : separator;
    text += kEnumNames<E>[i].name;
  }
  return text;
}

std::string describeBounds(const Bounds& bounds) {
  return std::string(bounds.excludeMin ? "(" : "[") + formatNumber(bounds.min) + ", " + formatNumber(bounds.max) +
         (bounds.excludeMax ? ")" : "]");
}

std::string typeText(const Entry& entry) {
  return std::visit(
      [&](const auto& member) -> std::string {
        using T = std::remove_cvref_t<decltype(member.of(std::declval<Settings&>()))>;
        if constexpr (std::is_same_v<T, bool>) {
          return "bool";
        } else if constexpr (std::is_enum_v<T>) {
          return "enum: " + enumList<T>("|", "|");
        } else if constexpr (std::is_same_v<T, std::uint32_t>) {
          return "uint " + describeBounds(entry.bounds);
        } else {
          return "float " + describeBounds(entry.bounds);
        }
      },
      entry.field);
}

// What a key accepts, phrased for the end of an error message.
std::string acceptedText(const Entry& entry) {
  return std::visit(
      [&](const auto& member) -> std::string {
        using T = std::remove_cvref_t<decltype(member.of(std::declval<Settings&>()))>;
        if constexpr (std::is_same_v<T, bool>) {
          return "on, off, true, false, yes, no, 1 or 0";
        } else if constexpr (std::is_enum_v<T>) {
          return enumList<T>(", ", " or ");
        } else if constexpr (std::is_same_v<T, std::uint32_t>) {
          return "an integer in " + describeBounds(entry.bounds);
        } else {
          return "a number in " + describeBounds(entry.bounds);
        }
      },
      entry.field);
}

[[noreturn]] void throwBadValue(const Entry& entry, std::string_view value) {
  throw std::invalid_argument("invalid value \"" + std::string(value) + "\" for " + std::string(kKeyPrefix) +
                              std::string(entry.key) + ": expected " + acceptedText(entry));
}

std::optional<bool> parseBool(std::string_view text) {
  const std::string lower = lowercase(text);
  if (lower == "on" || lower == "true" || lower == "yes" || lower == "1") return true;
  if (lower == "off" || lower == "false" || lower == "no" || lower == "0") return false;
  return std::nullopt;
}

// from_chars takes no sign for unsigned types, no leading space and no "0x";
// requiring it to consume all the text also rejects "2.5" and "3x".
template <typename Number>
std::optional<Number> parseNumber(std::string_view text) {
  Number value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  if constexpr (std::is_floating_point_v<Number>) {
    if (!std::isfinite(value)) return std::nullopt;
  }
  return value;
}

template <typename E>
std::optional<E> parseEnum(std::string_view text) {
  const std::string lower = lowercase(text);
  for (const EnumName<E>& entry : kEnumNames<E>) {
    if (entry.name == lower) return entry.value;
  }
  return std::nullopt;
}

void applyToField(Settings& settings, const Entry& entry, std::string_view text) {
  std::visit(
      [&](const auto& member) {
        using T = std::remove_cvref_t<decltype(member.of(settings))>;
        std::optional<T> value;
        if constexpr (std::is_same_v<T, bool>) {
          value = parseBool(text);
        } else if constexpr (std::is_enum_v<T>) {
          value = parseEnum<T>(text);
        } else {
          value = parseNumber<T>(text);
          if (value && !entry.bounds.contains(static_cast<double>(*value))) value.reset();
        }
        if (!value) throwBadValue(entry, text);
        member.of(settings) = *value;
      },
      entry.field);
}

std::string formatField(const Settings& settings, const Entry& entry) {
  return std::visit(
      [&](const auto& member) -> std::string {
        const auto& value = member.of(settings);
        using T = std::remove_cvref_t<decltype(value)>;
        if constexpr (std::is_same_v<T, bool>) {
          return value ? "on" : "off";
        } else if constexpr (std::is_enum_v<T>) {
          const std::string_view name = enumName(value);
          // A value cast in code from an unknown number has no name; show the number so validate() can say which.
          return name.empty() ? formatNumber(static_cast<std::uint32_t>(value)) : std::string(name);
        } else {
          return formatNumber(value);
        }
      },
      entry.field);
}

bool fieldIsValid(const Settings& settings, const Entry& entry) {
  return std::visit(
      [&](const auto& member) {
        const auto& value = member.of(settings);
        using T = std::remove_cvref_t<decltype(value)>;
        if constexpr (std::is_same_v<T, bool>) {
          return true;
        } else if constexpr (std::is_enum_v<T>) {
          return !enumName(value).empty();
        } else {
          // NaN fails both comparisons of contains(), so it is refused here too.
          return entry.bounds.contains(static_cast<double>(value));
        }
      },
      entry.field);
}

std::string_view lastSegment(std::string_view key) {
  const std::size_t dot = key.rfind('.');
  return dot == std::string_view::npos ? key : key.substr(dot + 1);
}

// Near misses of `key`: typos of the whole key, and the right field name
// under a missing or wrong struct prefix ("spatial_radius", "restir.seed").
std::vector<std::string_view> closestKeys(std::string_view key) {
  const std::string_view field = lastSegment(key);
  const std::size_t tolerance = std::max<std::size_t>(2, field.size() / 4);
  std::vector<std::pair<std::size_t, std::string_view>> scored;
  for (const Entry& entry : kEntries) {
    std::size_t distance = util::editDistance(key, entry.key);
    const std::string_view entryField = lastSegment(entry.key);
    distance = std::min(distance, util::editDistance(field, entryField) + 1);
    const bool fieldNameContainsTypedName = field.size() >= 4 && entryField.find(field) != std::string_view::npos;
    if (fieldNameContainsTypedName) distance = std::min<std::size_t>(distance, 2);
    if (distance <= tolerance) scored.emplace_back(distance, entry.key);
  }
  std::stable_sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  constexpr std::size_t kMaxSuggestions = 3;
  std::vector<std::string_view> closest;
  for (std::size_t i = 0; i < scored.size() && i < kMaxSuggestions; ++i) closest.push_back(scored[i].second);
  return closest;
}

// Keys may be given with or without the "gi." that the command line writes,
// so a JSON file may wrap everything in {"gi": {...}} or use "gi.seed".
const Entry& findEntry(std::string_view key) {
  const std::string_view relative = key.starts_with(kKeyPrefix) ? key.substr(kKeyPrefix.size()) : key;
  for (const Entry& entry : kEntries) {
    if (entry.key == relative) return entry;
  }
  std::string message = "unknown setting " + std::string(kKeyPrefix) + std::string(relative);
  const std::vector<std::string_view> closest = closestKeys(relative);
  if (closest.empty()) {
    message += " (see bounce render --help for every gi.* setting)";
  } else {
    message += "; did you mean ";
    for (std::size_t i = 0; i < closest.size(); ++i) {
      if (i > 0) message += i + 1 == closest.size() ? " or " : ", ";
      message += std::string(kKeyPrefix) + std::string(closest[i]);
    }
    message += "?";
  }
  throw std::invalid_argument(message);
}

template <typename T, typename Struct>
const Entry& entryOf(T Struct::*member) {
  for (const Entry& entry : kEntries) {
    const auto* field = std::get_if<Member<T>>(&entry.field);
    if (!field) continue;
    if constexpr (std::is_same_v<Struct, DiffuseSettings>) {
      if (field->diffuse == member) return entry;
    } else if constexpr (std::is_same_v<Struct, InputSettings>) {
      if (field->input == member) return entry;
    } else {
      if (field->top == member) return entry;
    }
  }
  throw std::logic_error("gi settings: a field used by validate() has no entry in the settings table");
}

std::string userKey(const Entry& entry) { return std::string(kKeyPrefix) + std::string(entry.key); }

// JSON values become the text applySetting takes, so a file and the command
// line go through the same parsing and range checks.
std::string jsonValueText(const nlohmann::json& value, const std::string& key) {
  switch (value.type()) {
    case nlohmann::json::value_t::boolean:
      return value.get<bool>() ? "true" : "false";
    case nlohmann::json::value_t::number_unsigned:
      return std::to_string(value.get<std::uint64_t>());
    case nlohmann::json::value_t::number_integer:
      return std::to_string(value.get<std::int64_t>());
    case nlohmann::json::value_t::number_float:
      return formatNumber(value.get<double>());
    case nlohmann::json::value_t::string:
      return value.get<std::string>();
    default:
      throw std::invalid_argument(std::string(kKeyPrefix) + key + ": got a JSON " + std::string(value.type_name()) +
                                  ", expected a number, a bool, a string or an object of settings");
  }
}

// {"diffuse": {"spatial_radius": 24}} and {"diffuse.spatial_radius": 24} both give "diffuse.spatial_radius".
void flattenJson(const nlohmann::json& object, const std::string& prefix,
                 std::vector<std::pair<std::string, std::string>>& keyValues) {
  for (const auto& [name, value] : object.items()) {
    const std::string key = prefix.empty() ? name : prefix + "." + name;
    if (value.is_object()) {
      flattenJson(value, key, keyValues);
    } else {
      keyValues.emplace_back(key, jsonValueText(value, key));
    }
  }
}

// Far deeper than any settings file ({"gi": {"diffuse": {...}}} is three);
// refused while parsing, before flattenJson's recursion could run out of
// stack on a hostile file.
constexpr int kMaxJsonDepth = 64;

// Refuses a key written twice in one object (JSON keeps the last silently;
// a file that sets a key twice is a mistake either way), naming it by its
// dotted path. Throws std::invalid_argument.
class RepeatedKeyCheck {
 public:
  void objectStart() {
    const std::string parent = open_.empty() ? "" : open_.back().path;
    open_.push_back({{}, open_.empty() ? "" : (parent.empty() ? lastKey_ : parent + "." + lastKey_)});
  }
  void objectEnd() { open_.pop_back(); }
  void key(const std::string& name) {
    lastKey_ = name;
    if (open_.back().keys.insert(name).second) return;
    const std::string& path = open_.back().path;
    const std::string key = path.empty() ? name : path + "." + name;
    throw std::invalid_argument((key.starts_with(kKeyPrefix) ? key : std::string(kKeyPrefix) + key) +
                                " is given more than once");
  }

 private:
  struct OpenObject {
    std::unordered_set<std::string> keys;
    std::string path;  // dotted path of the object, "" at the top
  };
  std::vector<OpenObject> open_;
  std::string lastKey_;
};

// Parses a settings file, refusing nesting deeper than kMaxJsonDepth and a
// key written twice in one object. Throws std::invalid_argument for those,
// nlohmann's exceptions for bad JSON.
nlohmann::json parseSettingsJson(std::istream& stream) {
  try {
    return util::parseJson(stream, kMaxJsonDepth, RepeatedKeyCheck{});
  } catch (const util::JsonTooDeep& tooDeep) {
    throw std::invalid_argument(tooDeep.what());
  }
}

}  // namespace

const std::vector<SettingInfo>& settingKeys() {
  static const std::vector<SettingInfo> keys = [] {
    const Settings defaults;
    std::vector<SettingInfo> infos;
    infos.reserve(kEntries.size());
    for (const Entry& entry : kEntries) {
      infos.push_back(
          {std::string(entry.key), typeText(entry), formatField(defaults, entry), std::string(entry.description)});
    }
    return infos;
  }();
  return keys;
}

void applySetting(Settings& settings, const std::string& key, const std::string& value) {
  applyToField(settings, findEntry(key), value);
}

void applySettingsFile(Settings& settings, const std::filesystem::path& file) {
  const std::string where = file.string() + ": ";
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) {
    throw std::runtime_error(where + (std::filesystem::exists(file, error) ? "not a regular file" : "no such file"));
  }
  std::ifstream stream(file);
  if (!stream) throw std::runtime_error(where + "cannot be opened for reading");

  nlohmann::json root;
  try {
    root = parseSettingsJson(stream);
  } catch (const nlohmann::json::exception& parseError) {
    throw std::runtime_error(where + util::withoutJsonExceptionTag(parseError.what()));
  } catch (const std::invalid_argument& invalid) {
    throw std::runtime_error(where + invalid.what());
  }
  if (!root.is_object()) {
    throw std::runtime_error(where + "the top level is a JSON " + std::string(root.type_name()) +
                             ", expected an object of settings such as {\"diffuse\": {\"spatial_radius\": 24}}");
  }

  // Applied to a copy so that a file refused half-way leaves no half of it behind.
  Settings updated = settings;
  try {
    std::vector<std::pair<std::string, std::string>> keyValues;
    flattenJson(root, "", keyValues);
    // With the nested and the dotted form of one key in one file, which one
    // wins would be up to the JSON library's member order; refuse it instead.
    std::vector<const Entry*> seen;
    for (const auto& [key, value] : keyValues) {
      const Entry& entry = findEntry(key);
      if (std::find(seen.begin(), seen.end(), &entry) != seen.end()) {
        throw std::invalid_argument(userKey(entry) + " is given more than once");
      }
      seen.push_back(&entry);
      applyToField(updated, entry, value);
    }
  } catch (const std::invalid_argument& invalid) {
    throw std::runtime_error(where + invalid.what());
  }
  settings = updated;
}

std::string settingValue(const Settings& settings, const std::string& key) {
  return formatField(settings, findEntry(key));
}

void validate(const Settings& settings) {
  for (const Entry& entry : kEntries) {
    if (!fieldIsValid(settings, entry)) throwBadValue(entry, formatField(settings, entry));
  }
  const DiffuseSettings& diffuse = settings.diffuse;
  if (diffuse.enabled && diffuse.screenCandidates == 0 && diffuse.brightCandidates == 0 &&
      diffuse.environmentCandidates == 0) {
    // With no initial candidate every reservoir stays empty: the diffuse output would be black, silently.
    throw std::invalid_argument(userKey(entryOf(&DiffuseSettings::screenCandidates)) + ", " +
                                userKey(entryOf(&DiffuseSettings::brightCandidates)) + " and " +
                                userKey(entryOf(&DiffuseSettings::environmentCandidates)) + " are all 0 while " +
                                userKey(entryOf(&DiffuseSettings::enabled)) +
                                " is on: at least one must be above 0 (or turn diffuse off)");
  }
  planWorldRays(settings);
}

std::uint32_t WorldRayPlan::perReservoir() const {
  return diffuseCandidates + skyReuseRays * spatialPasses + reuseVisibility + sampleVisibility + resolveVisibility +
         specular;
}

WorldRayPlan planWorldRays(const Settings& settings) {
  const DiffuseSettings& d = settings.diffuse;
  WorldRayPlan plan;
  const std::uint32_t spatialPasses =
      settings.restir ? (d.spatialSamples > 0 ? 1u : 0u) + (d.spatial2Samples > 0 ? 1u : 0u) : 0u;
  std::vector<std::string> fixedBy;
  if (d.enabled) {
    plan.spatialPasses = spatialPasses;
    if (d.reuseVisibility && settings.restir) {
      // Temporal reuse tests the history; each spatial pass tests every
      // neighbour it merges and again each one it normalises by.
      plan.reuseVisibility = 1u + 2u * (std::min(d.spatialSamples, shared::kMaxSpatialNeighbours) +
                                        std::min(d.spatial2Samples, shared::kMaxSpatialNeighbours));
      fixedBy.push_back(userKey(entryOf(&DiffuseSettings::reuseVisibility)) + " on");
    }
    if (d.visibility == Visibility::Hybrid) plan.sampleVisibility = 1;
    if (d.visibility == Visibility::World) {
      plan.resolveVisibility = 4u * d.resolveReservoirs;
      fixedBy.push_back(userKey(entryOf(&DiffuseSettings::visibility)) + " world");
    }
  }
  if (settings.specular.enabled) plan.specular = 1;
  const double budget = 4.0 * double(settings.worldRayBudget);  // per reservoir of four pixels
  const std::uint32_t fixed = plan.reuseVisibility + plan.sampleVisibility + plan.resolveVisibility + plan.specular;
  if (double(fixed) > budget + 1e-9) {
    std::string what = "the world rays the settings fix";
    if (!fixedBy.empty()) {
      what += " (";
      for (std::size_t i = 0; i < fixedBy.size(); ++i) what += (i ? ", " : "") + fixedBy[i];
      what += ")";
    }
    char needed[64];
    std::snprintf(needed, sizeof needed, "%g", double(fixed) / 4.0);
    throw std::invalid_argument(userKey(entryOf(&Settings::worldRayBudget)) + " = " +
                                formatField(settings, entryOf(&Settings::worldRayBudget)) + " is below " + what + ": " +
                                needed + " per pixel; raise it to at least that");
  }
  double left = budget - double(fixed);
  // As many as wanted of rays costing `each`, within what is left.
  const auto take = [&](std::uint32_t wanted, std::uint32_t each) {
    const std::uint32_t n = std::min(wanted, std::uint32_t((left + 1e-9) / double(each)));
    left -= double(n * each);
    return n;
  };
  if (!d.enabled) return plan;
  // One ray candidate before anything else: without one nothing off screen
  // lights the branch (sun-room: a third of the light); then the sky tests
  // of both passes (at most one per neighbour a pass merges); then the rest.
  plan.diffuseCandidates = take(std::min(d.rayCandidates, 1u), 1);
  if (d.skyReuseVisibility && !d.reuseVisibility && spatialPasses > 0) {
    const std::uint32_t neighbours =
        std::min(std::max(d.spatialSamples, d.spatial2Samples), shared::kMaxSpatialNeighbours);
    plan.skyReuseRays = take(std::min(d.skyReuseRays, neighbours), spatialPasses);
  }
  plan.diffuseCandidates += take(d.rayCandidates - plan.diffuseCandidates, 1);
  return plan;
}

}  // namespace bounce::gi
