// The table every gi.* setting is derived from (src/gi/settings.cpp: the
// key list, the parser, the printer and the validator): each entry a key, a
// member of Settings, a range and a description. Each unit owns its section
// of the table, in its own folder (diffuse/diffuse_settings.cpp, ...);
// settings.cpp joins them in the order of gi_settings.h's structs, so a new
// field is added in its unit's section and cannot be parsed but not
// validated, or listed but not parsed.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <string_view>
#include <variant>

#include "bounce/gi_settings.h"

namespace bounce::gi::settings_table {

// A field is in DiffuseSettings, SpecularSettings, CacheSettings, InputSettings, DenoiseSettings or directly in
// Settings; keeping the pointer-to-member (not a lambda) lets validate() find a key from its field.
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
           : input    ? settings.input.*input
           : denoise  ? settings.denoise.*denoise
                      : settings.*top;
  }
  const T& of(const Settings& settings) const {
    return diffuse    ? settings.diffuse.*diffuse
           : specular ? settings.specular.*specular
           : cache    ? settings.cache.*cache
           : input    ? settings.input.*input
           : denoise  ? settings.denoise.*denoise
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
using Field =
    std::variant<Member<bool>, Member<std::uint32_t>, Member<float>, Member<TargetFunction>, Member<MotionUnits>,
                 Member<Visibility>, Member<SpecularSampling>, Member<SpecularReprojection>>;

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

// The sections, each in its unit's folder.
std::span<const Entry> diffuseSection();   // gi.diffuse.*: src/gi/diffuse/diffuse_settings.cpp
std::span<const Entry> specularSection();  // gi.specular.*: src/gi/specular/specular_settings.cpp
std::span<const Entry> denoiseSection();   // gi.denoise.*: src/gi/denoise/denoise_settings.cpp
std::span<const Entry> cacheSection();     // gi.cache.*: src/gi/cache/cache_settings.cpp
// gi.input.* (how the engine's images are read) and the frame's own keys
// (gi.restir, gi.seed, gi.world_ray_budget): src/gi/frame_settings.cpp.
std::span<const Entry> frameSection();

}  // namespace bounce::gi::settings_table
