// Tests of src/gi/settings.cpp: the key table, parsing of every value type,
// ranges, the JSON settings file, validate(), and that docs/gi-settings.md
// lists every key as the code has it. CPU only.
#include "bounce/gi_settings.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "gi/image_table.h"
#include "gi/unit_catalog.h"
#include "gi/units.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

// The key each field must have, written out independently of the table in
// settings.cpp, so a misspelt key, a key bound to the wrong field or a field
// left out of the table fails here.
struct ExpectedField {
  std::string key;
  std::function<double(const Settings&)> read;
};

std::vector<ExpectedField> expectedFields() {
  return {
      {"diffuse.enabled", [](const Settings& s) { return double(s.diffuse.enabled); }},
      {"diffuse.screen_candidates", [](const Settings& s) { return double(s.diffuse.screenCandidates); }},
      {"diffuse.bright_candidates", [](const Settings& s) { return double(s.diffuse.brightCandidates); }},
      {"diffuse.environment_candidates", [](const Settings& s) { return double(s.diffuse.environmentCandidates); }},
      {"diffuse.ray_candidates", [](const Settings& s) { return double(s.diffuse.rayCandidates); }},
      {"diffuse.ray_screen_steps", [](const Settings& s) { return double(s.diffuse.rayScreenSteps); }},
      {"diffuse.bright_pixels", [](const Settings& s) { return double(s.diffuse.brightPixels); }},
      {"diffuse.environment_mip", [](const Settings& s) { return double(s.diffuse.environmentMip); }},
      {"diffuse.target", [](const Settings& s) { return double(s.diffuse.target); }},
      {"diffuse.temporal_max_m", [](const Settings& s) { return double(s.diffuse.temporalMaxM); }},
      {"diffuse.temporal_depth_tolerance", [](const Settings& s) { return double(s.diffuse.temporalDepthTolerance); }},
      {"diffuse.temporal_normal_tolerance_degrees",
       [](const Settings& s) { return double(s.diffuse.temporalNormalToleranceDegrees); }},
      {"diffuse.spatial_radius", [](const Settings& s) { return double(s.diffuse.spatialRadius); }},
      {"diffuse.spatial_samples", [](const Settings& s) { return double(s.diffuse.spatialSamples); }},
      {"diffuse.spatial2_radius", [](const Settings& s) { return double(s.diffuse.spatial2Radius); }},
      {"diffuse.spatial2_samples", [](const Settings& s) { return double(s.diffuse.spatial2Samples); }},
      {"diffuse.spatial_normal_tolerance_degrees",
       [](const Settings& s) { return double(s.diffuse.spatialNormalToleranceDegrees); }},
      {"diffuse.spatial_plane_tolerance", [](const Settings& s) { return double(s.diffuse.spatialPlaneTolerance); }},
      {"diffuse.jacobian", [](const Settings& s) { return double(s.diffuse.jacobian); }},
      {"diffuse.spatial_feedback", [](const Settings& s) { return double(s.diffuse.spatialFeedback); }},
      {"diffuse.resolve_reservoirs", [](const Settings& s) { return double(s.diffuse.resolveReservoirs); }},
      {"diffuse.visibility_steps", [](const Settings& s) { return double(s.diffuse.visibilitySteps); }},
      {"diffuse.visibility", [](const Settings& s) { return double(s.diffuse.visibility); }},
      {"diffuse.per_pixel_visibility", [](const Settings& s) { return double(s.diffuse.perPixelVisibility); }},
      {"diffuse.screen_visibility_per_reservoir",
       [](const Settings& s) { return double(s.diffuse.screenVisibilityPerReservoir); }},
      {"diffuse.reuse_visibility", [](const Settings& s) { return double(s.diffuse.reuseVisibility); }},
      {"diffuse.sky_reuse_visibility", [](const Settings& s) { return double(s.diffuse.skyReuseVisibility); }},
      {"diffuse.sky_reuse_rays", [](const Settings& s) { return double(s.diffuse.skyReuseRays); }},
      {"diffuse.visibility_thickness", [](const Settings& s) { return double(s.diffuse.visibilityThickness); }},
      {"diffuse.variance_clipping_gamma", [](const Settings& s) { return double(s.diffuse.varianceClippingGamma); }},
      {"diffuse.temporal_filter_frames", [](const Settings& s) { return double(s.diffuse.temporalFilterFrames); }},
      {"specular.enabled", [](const Settings& s) { return double(s.specular.enabled); }},
      {"specular.sampling", [](const Settings& s) { return double(s.specular.sampling); }},
      {"specular.lobe_fraction", [](const Settings& s) { return double(s.specular.lobeFraction); }},
      {"specular.reuse_min_roughness", [](const Settings& s) { return double(s.specular.reuseMinRoughness); }},
      {"specular.diffuse_sample_roughness",
       [](const Settings& s) { return double(s.specular.diffuseSampleRoughness); }},
      {"specular.cached_direct_roughness",
       [](const Settings& s) { return double(s.specular.cachedDirectRoughness); }},
      {"specular.trace_steps", [](const Settings& s) { return double(s.specular.traceSteps); }},
      {"specular.trace_thickness", [](const Settings& s) { return double(s.specular.traceThickness); }},
      {"specular.temporal_max_m", [](const Settings& s) { return double(s.specular.temporalMaxM); }},
      {"specular.temporal_depth_tolerance",
       [](const Settings& s) { return double(s.specular.temporalDepthTolerance); }},
      {"specular.temporal_normal_tolerance_degrees",
       [](const Settings& s) { return double(s.specular.temporalNormalToleranceDegrees); }},
      {"specular.spatial_samples", [](const Settings& s) { return double(s.specular.spatialSamples); }},
      {"specular.spatial_max_radius", [](const Settings& s) { return double(s.specular.spatialMaxRadius); }},
      {"specular.spatial_normal_tolerance_degrees",
       [](const Settings& s) { return double(s.specular.spatialNormalToleranceDegrees); }},
      {"specular.spatial_plane_tolerance", [](const Settings& s) { return double(s.specular.spatialPlaneTolerance); }},
      {"specular.jacobian", [](const Settings& s) { return double(s.specular.jacobian); }},
      {"specular.resolve_max_samples", [](const Settings& s) { return double(s.specular.resolveMaxSamples); }},
      {"specular.resolve_full_roughness", [](const Settings& s) { return double(s.specular.resolveFullRoughness); }},
      {"specular.resolve_max_radius", [](const Settings& s) { return double(s.specular.resolveMaxRadius); }},
      {"specular.reprojection", [](const Settings& s) { return double(s.specular.reprojection); }},
      {"specular.variance_clipping_gamma", [](const Settings& s) { return double(s.specular.varianceClippingGamma); }},
      {"specular.temporal_filter_frames", [](const Settings& s) { return double(s.specular.temporalFilterFrames); }},
      {"denoise.enabled", [](const Settings& s) { return double(s.denoise.enabled); }},
      {"denoise.max_accumulated_frames", [](const Settings& s) { return double(s.denoise.maxAccumulatedFrames); }},
      {"denoise.history_fix_frames", [](const Settings& s) { return double(s.denoise.historyFixFrames); }},
      {"denoise.diffuse_pre_pass_radius", [](const Settings& s) { return double(s.denoise.diffusePrePassRadius); }},
      {"denoise.specular_pre_pass_radius", [](const Settings& s) { return double(s.denoise.specularPrePassRadius); }},
      {"denoise.history_fix_stride", [](const Settings& s) { return double(s.denoise.historyFixStride); }},
      {"denoise.blur_radius", [](const Settings& s) { return double(s.denoise.blurRadius); }},
      {"denoise.min_blur_radius", [](const Settings& s) { return double(s.denoise.minBlurRadius); }},
      {"denoise.post_blur_radius_scale", [](const Settings& s) { return double(s.denoise.postBlurRadiusScale); }},
      {"denoise.plane_distance_sensitivity",
       [](const Settings& s) { return double(s.denoise.planeDistanceSensitivity); }},
      {"denoise.lobe_angle_fraction", [](const Settings& s) { return double(s.denoise.lobeAngleFraction); }},
      {"denoise.roughness_fraction", [](const Settings& s) { return double(s.denoise.roughnessFraction); }},
      {"denoise.stabilization_frames", [](const Settings& s) { return double(s.denoise.stabilizationFrames); }},
      {"denoise.disocclusion_threshold", [](const Settings& s) { return double(s.denoise.disocclusionThreshold); }},
      {"denoise.normal_tolerance_degrees", [](const Settings& s) { return double(s.denoise.normalToleranceDegrees); }},
      {"denoise.depth_tolerance", [](const Settings& s) { return double(s.denoise.depthTolerance); }},
      {"denoise.clamp_sigma", [](const Settings& s) { return double(s.denoise.clampSigma); }},
      {"denoise.anti_firefly", [](const Settings& s) { return double(s.denoise.antiFirefly); }},
      {"denoise.checkerboard", [](const Settings& s) { return double(s.denoise.checkerboard); }},
      {"cache.enabled", [](const Settings& s) { return double(s.cache.enabled); }},
      {"cache.memory_mib", [](const Settings& s) { return double(s.cache.memoryMib); }},
      {"cache.cell_size", [](const Settings& s) { return double(s.cache.cellSize); }},
      {"cache.update_rays", [](const Settings& s) { return double(s.cache.updateRays); }},
      {"cache.update_bounces", [](const Settings& s) { return double(s.cache.updateBounces); }},
      {"cache.history_samples", [](const Settings& s) { return double(s.cache.historySamples); }},
      {"cache.max_age", [](const Settings& s) { return double(s.cache.maxAge); }},
      {"cache.inject_stride", [](const Settings& s) { return double(s.cache.injectStride); }},
      {"cache.direct_light", [](const Settings& s) { return double(s.cache.directLight); }},
      {"input.motion_units", [](const Settings& s) { return double(s.input.motionUnits); }},
      {"input.motion_scale_x", [](const Settings& s) { return double(s.input.motionScaleX); }},
      {"input.motion_scale_y", [](const Settings& s) { return double(s.input.motionScaleY); }},
      {"restir", [](const Settings& s) { return double(s.restir); }},
      {"seed", [](const Settings& s) { return double(s.seed); }},
      {"world_ray_budget", [](const Settings& s) { return double(s.worldRayBudget); }},
  };
}

