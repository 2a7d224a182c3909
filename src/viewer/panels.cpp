#include "viewer/panels.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include <imgui.h>

namespace bounce::viewer {
namespace {

// The branch a key belongs to: the part before its first dot ("general"
// for keys without one, as "restir" and "seed").
std::string groupOf(const std::string& key) {
  const std::size_t dot = key.find('.');
  return dot == std::string::npos ? "general" : key.substr(0, dot);
}

// "[lo, hi]" or "(lo, hi]" of a numeric type, as two numbers.
bool rangeOf(const std::string& type, double& low, double& high) {
  const std::size_t open = type.find_first_of("[(");
  const std::size_t comma = type.find(',', open);
  if (open == std::string::npos || comma == std::string::npos) return false;
  char* end = nullptr;
  low = std::strtod(type.c_str() + open + 1, &end);
  high = std::strtod(type.c_str() + comma + 1, &end);
  return true;
}

std::vector<std::string> enumChoices(const std::string& type) {
  std::vector<std::string> choices;
  std::string rest = type.substr(type.find(':') + 1);
  std::size_t start = 0;
  while (start <= rest.size()) {
    std::size_t bar = rest.find('|', start);
    if (bar == std::string::npos) bar = rest.size();
    std::string choice = rest.substr(start, bar - start);
    choice.erase(0, choice.find_first_not_of(' '));
    choice.erase(choice.find_last_not_of(' ') + 1);
    if (!choice.empty()) choices.push_back(choice);
    start = bar + 1;
  }
  return choices;
}

void tooltip(const gi::SettingInfo& info) {
  if (!ImGui::IsItemHovered()) return;
  ImGui::BeginTooltip();
  ImGui::PushTextWrapPos(ImGui::GetFontSize() * 30.0f);
  ImGui::TextUnformatted(("gi." + info.key).c_str());
  ImGui::TextUnformatted(info.description.c_str());
  ImGui::TextDisabled("%s, default %s", info.type.c_str(), info.defaultValue.c_str());
  ImGui::PopTextWrapPos();
  ImGui::EndTooltip();
}

// One setting's widget; returns the new value as text when it changed.
std::optional<std::string> settingWidget(const gi::SettingInfo& info, const std::string& value) {
  const std::string label =
      info.key.substr(info.key.find('.') == std::string::npos ? 0 : info.key.find('.') + 1) + "##" + info.key;
  std::optional<std::string> changed;
  if (info.type == "bool") {
    bool on = value == "on";
    if (ImGui::Checkbox(label.c_str(), &on)) changed = on ? "on" : "off";
  } else if (info.type.rfind("enum", 0) == 0) {
    const std::vector<std::string> choices = enumChoices(info.type);
    if (ImGui::BeginCombo(label.c_str(), value.c_str())) {
      for (const std::string& choice : choices)
        if (ImGui::Selectable(choice.c_str(), choice == value)) changed = choice;
      ImGui::EndCombo();
    }
  } else if (info.type.rfind("uint", 0) == 0) {
    double low = 0.0, high = 0.0;
    int v = std::atoi(value.c_str());
    if (rangeOf(info.type, low, high) && high - low <= 256.0) {
      if (ImGui::SliderInt(label.c_str(), &v, int(low), int(high))) changed = std::to_string(v);
    } else if (ImGui::InputInt(label.c_str(), &v, 1, 10, ImGuiInputTextFlags_EnterReturnsTrue)) {
      changed = std::to_string(std::max(v, 0));
    }
  } else {
    double low = 0.0, high = 0.0;
    float v = float(std::atof(value.c_str()));
    const bool ranged = rangeOf(info.type, low, high) && std::isfinite(high) && high - low <= 1000.0;
    if (ranged ? ImGui::SliderFloat(label.c_str(), &v, float(low), float(high), "%.4g")
               : ImGui::InputFloat(label.c_str(), &v, 0.0f, 0.0f, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue)) {
      char text[32];
      std::snprintf(text, sizeof text, "%.9g", double(v));
      changed = text;
    }
  }
  tooltip(info);
  return changed;
}

void settingsPanel(PanelState& state, PanelActions& actions) {
  int mode = int(state.mode);
  ImGui::TextUnformatted("GI");
  ImGui::SameLine();
  for (GiMode m : {GiMode::Off, GiMode::ScreenOnly, GiMode::Hybrid}) {
    if (ImGui::RadioButton(giModeName(m), &mode, int(m))) actions.modeChanged = true;
    ImGui::SameLine();
  }
  ImGui::NewLine();
  state.mode = GiMode(mode);
  ImGui::InputText("file", state.settingsFile, sizeof state.settingsFile);
  if (ImGui::Button("load")) actions.loadSettings = true;
  ImGui::SameLine();
  if (ImGui::Button("save")) actions.saveSettings = true;
  ImGui::SameLine();
  if (ImGui::Button("defaults")) {
    state.settings = gi::Settings{};
    actions.settingsChanged = true;
  }
  if (!state.settingsMessage.empty()) ImGui::TextWrapped("%s", state.settingsMessage.c_str());
  std::string openGroup;
  bool groupOpen = false;
  for (const gi::SettingInfo& info : gi::settingKeys()) {
    const std::string group = groupOf(info.key);
    if (group != openGroup) {
      openGroup = group;
      groupOpen = ImGui::CollapsingHeader(group.c_str());
    }
    if (!groupOpen) continue;
    const std::optional<std::string> value = settingWidget(info, gi::settingValue(state.settings, info.key));
    if (!value) continue;
    gi::Settings edited = state.settings;
    try {
      gi::applySetting(edited, info.key, *value);
      gi::validate(edited);
      state.settings = edited;
      state.settingsMessage.clear();
      actions.settingsChanged = true;
    } catch (const std::exception& error) {
      state.settingsMessage = error.what();
    }
  }
}

void timingsPanel(const PanelState& state) {
  ImGui::Text("GPU %.3f ms a frame, %.1f MB of device memory", state.frameMs, double(state.memoryBytes) / 1.0e6);
  double longest = 0.0;
  for (const gpu::LatestTiming& t : state.timings) longest = std::max(longest, t.ms);
  for (const gpu::LatestTiming& t : state.timings) {
    ImGui::ProgressBar(longest > 0.0 ? float(t.ms / longest) : 0.0f, ImVec2(120.0f, 0.0f), "");
    ImGui::SameLine();
    ImGui::Text("%7.3f ms  %s", t.ms, t.pass.c_str());
  }
}

void viewPanel(PanelState& state, PanelActions& actions) {
  const char* current = state.stageNames.empty() ? "final" : state.stageNames[std::size_t(state.stage)].c_str();
  if (ImGui::BeginCombo("image", current)) {
    for (std::size_t i = 0; i < state.stageNames.size(); ++i)
      if (ImGui::Selectable(state.stageNames[i].c_str(), int(i) == state.stage)) {
        state.stage = int(i);
        actions.viewChanged = true;
      }
    ImGui::EndCombo();
  }
  int split = int(state.split);
  ImGui::TextUnformatted("right half");
  for (SplitMode m : {SplitMode::None, SplitMode::GiOff, SplitMode::Other, SplitMode::Reference}) {
    ImGui::SameLine();
    if (ImGui::RadioButton(splitModeName(m), &split, int(m))) actions.viewChanged = true;
  }
  state.split = SplitMode(split);
  if (state.split == SplitMode::Other) {
    ImGui::InputText("other settings", state.otherSettingsFile, sizeof state.otherSettingsFile);
    ImGui::SameLine();
    if (ImGui::Button("load##other")) actions.loadOtherSettings = true;
    ImGui::TextDisabled("right: the GI with these settings (the defaults until a file is loaded)");
  }
  if (state.split == SplitMode::Reference) {
    ImGui::Text("reference: %llu spp (accumulates while the camera is still)",
                static_cast<unsigned long long>(state.referenceSpp));
    if (state.relMse && state.flip)
      ImGui::Text("GI frame against it: relMSE %.4g, HDR-FLIP %.4g", *state.relMse, *state.flip);
    if (ImGui::Button("measure now")) actions.measure = true;
  }
  ImGui::Checkbox("pixel inspector", &state.inspector);
  if (state.inspector && state.inspectedPixel) {
    ImGui::Text("pixel (%u, %u)", state.inspectedPixel->x, state.inspectedPixel->y);
    for (const InspectedValue& v : state.inspected) {
      if (v.channels == 1)
        ImGui::Text("%-40s %.5g", v.image.c_str(), double(v.value.x));
      else
        ImGui::Text("%-40s %.4g %.4g %.4g %.4g", v.image.c_str(), double(v.value.x), double(v.value.y),
                    double(v.value.z), double(v.value.w));
    }
  }
}

// The picked material's BRDF plots, in a window of their own beside the
// panels. The image is blitted where this window keeps an empty item
// (Dear ImGui 1.86's Vulkan backend draws no images of ours).
void brdfPanel(PanelState& state) {
  ImGui::SetNextWindowPos(ImVec2(346.0f, 8.0f), ImGuiCond_FirstUseEver);
  if (ImGui::Begin("BRDF", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("%s: view at 45 degrees, %u samples", state.material.name.c_str(), state.brdfPlotSamples);
    const ImVec2 size(float(state.brdfPlotSize.x), float(state.brdfPlotSize.y));
    ImGui::Dummy(size);
    const ImVec2 at = ImGui::GetItemRectMin();
    const ImVec2 windowMin = ImGui::GetWindowPos();
    const ImVec2 windowMax(windowMin.x + ImGui::GetWindowWidth(), windowMin.y + ImGui::GetWindowHeight());
    // Only where the window shows all of it, so it covers no other widget.
    if (ImGui::IsItemVisible() && at.x >= windowMin.x && at.y >= windowMin.y && at.x + size.x <= windowMax.x &&
        at.y + size.y <= windowMax.y)
      state.brdfPlotAt = glm::ivec2(int(at.x), int(at.y));
  }
  ImGui::End();
}

void materialPanel(PanelState& state, PanelActions& actions) {
  ImGui::InputText("glTF", state.gltfFile, sizeof state.gltfFile);
  ImGui::SameLine();
  if (ImGui::Button("save")) actions.saveGltf = true;
  if (!state.materialMessage.empty()) ImGui::TextWrapped("%s", state.materialMessage.c_str());
  if (!state.pickedMaterial) {
    ImGui::TextWrapped("Click a surface (left button) to edit its material.");
    return;
  }
  scene::Material& m = state.material;
  ImGui::Text("material %u: %s", *state.pickedMaterial, m.name.c_str());
  bool changed = false;
  changed |= ImGui::ColorEdit3("base colour", &m.baseColorFactor.x, ImGuiColorEditFlags_Float);
  changed |= ImGui::SliderFloat("roughness", &m.roughnessFactor, 0.0f, 1.0f);
  changed |= ImGui::SliderFloat("metallic", &m.metallicFactor, 0.0f, 1.0f);
  changed |= ImGui::ColorEdit3("emission", &m.emissiveFactor.x, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR);
  changed |= ImGui::DragFloat("emission strength", &m.emissiveStrength, 0.05f, 0.0f, 1000.0f);
  if (m.baseColorTexture >= 0 || m.metallicRoughnessTexture >= 0)
    ImGui::TextDisabled("textured: the factors multiply its textures");

  if (changed) {
    m.baseColorFactor = glm::clamp(m.baseColorFactor, 0.0f, 1.0f);
    m.emissiveFactor = glm::max(m.emissiveFactor, glm::vec3(0.0f));
    m.emissiveStrength = std::max(m.emissiveStrength, 0.0f);
    actions.materialChanged = true;
  }
}

}  // namespace

const char* giModeName(GiMode mode) {
  switch (mode) {
    case GiMode::Off:
      return "off";
    case GiMode::ScreenOnly:
      return "screen-only";
    case GiMode::Hybrid:
      break;
  }
  return "hybrid";
}

const char* splitModeName(SplitMode mode) {
  switch (mode) {
    case SplitMode::None:
      return "none";
    case SplitMode::GiOff:
      return "gi-off";
    case SplitMode::Other:
      return "other";
    case SplitMode::Reference:
      break;
  }
  return "reference";
}

const std::vector<KeyHelp>& keyHelp() {
  static const std::vector<KeyHelp> keys = {
      {"W A S D", "move forward, left, back, right"},
      {"Q E", "move down, up"},
      {"shift", "move 4x faster"},
      {"right mouse drag", "turn"},
      {"mouse wheel", "movement speed"},
      {"left click", "pick the material under the cursor"},
      {"P", "pause / resume"},
      {"R", "record frames to OUT/recording-N/ / stop"},
      {"C", "follow the camera path (--camera) / fly again"},
      {"N", "one frame while paused"},
      {"F12", "screenshot: PNG + EXR of the frame (shift: every stage too)"},
      {"H", "this help"},
      {"U", "hide / show the panels"},
      {"Esc", "quit"},
  };
  return keys;
}

void drawPanels(PanelState& state, PanelActions& actions) {
  state.brdfPlotAt.reset();
  if (state.hidden) return;
  ImGui::SetNextWindowPos(ImVec2(8.0f, 8.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330.0f, 430.0f), ImGuiCond_FirstUseEver);
  // See-through, so the frame under the panels still shows.
  ImGui::SetNextWindowBgAlpha(0.7f);
  if (ImGui::Begin("bounce")) {
    ImGui::SliderFloat("exposure", &state.exposure, 0.05f, 16.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
    ImGui::Text("camera speed %.3g / s%s%s%s", double(state.cameraSpeed), state.paused ? "   (paused)" : "",
                state.playing ? "   (camera path)" : "", state.recording ? "   (recording)" : "");
    if (ImGui::Button("screenshot (F12)")) actions.screenshot = true;
    if (ImGui::CollapsingHeader("GI settings")) settingsPanel(state, actions);
    if (ImGui::CollapsingHeader("view", ImGuiTreeNodeFlags_DefaultOpen)) viewPanel(state, actions);
    if (ImGui::CollapsingHeader("timings", ImGuiTreeNodeFlags_DefaultOpen)) timingsPanel(state);
    // Opens when a click picks a material.
    if (state.openMaterialPanel) ImGui::SetNextItemOpen(true);
    state.openMaterialPanel = false;
    if (ImGui::CollapsingHeader("material")) materialPanel(state, actions);
  }
  ImGui::End();
  if (state.pickedMaterial) brdfPanel(state);
  if (state.showHelp) {
    ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    if (ImGui::Begin("keys (H)", &state.showHelp, ImGuiWindowFlags_AlwaysAutoResize)) {
      for (const KeyHelp& k : keyHelp()) {
        ImGui::TextUnformatted(k.key);
        ImGui::SameLine(170.0f);
        ImGui::TextUnformatted(k.action);
      }
    }
    ImGui::End();
  }
}

std::string settingsJson(const gi::Settings& settings) {
  std::string json = "{\n";
  const std::vector<gi::SettingInfo>& keys = gi::settingKeys();
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const gi::SettingInfo& info = keys[i];
    std::string value = gi::settingValue(settings, info.key);
    if (info.type == "bool")
      value = value == "on" ? "true" : "false";
    else if (info.type.rfind("enum", 0) == 0)
      value = "\"" + value + "\"";
    json += "  \"" + info.key + "\": " + value + (i + 1 < keys.size() ? ",\n" : "\n");
  }
  return json + "}\n";
}

}  // namespace bounce::viewer
