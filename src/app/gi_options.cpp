#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/option_checks.h"
#include "render/scene_bridge.h"
#include "util/printable.h"

namespace bounce::app {

void addGiOptions(CLI::App& command, GiOptions& options, bool warmup) {
  command
      .add_option("--gi", options.mode,
                  "Global illumination: the GI library's branches, a comma list of diffuse (indirect diffuse) and "
                  "specular (indirect specular), or off (direct light only)")
      ->check(CLI::Validator(
          [](std::string& value) -> std::string {
            if (value == "off") return "";
            bool any = false;
            for (const std::string& branch : giBranches(value)) {
              if (branch != "diffuse" && branch != "specular")
                return "'" + branch + "' is not a GI branch (diffuse, specular; or off alone)";
              any = true;
            }
            return any ? "" : "no GI branch given (diffuse, specular, or off)";
          },
          "diffuse,specular|off"))
      ->capture_default_str();
  command
      .add_option("--scene-bridge", options.sceneBridge,
                  "How the GI sees beyond the screen: bvh (rays through the renderer's BVH, a radiance cache) or none "
                  "(screen space only, what an engine that hands over a G-buffer alone gets)")
      ->check(CLI::IsMember({"bvh", "none"}))
      ->capture_default_str();
  addGiSettingsOptions(command, options);
  if (warmup)
    command
        .add_option("--gi-warmup", options.warmup,
                    "Frames rendered at the first camera before the first output frame, so that light has "
                    "bounced and histories have filled (GI only)")
        ->check(CLI::Range(0u, 10000u))
        ->capture_default_str();
}

void addGiSettingsOptions(CLI::App& command, GiOptions& options) {
  command
      .add_option("--gi-settings", options.settingsFile,
                  "JSON file of GI settings (docs/gi-settings.md); --gi.KEY flags override it")
      ->check(CLI::ExistingFile);
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

std::vector<std::string> giBranches(const std::string& mode) {
  std::vector<std::string> branches;
  std::size_t start = 0;
  while (start <= mode.size()) {
    const std::size_t comma = std::min(mode.find(',', start), mode.size());
    branches.push_back(mode.substr(start, comma - start));
    start = comma + 1;
  }
  return branches;
}

bool giEnabled(const GiOptions& options) { return options.mode != "off"; }

gi::SceneBridge giSceneBridge(const GiOptions& options) {
  return options.sceneBridge == "bvh" ? render::bvhSceneBridge() : gi::SceneBridge{};
}

gi::ContextDesc giContextDesc(std::uint32_t width, std::uint32_t height, const GiOptions& options) {
  return {.maxWidth = width,
          .maxHeight = height,
          .framesInFlight = render::FrameRenderer::kFramesInFlight,
          .sceneBridge = giSceneBridge(options)};
}

void warnIgnoredGiOptions(const GiOptions& options) {
  if (giEnabled(options)) return;
  std::string ignored;
  if (!options.settingsFile.empty()) ignored = "--gi-settings " + options.settingsFile;
  for (const auto& [key, value] : options.overrides) ignored += (ignored.empty() ? "--gi." : ", --gi.") + key;
  if (!ignored.empty())
    std::fprintf(stderr, "bounce: warning: --gi off: ignoring %s\n", util::printable(ignored).c_str());
}

gi::Settings giSettings(const GiOptions& options, const gi::Settings& base) {
  gi::Settings settings = base;
  if (!options.settingsFile.empty()) gi::applySettingsFile(settings, options.settingsFile);
  // A --gi.KEY value the library refuses is a mistake on the command line.
  for (const auto& [key, value] : options.overrides) {
    try {
      gi::applySetting(settings, key, value);
    } catch (const std::exception& refused) {
      throw UsageError(refused.what());
    }
  }
  // --gi names the branches that run: one it leaves out is off whatever the settings say.
  const std::vector<std::string> branches = giBranches(options.mode);
  const auto listed = [&](const char* name) {
    return std::find(branches.begin(), branches.end(), name) != branches.end();
  };
  if (!listed("diffuse")) settings.diffuse.enabled = false;
  if (!listed("specular")) settings.specular.enabled = false;
  try {
    // With the bridge the command will use: a contradiction the library
    // would only find once built (after the scene loads) is found now.
    gi::validate(settings, !giSceneBridge(options).shaders.empty());
  } catch (const std::invalid_argument& invalid) {
    // The keys at fault may come from the file, the flags or both: name the file.
    if (options.settingsFile.empty()) throw UsageError(invalid.what());
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