std::vector<std::string> allKeys() {
  std::vector<std::string> keys;
  for (const SettingInfo& info : settingKeys()) keys.push_back(info.key);
  return keys;
}

// An accepted value other than the default: the other bool or enum value, or
// the first of a few numbers that the key's range admits.
std::string otherValidValue(const SettingInfo& info) {
  if (info.type == "bool") return info.defaultValue == "on" ? "off" : "on";
  if (info.type.starts_with("enum")) {  // "enum: a|b|...": the first value that is not the default
    std::string values = info.type.substr(info.type.find(' ') + 1) + "|";
    for (std::size_t bar = values.find('|'); bar != std::string::npos; bar = values.find('|')) {
      const std::string value = values.substr(0, bar);
      if (value != info.defaultValue) return value;
      values.erase(0, bar + 1);
    }
  }
  for (const char* candidate : {"1", "2", "0.5", "0"}) {
    if (candidate == info.defaultValue) continue;
    try {
      Settings settings;
      applySetting(settings, info.key, candidate);
      return candidate;
    } catch (const std::invalid_argument&) {
    }
  }
  ADD_FAILURE() << "no other valid value for " << info.key;
  return info.defaultValue;
}

// The message of the std::invalid_argument that `call` throws; fails the test if it throws none.
template <typename Call>
std::string invalidArgumentMessage(Call call) {
  try {
    call();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  ADD_FAILURE() << "no std::invalid_argument thrown";
  return {};
}

template <typename Call>
std::string runtimeErrorMessage(Call call) {
  try {
    call();
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  ADD_FAILURE() << "no std::runtime_error thrown";
  return {};
}

void expectRefused(const std::string& key, const std::string& value, const std::string& acceptedHint) {
  Settings settings;
  const std::string before = settingValue(settings, key);
  const std::string message = invalidArgumentMessage([&] { applySetting(settings, key, value); });
  EXPECT_NE(message.find("gi." + key), std::string::npos) << message;
  EXPECT_NE(message.find("\"" + value + "\""), std::string::npos) << message;
  EXPECT_NE(message.find(acceptedHint), std::string::npos) << message;
  EXPECT_EQ(settingValue(settings, key), before) << "a refused value must leave the field alone";
}

class TempFile {
 public:
  explicit TempFile(const std::string& contents) {
    path_ = std::filesystem::temp_directory_path() /
            ("bounce_gi_settings_" + std::to_string(counter_++) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".json");
    std::ofstream(path_) << contents;
  }
  ~TempFile() { std::filesystem::remove(path_); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  std::filesystem::path path_;
};

TEST(GiSettings, DefaultsAreValid) { EXPECT_NO_THROW(validate(Settings{})); }

TEST(GiSettings, KeysAreTheSnakeCaseFieldNamesInStructOrder) {
  std::vector<std::string> expected;
  for (const ExpectedField& field : expectedFields()) expected.push_back(field.key);
  EXPECT_EQ(allKeys(), expected);
}

TEST(GiSettings, KeysAreUniqueAndDescribed) {
  const std::vector<std::string> keys = allKeys();
  EXPECT_EQ(std::set<std::string>(keys.begin(), keys.end()).size(), keys.size());
  for (const SettingInfo& info : settingKeys()) {
    EXPECT_FALSE(info.description.empty()) << info.key;
    EXPECT_FALSE(info.type.empty()) << info.key;
    EXPECT_EQ(info.defaultValue, settingValue(Settings{}, info.key)) << info.key;
  }
}

TEST(GiSettings, DefaultValuesAreTheStructDefaults) {
  std::map<std::string, std::string> defaults;
  for (const SettingInfo& info : settingKeys()) defaults[info.key] = info.defaultValue;
  EXPECT_EQ(defaults["diffuse.enabled"], "on");
  EXPECT_EQ(defaults["diffuse.screen_candidates"], "6");
  EXPECT_EQ(defaults["diffuse.target"], "luminance");
  EXPECT_EQ(defaults["diffuse.temporal_depth_tolerance"], "0.05");
  EXPECT_EQ(defaults["diffuse.spatial_radius"], "16");
  EXPECT_EQ(defaults["restir"], "on");
  EXPECT_EQ(defaults["seed"], "0");
}

TEST(GiSettings, TypesNameTheRange) {
  std::map<std::string, std::string> types;
  for (const SettingInfo& info : settingKeys()) types[info.key] = info.type;
  EXPECT_EQ(types["diffuse.enabled"], "bool");
  EXPECT_EQ(types["diffuse.screen_candidates"], "uint [0, 64]");
  EXPECT_EQ(types["diffuse.temporal_normal_tolerance_degrees"], "float (0, 180)");
  EXPECT_EQ(types["diffuse.visibility_thickness"], "float (0, 1]");
  EXPECT_EQ(types["diffuse.target"], "enum: luminance|color-length");
  EXPECT_EQ(types["seed"], "uint [0, 4294967295]");
}

TEST(GiSettings, EveryKeyRoundTripsThroughItsText) {
  for (const SettingInfo& info : settingKeys()) {
    for (const std::string& text : {info.defaultValue, otherValidValue(info)}) {
      Settings settings;
      applySetting(settings, info.key, text);
      const std::string printed = settingValue(settings, info.key);
      Settings reparsed;
      applySetting(reparsed, info.key, printed);
      EXPECT_EQ(settingValue(reparsed, info.key), printed) << info.key;
    }
  }
}

TEST(GiSettings, FloatsPrintWithEnoughDigitsToRoundTrip) {
  Settings settings;
  settings.diffuse.spatialPlaneTolerance = std::nextafter(0.1f, 1.0f);
  Settings reparsed;
  applySetting(reparsed, "diffuse.spatial_plane_tolerance", settingValue(settings, "diffuse.spatial_plane_tolerance"));
  EXPECT_EQ(reparsed.diffuse.spatialPlaneTolerance, settings.diffuse.spatialPlaneTolerance);
}

TEST(GiSettings, EachKeySetsItsOwnFieldAndNoOther) {
  const std::vector<ExpectedField> fields = expectedFields();
  const Settings defaults;
  for (const SettingInfo& info : settingKeys()) {
    Settings settings;
    applySetting(settings, info.key, otherValidValue(info));
    for (const ExpectedField& field : fields) {
      if (field.key == info.key) {
        EXPECT_NE(field.read(settings), field.read(defaults)) << info.key << " did not change its field";
      } else {
        EXPECT_EQ(field.read(settings), field.read(defaults)) << info.key << " changed the field of " << field.key;
      }
    }
    for (const std::string& other : allKeys()) {
      if (other == info.key) continue;
      EXPECT_EQ(settingValue(settings, other), settingValue(defaults, other))
          << "setting " << info.key << " changed settingValue of " << other;
    }
  }
}

TEST(GiSettings, BoolsAcceptTheUsualWords) {
  for (const char* yes : {"on", "true", "yes", "1", "ON", "True"}) {
    Settings settings;
    settings.restir = false;
    applySetting(settings, "restir", yes);
    EXPECT_TRUE(settings.restir) << yes;
  }
  for (const char* no : {"off", "false", "no", "0", "OFF"}) {
    Settings settings;
    applySetting(settings, "restir", no);
    EXPECT_FALSE(settings.restir) << no;
  }
}

TEST(GiSettings, ParsesEachType) {
  Settings settings;
  applySetting(settings, "diffuse.spatial_radius", "24.5");
  EXPECT_EQ(settings.diffuse.spatialRadius, 24.5f);
  applySetting(settings, "diffuse.spatial2_samples", "9");
  EXPECT_EQ(settings.diffuse.spatial2Samples, 9u);
  applySetting(settings, "diffuse.target", "color-length");
  EXPECT_EQ(settings.diffuse.target, TargetFunction::ColorLength);
  applySetting(settings, "seed", "4294967295");
  EXPECT_EQ(settings.seed, 4294967295u);
  applySetting(settings, "diffuse.jacobian", "off");
  EXPECT_FALSE(settings.diffuse.jacobian);
}

TEST(GiSettings, AcceptsTheCommandLinePrefix) {
  Settings settings;
  applySetting(settings, "gi.diffuse.spatial_radius", "24");
  EXPECT_EQ(settings.diffuse.spatialRadius, 24.0f);
  EXPECT_EQ(settingValue(settings, "gi.diffuse.spatial_radius"), "24");
}

TEST(GiSettings, RefusesMalformedValuesOfEachType) {
  for (const char* value : {"", "maybe", "2", "onn", " on"}) expectRefused("restir", value, "on, off");
  for (const char* value : {"", "-1", "2.5", "abc", "4294967296", "99999999999999999999", "+3", "0x10", "3x"}) {
    expectRefused("seed", value, "an integer in [0, 4294967295]");
  }
  for (const char* value : {"", "nan", "NaN", "inf", "-inf", "infinity", "abc", "3x", "1e39", "1,5", " 3"}) {
    expectRefused("diffuse.spatial_radius", value, "a number in [0, 256]");
  }
  for (const char* value : {"", "color_length", "rgb", "0"}) {
    expectRefused("diffuse.target", value, "luminance or color-length");
  }
}

TEST(GiSettings, RefusesOutOfRangeValues) {
  expectRefused("diffuse.screen_candidates", "65", "[0, 64]");
  expectRefused("diffuse.bright_pixels", "0", "[1, 4096]");
  expectRefused("diffuse.bright_pixels", "4097", "[1, 4096]");
  expectRefused("diffuse.environment_mip", "16.5", "[0, 16]");
  expectRefused("diffuse.temporal_max_m", "0", "[1, 1000]");
  expectRefused("diffuse.temporal_depth_tolerance", "0", "(0, 1]");
  expectRefused("diffuse.temporal_normal_tolerance_degrees", "180", "(0, 180)");
  expectRefused("diffuse.spatial_normal_tolerance_degrees", "0", "(0, 180)");
  expectRefused("diffuse.spatial_radius", "-1", "[0, 256]");
  expectRefused("diffuse.spatial2_radius", "256.5", "[0, 256]");
  expectRefused("diffuse.spatial_samples", "65", "[0, 64]");
  expectRefused("diffuse.resolve_reservoirs", "5", "[1, 4]");
  expectRefused("diffuse.resolve_reservoirs", "0", "[1, 4]");
  expectRefused("diffuse.visibility_steps", "257", "[0, 256]");
  expectRefused("diffuse.visibility_thickness", "1.01", "(0, 1]");
  expectRefused("diffuse.variance_clipping_gamma", "0", "(0, 100]");
  expectRefused("diffuse.temporal_filter_frames", "1025", "[1, 1024]");
}

TEST(GiSettings, AcceptsRangeEnds) {
  Settings settings;
  applySetting(settings, "diffuse.resolve_reservoirs", "1");
  applySetting(settings, "diffuse.resolve_reservoirs", "4");
  applySetting(settings, "diffuse.visibility_thickness", "1");
  applySetting(settings, "diffuse.temporal_normal_tolerance_degrees", "179.9");
  EXPECT_NO_THROW(validate(settings));
}

TEST(GiSettings, UnknownKeysSuggestTheClosest) {
  Settings settings;
  std::string message = invalidArgumentMessage([&] { applySetting(settings, "diffuse.spatial_radios", "3"); });
  EXPECT_NE(message.find("gi.diffuse.spatial_radios"), std::string::npos) << message;
  EXPECT_NE(message.find("did you mean gi.diffuse.spatial_radius"), std::string::npos) << message;

  message = invalidArgumentMessage([&] { applySetting(settings, "spatial_radius", "3"); });
  EXPECT_NE(message.find("gi.diffuse.spatial_radius"), std::string::npos) << message;

  message = invalidArgumentMessage([&] { applySetting(settings, "completely.unrelated", "3"); });
  EXPECT_NE(message.find("gi.completely.unrelated"), std::string::npos) << message;
  EXPECT_NE(message.find("bounce render --help"), std::string::npos) << message;

  message = invalidArgumentMessage([&] { (void)settingValue(settings, "diffuse"); });
  EXPECT_NE(message.find("unknown setting gi.diffuse"), std::string::npos) << message;
}

TEST(GiSettings, ValidateCatchesBadFieldsSetInCode) {
  Settings settings;
  settings.diffuse.resolveReservoirs = 0;
  std::string message = invalidArgumentMessage([&] { validate(settings); });
  EXPECT_NE(message.find("gi.diffuse.resolve_reservoirs"), std::string::npos) << message;
  EXPECT_NE(message.find("[1, 4]"), std::string::npos) << message;

  settings = {};
  settings.diffuse.visibilityThickness = std::numeric_limits<float>::quiet_NaN();
  message = invalidArgumentMessage([&] { validate(settings); });
  EXPECT_NE(message.find("gi.diffuse.visibility_thickness"), std::string::npos) << message;

  settings = {};
  settings.diffuse.target = static_cast<TargetFunction>(7);
  message = invalidArgumentMessage([&] { validate(settings); });
  EXPECT_NE(message.find("gi.diffuse.target"), std::string::npos) << message;
  EXPECT_NE(message.find("\"7\""), std::string::npos) << message;
}

TEST(GiSettings, ValidateRefusesNoCandidatesOnlyWhileDiffuseIsOn) {
  Settings settings;
  settings.diffuse.screenCandidates = 0;
  settings.diffuse.brightCandidates = 0;
  settings.diffuse.environmentCandidates = 0;
  const std::string message = invalidArgumentMessage([&] { validate(settings); });
  EXPECT_NE(message.find("gi.diffuse.screen_candidates"), std::string::npos) << message;
  EXPECT_NE(message.find("gi.diffuse.environment_candidates"), std::string::npos) << message;

  settings.diffuse.enabled = false;
  EXPECT_NO_THROW(validate(settings));

  settings.diffuse.enabled = true;
  settings.diffuse.environmentCandidates = 1;
  EXPECT_NO_THROW(validate(settings));
}

// With a bridge that traces, ray candidates replace the environment's: the
// library refused screen, bright and ray candidates all 0 only once it was
// built, after the command had loaded its scene.
TEST(GiSettings, ValidateWithATracingBridgeRefusesNoScreenBrightOrRayCandidate) {
  Settings settings;
  settings.diffuse.screenCandidates = 0;
  settings.diffuse.brightCandidates = 0;
  settings.diffuse.rayCandidates = 0;
  EXPECT_NO_THROW(validate(settings, false)) << "without a bridge the environment candidates remain";
  std::string message = invalidArgumentMessage([&] { validate(settings, true); });
  for (const char* key : {"gi.diffuse.screen_candidates", "gi.diffuse.bright_candidates",
                          "gi.diffuse.ray_candidates is 0", "gi.diffuse.environment_candidates"})
    EXPECT_NE(message.find(key), std::string::npos) << key << ": " << message;

  // Ray candidates asked for, but the budget leaves none after what the settings fix.
  settings.diffuse.rayCandidates = 2;
  settings.worldRayBudget = 0.5f;
  ASSERT_EQ(planWorldRays(settings).diffuseCandidates, 0u);
  message = invalidArgumentMessage([&] { validate(settings, true); });
  EXPECT_NE(message.find("gi.world_ray_budget 0.5 leaves no ray for gi.diffuse.ray_candidates"), std::string::npos)
      << message;

  settings.worldRayBudget = Settings{}.worldRayBudget;
  EXPECT_NO_THROW(validate(settings, true));
  settings.diffuse.rayCandidates = 0;
  settings.diffuse.brightCandidates = 1;
  EXPECT_NO_THROW(validate(settings, true));
  settings.diffuse.brightCandidates = 0;
  settings.diffuse.enabled = false;
  EXPECT_NO_THROW(validate(settings, true));
}

TEST(GiSettings, JsonFileTakesNestedDottedAndWrappedForms) {
  const TempFile file(R"({
    "restir": false,
    "seed": 7,
    "diffuse": {"spatial_radius": 24, "jacobian": "off", "target": "color-length", "visibility_thickness": 0.25},
    "diffuse.spatial2_samples": 3,
    "gi": {"diffuse": {"temporal_max_m": "30"}},
    "gi.diffuse.enabled": 1
  })");
  Settings settings;
  applySettingsFile(settings, file.path());
  EXPECT_FALSE(settings.restir);
  EXPECT_EQ(settings.seed, 7u);
  EXPECT_EQ(settings.diffuse.spatialRadius, 24.0f);
  EXPECT_FALSE(settings.diffuse.jacobian);
  EXPECT_EQ(settings.diffuse.target, TargetFunction::ColorLength);
  EXPECT_EQ(settings.diffuse.visibilityThickness, 0.25f);
  EXPECT_EQ(settings.diffuse.spatial2Samples, 3u);
  EXPECT_EQ(settings.diffuse.temporalMaxM, 30u);
  EXPECT_TRUE(settings.diffuse.enabled);
  EXPECT_EQ(settings.diffuse.screenCandidates, Settings{}.diffuse.screenCandidates) << "keys not in the file stay";
}

TEST(GiSettings, JsonFloatsForIntegersAreTakenWhenWhole) {
  const TempFile whole(R"({"diffuse": {"spatial_samples": 8.0}})");
  Settings settings;
  applySettingsFile(settings, whole.path());
  EXPECT_EQ(settings.diffuse.spatialSamples, 8u);

  const TempFile fraction(R"({"diffuse": {"spatial_samples": 8.5}})");
  const std::string message = runtimeErrorMessage([&] { applySettingsFile(settings, fraction.path()); });
  EXPECT_NE(message.find("gi.diffuse.spatial_samples"), std::string::npos) << message;
}

TEST(GiSettings, JsonErrorsNameTheFile) {
  struct Case {
    std::string contents;
    std::string expectedInMessage;
  };
  const std::vector<Case> cases = {
      {R"({"diffuse": {"spatial_radius": 24,}})", "line 1"},
      {"{\n  \"restir\": false\n  \"seed\": 3\n}", "line 3"},
      {R"([1, 2])", "array"},
      {R"({"diffuse": {"spatial_radios": 24}})", "did you mean gi.diffuse.spatial_radius"},
      {R"({"diffuse": {"spatial_radius": -4}})", "[0, 256]"},
      {R"({"diffuse": {"spatial_radius": [24]}})", "gi.diffuse.spatial_radius: got a JSON array"},
      {R"({"seed": null})", "gi.seed: got a JSON null"},
      {R"({"restir": "sometimes"})", "\"sometimes\""},
      {R"({"diffuse": {"seed": 1}})", "did you mean gi.seed"},
      {R"({"diffuse": {"spatial_radius": 8}, "diffuse.spatial_radius": 9})", "more than once"},
      // JSON itself keeps the last of a repeated key silently.
      {R"({"diffuse": {"spatial_radius": 8, "spatial_radius": 9}})",
       "gi.diffuse.spatial_radius is given more than once"},
      {R"({"gi": {"seed": 1, "seed": 1}})", "gi.seed is given more than once"},
      // 30,000 levels overflowed the stack of the recursive flattening.
      {std::string(30000, '[') + std::string(30000, ']'), "nested deeper than 64 levels"},
      {[] {
         std::string text;
         for (int i = 0; i < 30000; ++i) text += "{\"a\":";
         return text + "1" + std::string(30000, '}');
       }(),
       "nested deeper than 64 levels"},
  };
  for (const Case& testCase : cases) {
    const TempFile file(testCase.contents);
    Settings settings;
    const std::string message = runtimeErrorMessage([&] { applySettingsFile(settings, file.path()); });
    EXPECT_TRUE(message.starts_with(file.path().string() + ": ")) << message;
    EXPECT_NE(message.find(testCase.expectedInMessage), std::string::npos) << message;
    for (const SettingInfo& info : settingKeys()) {
      EXPECT_EQ(settingValue(settings, info.key), info.defaultValue) << "a refused file changed " << info.key;
    }
  }

  const std::filesystem::path missing = std::filesystem::temp_directory_path() / "bounce_no_such_settings.json";
  Settings settings;
  const std::string message = runtimeErrorMessage([&] { applySettingsFile(settings, missing); });
  EXPECT_TRUE(message.starts_with(missing.string() + ": ")) << message;
  EXPECT_NE(message.find("no such file"), std::string::npos) << message;
}

// The ray budget's plan: what the settings fix is paid first, then one ray
// candidate, then sky tests in both spatial passes, then the other
// candidates, each cut to fit.
TEST(GiSettings, WorldRayPlanSpendsTheBudgetInOrder) {
  Settings settings;
  WorldRayPlan plan = planWorldRays(settings);
  EXPECT_EQ(plan.sampleVisibility, 1u);
  EXPECT_EQ(plan.specular, 1u);
  EXPECT_EQ(plan.spatialPasses, 2u);
  EXPECT_EQ(plan.skyReuseRays, 5u) << "every neighbour of a pass, no more";
  EXPECT_EQ(plan.diffuseCandidates, 2u);
  EXPECT_EQ(plan.perReservoir(), 14u) << "the default budget pays for every default ray";
  EXPECT_LE(double(plan.perReservoir()), 4.0 * double(settings.worldRayBudget));

  settings.worldRayBudget = 1.25f;  // five a reservoir: two fixed, a candidate, one sky test a pass
  plan = planWorldRays(settings);
  EXPECT_EQ(plan.diffuseCandidates, 1u);
  EXPECT_EQ(plan.skyReuseRays, 1u);
  settings.worldRayBudget = 1.0f;  // four: a test in both passes does not fit; the second candidate does
  plan = planWorldRays(settings);
  EXPECT_EQ(plan.skyReuseRays, 0u);
  EXPECT_EQ(plan.diffuseCandidates, 2u);
  settings.worldRayBudget = 0.75f;  // three: one candidate
  plan = planWorldRays(settings);
  EXPECT_EQ(plan.skyReuseRays, 0u);
  EXPECT_EQ(plan.diffuseCandidates, 1u);

  // What the settings fix is never cut: a budget below it is refused, naming both.
  settings.worldRayBudget = 0.25f;
  std::string message = invalidArgumentMessage([&] { planWorldRays(settings); });
  EXPECT_NE(message.find("gi.world_ray_budget"), std::string::npos) << message;
  EXPECT_NE(message.find("0.5 per pixel"), std::string::npos) << message;
  EXPECT_THROW(validate(settings), std::invalid_argument);
  settings.worldRayBudget = 3.5f;
  settings.diffuse.reuseVisibility = true;  // 1 + 2 x (5 + 5) rays of its own
  message = invalidArgumentMessage([&] { planWorldRays(settings); });
  EXPECT_NE(message.find("gi.diffuse.reuse_visibility on"), std::string::npos) << message;
  settings.worldRayBudget = 64.0f;
  plan = planWorldRays(settings);
  EXPECT_EQ(plan.reuseVisibility, 21u);
  EXPECT_EQ(plan.skyReuseRays, 0u);  // every neighbour is tested already
  EXPECT_EQ(plan.diffuseCandidates, 2u);

  // Without diffuse or specular, none of theirs.
  settings = Settings{};
  settings.diffuse.enabled = false;
  settings.specular.enabled = false;
  plan = planWorldRays(settings);
  EXPECT_EQ(plan.perReservoir(), 0u);
}

TEST(GiSettings, DocsListEveryKeyWithItsTypeAndDefault) {
  std::ifstream docs(std::string(BOUNCE_SOURCE_DIR) + "/docs/gi-settings.md");
  ASSERT_TRUE(docs) << "docs/gi-settings.md is missing";
  std::map<std::string, std::string> rows;
  for (std::string line; std::getline(docs, line);) {
    if (!line.starts_with("| `--gi.")) continue;
    const std::size_t keyEnd = line.find('`', 3);
    // Markdown escapes the | of "enum: a|b" inside a table cell.
    for (std::size_t bar = line.find("\\|"); bar != std::string::npos; bar = line.find("\\|", bar)) line.erase(bar, 1);
    rows[line.substr(std::string("| `--gi.").size(), keyEnd - std::string("| `--gi.").size())] = line;
  }
  for (const SettingInfo& info : settingKeys()) {
    ASSERT_TRUE(rows.contains(info.key)) << "docs/gi-settings.md has no row for --gi." << info.key;
    EXPECT_NE(rows[info.key].find("` | " + info.type + " | " + info.defaultValue + " | "), std::string::npos)
        << "docs/gi-settings.md has another type or default for " << info.key << ":\n"
        << rows[info.key];
    rows.erase(info.key);
  }
  for (const auto& [key, row] : rows) ADD_FAILURE() << "docs/gi-settings.md lists --gi." << key << ", not a setting";
}

}  // namespace
}  // namespace bounce::gi

