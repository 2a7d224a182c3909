// bounce view's Dear ImGui panels: the GI settings (every key of the one
// settings table, gi::settingKeys(), grouped by branch, its type, range,
// default and description as the tooltip, so the panel cannot drift from
// --gi.KEY), the GI mode, live timings per pass and memory, the material
// editor, and the help overlay. The panels edit a copy of the state; the
// viewer applies what changed after the frame's UI is built.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include "bounce/gi_settings.h"

#include "gpu/timing.h"
#include "scene/scene.h"

namespace bounce::viewer {

enum class GiMode { Off, ScreenOnly, Hybrid };
const char* giModeName(GiMode mode);  // off, screen-only, hybrid

// What the right half of the window shows beside the GI frame.
enum class SplitMode { None, GiOff, Other, Reference };
const char* splitModeName(SplitMode mode);  // none, gi-off, other, reference

// One image's value at the inspected pixel.
struct InspectedValue {
  std::string image;
  glm::vec4 value;
  std::uint32_t channels;
};

struct PanelState {
  GiMode mode = GiMode::Hybrid;
  gi::Settings settings;
  std::string settingsMessage;  // the last refused value or file, shown in red; or what was saved
  char settingsFile[512] = "gi-settings.json";
  std::optional<std::uint32_t> pickedMaterial;
  scene::Material material;                // the picked one, as edited
  std::vector<gpu::LatestTiming> timings;  // the passes of the latest completed frame
  double frameMs = 0.0;                    // GPU time of the latest frame
  std::uint64_t memoryBytes = 0;           // device memory in use
  float exposure = 1.0f;
  float cameraSpeed = 0.0f;
  bool paused = false;
  bool playing = false;  // following the camera path
  bool recording = false;
  bool showHelp = false;
  bool hidden = false;  // no panels: the frame alone (U, or a script's 'panels off')
  // The view: which image fills the window ("final" or a stage's name,
  // false colour as --dump-stages writes it), the split screen, the
  // reference's samples and the GI frame's error against it.
  gi::Settings otherSettings;  // the split's other settings (the defaults unless loaded)
  char otherSettingsFile[512] = "";
  std::vector<std::string> stageNames;
  int stage = 0;
  SplitMode split = SplitMode::None;
  std::uint64_t referenceSpp = 0;
  std::optional<double> relMse, flip;
  // The pixel inspector: every image's value under the cursor.
  bool inspector = false;
  std::optional<glm::uvec2> inspectedPixel;
  std::vector<InspectedValue> inspected;
  char gltfFile[512] = "edited.gltf";
  std::string materialMessage;  // what the last save did
  // The picked material's BRDF plots (viewer/brdf_plot.h): their size, the
  // samples so far, and where the panel kept room for them this frame
  // (window pixels; empty when that room is not on screen).
  glm::ivec2 brdfPlotSize{0};
  std::uint32_t brdfPlotSamples = 0;
  std::optional<glm::ivec2> brdfPlotAt;
  bool openMaterialPanel = false;  // a material was just picked
};

// What the user asked for this frame.
struct PanelActions {
  bool settingsChanged = false;  // state.settings holds the new settings (valid)
  bool modeChanged = false;
  bool materialChanged = false;  // state.material holds the edited values
  bool loadSettings = false;     // from state.settingsFile
  bool saveSettings = false;
  bool screenshot = false;
  bool viewChanged = false;        // stage or split
  bool loadOtherSettings = false;  // the split's other settings from state.otherSettingsFile
  bool measure = false;            // compare the GI frame with the reference now
  bool saveGltf = false;           // the scene with the edited materials, to state.gltfFile
};

// Builds this frame's panels (between ImGui::NewFrame and ImGui::Render).
void drawPanels(PanelState& state, PanelActions& actions);

// The help overlay's lines: key, what it does.
struct KeyHelp {
  const char* key;
  const char* action;
};
const std::vector<KeyHelp>& keyHelp();

// The settings as a JSON object of dotted keys, the form
// gi::applySettingsFile reads back.
std::string settingsJson(const gi::Settings& settings);

}  // namespace bounce::viewer
