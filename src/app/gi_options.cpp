#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.h"
#include "render/scene_bridge.h"

namespace bounce::app {

void addGiOptions(CLI::App& command, GiOptions& options, bool warmup) {
  command.add_option("--gi", options.mode, "Global illumination: diffuse (the GI library's indirect diffuse) or off")
      ->check(CLI::IsMember({"diffuse", "off"}))
      ->capture_default_str();
  command
      .add_option("--scene-bridge", options.sceneBridge,
                  "How the GI sees beyond the screen: bvh (rays through the renderer's BVH, a radiance cache) or none "
                  "(screen space only, what an engine that hands over a G-buffer alone gets)")
      ->check(CLI::IsMember({"bvh", "none"}))
      ->capture_default_str();
  command
      .add_option("--gi-settings", options.settingsFile,
                  "JSON file of GI settings (docs/gi-settings.md); --gi.KEY flags override it")
      ->check(CLI::ExistingFile);
  if (warmup)
    command
        .add_option("--gi-warmup", options.warmup,
                    "Frames rendered at the first camera before the first output frame, so that light has "
                    "bounced and histories have filled (GI only)")
        ->check(CLI::Range(0u, 10000u))
        ->capture_default_str();
  // One flag per setting, in the table's order; their values are applied
  // after the file, in the order they were given.
  for (const gi::SettingInfo& setting : gi::settingKeys()) {
    const std::string key = setting.key;
    command
        .add_option_function<std::string>(
            "--gi." + key, [&options, key](const std::string& value) { options.overrides.emplace_back(key, value); },
            setting.description + " [" + setting.type + ", default " + setting.defaultValue + "]")
        ->group("GI settings (docs/gi-settings.md)");
  }
}

bool giEnabled(const GiOptions& options) { return options.mode == "diffuse"; }

gi::SceneBridge giSceneBridge(const GiOptions& options) {
  return options.sceneBridge == "bvh" ? render::bvhSceneBridge() : gi::SceneBridge{};
}

void warnIgnoredGiOptions(const GiOptions& options) {
  if (giEnabled(options)) return;
  std::string ignored;
  if (!options.settingsFile.empty()) ignored = "--gi-settings " + options.settingsFile;
  for (const auto& [key, value] : options.overrides) ignored += (ignored.empty() ? "--gi." : ", --gi.") + key;
  if (!ignored.empty()) std::fprintf(stderr, "bounce: warning: --gi off: ignoring %s\n", ignored.c_str());
}

gi::Settings giSettings(const GiOptions& options) {
  gi::Settings settings;
  if (!options.settingsFile.empty()) gi::applySettingsFile(settings, options.settingsFile);
  for (const auto& [key, value] : options.overrides) gi::applySetting(settings, key, value);
  try {
    gi::validate(settings);
  } catch (const std::invalid_argument& invalid) {
    // The keys at fault may come from the file, the flags or both: name the file.
    if (options.settingsFile.empty()) throw;
    throw std::invalid_argument(options.settingsFile + (options.overrides.empty() ? ": " : " with the --gi.* flags: ") +
                                invalid.what());
  }
  return settings;
}

std::string unknownGiSettingFlag(int argc, const char* const* argv) {
  const std::string prefix = "--gi.";
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument.rfind(prefix, 0) != 0) continue;
    const std::string key = argument.substr(prefix.size(), argument.find('=') - prefix.size());
    const std::vector<gi::SettingInfo>& keys = gi::settingKeys();
    if (std::any_of(keys.begin(), keys.end(), [&](const gi::SettingInfo& s) { return s.key == key; })) continue;
    try {
      gi::Settings scratch;
      gi::applySetting(scratch, key, "0");
    } catch (const std::exception& e) {
      return e.what();
    }
  }
  return "";
}

}  // namespace bounce::app