// The library's promise to engines: it never sees a scene. Its sources,
// public headers and shaders may include gpu/, io/, shared math and their
// own files, never the renderer, the scene importer or the app.
// Each layer includes only what is below it (docs/architecture.md): gpu/
// nothing of io/ (image files), gi/ and the public headers nothing of the
// renderer, scenes, files or tools, and the public headers nothing of src/.
TEST(GiLayering, EachLayerIncludesOnlyWhatIsBelowIt) {
  namespace fs = std::filesystem;
  const fs::path root(BOUNCE_SOURCE_DIR);
  const std::vector<const char*> aboveGi = {"\"render/", "\"scene/", "\"app/", "\"metrics/", "\"io/", "\"gpuio/"};
  struct Rule {
    const char* dir;
    std::vector<const char*> forbidden;
  };
  std::vector<const char*> publicForbidden = aboveGi;
  publicForbidden.insert(publicForbidden.end(), {"\"gpu/", "\"gi/", "\"shared/", "<glm/"});
  const Rule rules[] = {{"src/gpu", {"\"io/", "\"gpuio/", "\"gi/", "\"render/", "\"scene/", "\"app/"}},
                        {"src/gi", aboveGi},
                        {"shaders/gi", aboveGi},
                        {"include/bounce", publicForbidden}};
  int scanned = 0;
  for (const Rule& rule : rules) {
    ASSERT_TRUE(fs::is_directory(root / rule.dir)) << rule.dir;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root / rule.dir)) {
      if (!entry.is_regular_file()) continue;
      ++scanned;
      std::ifstream file(entry.path());
      std::string line;
      for (int number = 1; std::getline(file, line); ++number) {
        if (line.rfind("#include", 0) != 0) continue;
        for (const char* forbidden : rule.forbidden)
          EXPECT_EQ(line.find(forbidden), std::string::npos)
              << entry.path().string() << ":" << number << " includes what its layer may not: " << line;
      }
    }
  }
  EXPECT_GT(scanned, 40);
}

