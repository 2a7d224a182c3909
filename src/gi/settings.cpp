// The settings layer of gi_settings.h: one table of every settable field
// (key, member, range, description; each unit's section in its own folder,
// gi/settings_table.h) from which the key list, the parser, the printer and
// the validator are all derived.
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

#include "gi/diffuse/diffuse_common.glsl"
#include "gi/settings_table.h"
#include "util/edit_distance.h"
#include "util/json_error.h"
#include "util/json_parse.h"

namespace bounce::gi {
namespace {

using namespace settings_table;

constexpr std::string_view kKeyPrefix = "gi.";

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

// The single source of truth: the units' sections (gi/settings_table.h), in
// the order of the structs in gi_settings.h. The ranges keep every value
// inside what the passes are written for (loop counts that fit a frame,
// angles that leave some neighbours, fractions of viewZ).
const std::vector<Entry>& entries() {
  static const std::vector<Entry> table = [] {
    std::vector<Entry> all;
    for (const std::span<const Entry> section :
         {diffuseSection(), specularSection(), denoiseSection(), cacheSection(), frameSection()})
      all.insert(all.end(), section.begin(), section.end());
    return all;
  }();
  return table;
}

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
  for (const Entry& entry : entries()) {
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
  for (const Entry& entry : entries()) {
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
  for (const Entry& entry : entries()) {
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
    infos.reserve(entries().size());
    for (const Entry& entry : entries()) {
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
  for (const Entry& entry : entries()) {
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

void validate(const Settings& settings, bool bridgeTraces) {
  validate(settings);
  const DiffuseSettings& diffuse = settings.diffuse;
  if (!bridgeTraces || !diffuse.enabled || diffuse.screenCandidates > 0 || diffuse.brightCandidates > 0) return;
  // With a bridge that traces, ray candidates take the environment
  // candidates' place (the diffuse unit's own check, made only once the
  // library is built: after a scene has loaded).
  if (planWorldRays(settings).diffuseCandidates > 0) return;
  const std::string rays = userKey(entryOf(&DiffuseSettings::rayCandidates));
  throw std::invalid_argument(
      userKey(entryOf(&DiffuseSettings::screenCandidates)) + " and " +
      userKey(entryOf(&DiffuseSettings::brightCandidates)) + " are 0 and " +
      (diffuse.rayCandidates == 0 ? rays + " is 0"
                                  : userKey(entryOf(&Settings::worldRayBudget)) + " " +
                                        formatField(settings, entryOf(&Settings::worldRayBudget)) +
                                        " leaves no ray for " + rays) +
      " while " + userKey(entryOf(&DiffuseSettings::enabled)) +
      " is on with a scene bridge that traces (its rays replace " +
      userKey(entryOf(&DiffuseSettings::environmentCandidates)) +
      "): every reservoir would stay empty; raise one of them above 0 (or turn diffuse off)");
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