// The orchestrator talks to its units through their interface: no cast to
// a concrete unit anywhere in the library (a new branch must not need one).
TEST(GiLayering, NoCastToAConcreteUnitInTheLibrary) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(BOUNCE_SOURCE_DIR) / "src/gi";
  std::string found;
  int scanned = 0;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    ++scanned;
    std::ifstream file(entry.path());
    std::string line;
    for (int number = 1; std::getline(file, line); ++number)
      for (const char* unit : {"DiffuseBranch", "SpecularBranch", "RadianceCache", "Denoiser", "Branch"})
        for (const char* cast : {"static_cast<", "dynamic_cast<", "reinterpret_cast<"})
          if (line.find(std::string(cast) + unit + "&") != std::string::npos ||
              line.find(std::string(cast) + unit + "*") != std::string::npos ||
              line.find(std::string(cast) + "const " + unit) != std::string::npos)
            found += entry.path().string() + ":" + std::to_string(number) + ": " + line + "\n";
  }
  EXPECT_GT(scanned, 40);
  EXPECT_TRUE(found.empty()) << "casts to a concrete unit:\n" << found;
}

namespace bounce::gi {

namespace {

// The table rows of docs/passes.md whose first cell names a library pass or
// image ("| `gi.", as both tables write them): by the name in the first
// cell's backticks, the whole line.
std::multimap<std::string, std::string> libraryRows() {
  std::ifstream docs(std::string(BOUNCE_SOURCE_DIR) + "/docs/passes.md");
  EXPECT_TRUE(docs) << "docs/passes.md is missing";
  std::multimap<std::string, std::string> rows;
  for (std::string line; std::getline(docs, line);)
    if (line.rfind("| `gi.", 0) == 0) rows.emplace(line.substr(3, line.find('`', 3) - 3), line);
  return rows;
}

// Whether a name of docs/passes.md stands for a pass: the same, or a
// family of passes written with an upper-case placeholder for one
// dot-separated part (gi.denoise.SIGNAL.blur, gi.diffuse.reservoir_view.STAGE).
bool namesPass(const std::string& documented, const std::string& pass) {
  const auto parts = [](const std::string& name) {
    std::vector<std::string> split(1);
    for (char c : name) {
      if (c == '.')
        split.emplace_back();
      else
        split.back().push_back(c);
    }
    return split;
  };
  const std::vector<std::string> a = parts(documented), b = parts(pass);
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const bool placeholder =
        !a[i].empty() && std::all_of(a[i].begin(), a[i].end(), [](char c) { return c >= 'A' && c <= 'Z'; });
    if (!placeholder && a[i] != b[i]) return false;
  }
  return true;
}

// The second cell of a passes-table row: "`gi/diffuse/gather.comp`", perhaps with words after.
std::string secondCell(const std::string& row) {
  const std::size_t first = row.find(" | ");
  const std::size_t second = row.find(" | ", first + 3);
  return first == std::string::npos || second == std::string::npos ? "" : row.substr(first + 3, second - first - 3);
}

}  // namespace

// docs/passes.md lists every pass every unit declares (gi/unit_catalog.h:
// the environment, the frame, the pyramid, screen tiles, the light change,
// the cache, both branches, the engine's signals, the denoiser) with the
// shader it runs, and no pass that does not exist.
// The catalog the docs are checked against holds every unit a context is
// made of, in recording order: a unit registered without a catalog entry
// would escape the checks below.
TEST(GiDocs, TheCatalogHoldsEveryRegisteredUnitInOrder) {
  std::vector<std::string> catalog;
  for (const DeclaredUnit& unit : declaredUnits())
    if (unit.name != "environment") catalog.push_back(unit.name);
  std::vector<std::string> registered;
  for (const UnitRegistration& unit : registeredUnits()) registered.push_back(unit.name);
  EXPECT_EQ(catalog, registered);
}

TEST(GiDocs, PassesMdListsEveryPassOfEveryUnitWithItsShader) {
  const std::multimap<std::string, std::string> rows = libraryRows();
  // Image rows name images, not passes: only rows with a shader cell are passes.
  std::map<std::string, std::string> passRows;
  for (const auto& [name, row] : rows)
    if (secondCell(row).find(".comp`") != std::string::npos) passRows.emplace(name, row);
  std::set<std::string> documentedAndDeclared;
  std::string problems;
  std::size_t declared = 0;
  for (const DeclaredUnit& unit : declaredUnits())
    for (const gpu::PassDesc& pass : unit.passes) {
      ++declared;
      const auto row = std::find_if(passRows.begin(), passRows.end(),
                                    [&](const auto& entry) { return namesPass(entry.first, pass.name); });
      if (row == passRows.end()) {
        problems += "no row for pass " + pass.name + " (unit " + unit.name + ")\n";
        continue;
      }
      documentedAndDeclared.insert(row->first);
      const std::string shader = "`" + pass.shader + ".comp`";
      if (secondCell(row->second).rfind(shader, 0) != 0)
        problems += "the row of " + row->first + " names another shader than " + shader + " (pass " + pass.name + ")\n";
    }
  EXPECT_GT(declared, 40u);
  for (const auto& [name, row] : passRows)
    if (!documentedAndDeclared.contains(name)) problems += "a row for " + name + ", which no unit declares\n";
  EXPECT_TRUE(problems.empty()) << "docs/passes.md and the units' pass declarations differ:\n" << problems;
}

// docs/passes.md lists every image of the library as the tables in the code
// declare it (the tables make the images; the docs must not drift from
// them), the cache's debug views included, and no image that is not made.
TEST(GiDocs, PassesMdListsEveryImageOfTheTables) {
  const std::multimap<std::string, std::string> rows = libraryRows();
  std::set<std::string> declared;
  std::string missing;
  for (const DeclaredUnit& unit : declaredUnits())
    for (const ImageSpec& spec : unit.images) {
      declared.insert(std::string(spec.name));
      const std::string row = "| `" + std::string(spec.name) + "` | " + resolutionName(spec.resolution) + " | " +
                              gpu::formatName(spec.format) + " | " + (spec.history ? "yes" : "no") + " | " +
                              (spec.debug ? "debug views only; " : "") + (spec.transient ? "transient; " : "") +
                              std::string(spec.purpose) + " |";
      bool found = false;
      for (auto [at, end] = rows.equal_range(std::string(spec.name)); at != end; ++at) found |= at->second == row;
      if (!found) missing += row + "\n";
    }
  for (const auto& [name, row] : rows)
    if (row.find("| VK_FORMAT_") != std::string::npos && !declared.contains(name))
      missing += "(a row for " + name + ", which no table declares)\n";
  EXPECT_TRUE(missing.empty()) << "docs/passes.md lacks these rows (or has them otherwise):\n" << missing;
}

}  // namespace bounce::gi
