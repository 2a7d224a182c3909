#include "viewer/viewer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include "bounce/gi_settings.h"
#include "gpu/format.h"
#include "gpu/frame_loop.h"
#include "gpuio/gpu_images.h"
#include "gpuio/stage_dump.h"
#include "io/image_io.h"
#include "metrics/image_metrics.h"
#include "render/frame_memory.h"
#include "render/frame_pipeline.h"
#include "render/gi_bridge.h"
#include "render/reference_renderer.h"
#include "scene/gltf_export.h"
#include "viewer/brdf_plot.h"
#include "viewer/fly_camera.h"
#include "viewer/pixel_inspector.h"
#include "viewer/script_player.h"
#include "viewer/session_recorder.h"
#include "viewer/split_view.h"
#include "viewer/viewer_shaders.h"

namespace bounce::viewer {
namespace {

namespace fs = std::filesystem;

struct DisplayParams {
  std::uint32_t width;
  std::uint32_t height;
  float exposure;
  std::uint32_t splitColumn;
};

// The BRDF plots' panels, pixels a side: three fit the panel's width. Each
// frame adds kBrdfSamplesPerFrame samples (about half a millisecond of CPU).
constexpr int kBrdfPlotPanelSize = 90;
constexpr std::uint32_t kBrdfSamplesPerFrame = 4096;

gpu::PassDesc displayPassDesc() {
  return gpu::PassDesc{.name = "viewer.display",
                       .shader = "viewer/display",
                       .shaders = viewer::shaders(),
                       .resources = {{"gIn_Frame", gpu::Access::Read, VK_FORMAT_UNDEFINED,
                                      "the frame: linear HDR radiance", gpu::ResourceKind::SampledImage},
                                     {"gIn_Right", gpu::Access::Read, VK_FORMAT_UNDEFINED,
                                      "split screen: the right half's image (GI off, or the reference)",
                                      gpu::ResourceKind::SampledImage},
                                     {"gOut_Display", gpu::Access::Write, gpu::formats::kRgba8,
                                      "tonemapped, sRGB-encoded: what the window shows"}},
                       .constants = {BOUNCE_CONSTANTS_LAYOUT("", DisplayParams, width, height, exposure, splitColumn)}};
}

// NAME, or the first of NAME-2, NAME-3... for which none of the files
// OUT/NAME+SUFFIX exists: a screenshot never replaces a file, whether an
// earlier session wrote it or the user put it there.
std::string freeOutputName(const fs::path& out, const std::string& name, std::initializer_list<const char*> suffixes) {
  const auto taken = [&](const std::string& candidate) {
    std::error_code error;
    for (const char* suffix : suffixes)
      if (fs::exists(fs::symlink_status(out / (candidate + suffix), error))) return true;
    return false;
  };
  if (!taken(name)) return name;
  for (int n = 2;; ++n)
    if (const std::string candidate = name + "-" + std::to_string(n); !taken(candidate)) return candidate;
}

// The viewer's state between frames.
class Session {
 public:
  Session(const scene::Scene& scene, const ViewerOptions& options)
      : scene_(scene),
        options_(options),
        window_(options.window),
        context_(window_.context()),
        pipeline_(context_, scene, {.renderer = fitting(context_, options)}),
        renderer_(pipeline_.renderer()),
        loop_(pipeline_.loop()),
        camera_(options.camera, sceneSize(scene)),
        display_(context_, gpu::ImageDesc{.name = "viewer.display",
                                          .width = options.renderer.width,
                                          .height = options.renderer.height,
                                          .format = gpu::formats::kRgba8,
                                          .visualize = gpu::Visualize::Color}),
        displayPass_(context_, displayPassDesc()),
        script_(options.script),
        recorder_(options.record, scene.name, options.settings, options.mode),
        split_(context_, scene, options, pipeline_),
        inspector_(context_),
        brdfImage_(context_, gpu::ImageDesc{.name = "viewer.brdf_plot",
                                            .width = std::uint32_t(brdfPlot_.width()),
                                            .height = std::uint32_t(brdfPlot_.height()),
                                            .format = gpu::formats::kRgba8,
                                            .visualize = gpu::Visualize::Color}) {
    panels_.brdfPlotSize = glm::ivec2(brdfPlot_.width(), brdfPlot_.height());
    panels_.recording = recorder_.active();
    panels_.mode = options.mode;
    panels_.settings = options.settings;
    panels_.exposure = options.exposure;
    makeGi();
  }

  // A script command's failure, or anything else thrown mid-session, leaves
  // frames in flight: the GPU must be done with every pipeline, image and
  // query pool before the members that own them are destroyed (lavapipe
  // otherwise runs a freed pipeline, and the heap is corrupted).
  ~Session() { window_.waitIdle(); }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  int run();

 private:
  // The renderer's options, once the frame's images (the renderer's, the
  // GI library's in its larger mode, the window's) are known to fit the
  // device: nothing is made for a frame it cannot hold.
  static const render::FrameRendererOptions& fitting(const gpu::Context& context, const ViewerOptions& options) {
    const std::uint32_t width = options.renderer.width, height = options.renderer.height;
    const std::uint64_t display = std::uint64_t(width) * height * gpu::formatInfo(gpu::formats::kRgba8).bytesPerPixel;
    render::requireFrameMemory(context, width, height, std::pair(options.hybrid, options.settings), false, display);
    return options.renderer;
  }
  static float sceneSize(const scene::Scene& scene) {
    const scene::Bounds bounds = scene::worldBounds(scene, 0.0f);
    return glm::length(bounds.max - bounds.min);
  }
  void makeGi();
  // A script command the player hands over; true when it takes the next frame.
  bool execute(const ScriptCommand& command);
  FlyInput interactiveInput();
  void applyPanelActions(const PanelActions& actions);
  void renderFrame(const FlyInput& input, bool capture);
  gpu::Image& frameImage() { return pipeline_.frameImage(); }
  render::GiBridge* gi() { return pipeline_.gi(); }
  void pick(std::uint32_t x, std::uint32_t y);
  void editMaterial(const scene::Material& material);
  void screenshot(const std::string& name);
  // Every image a user may look at: the renderer's (render.NAME) and the GI library's.
  std::vector<NamedImage> namedImages();
  void refreshStageNames();
  void showStage();
  // Uploads display values (rgba, [0, 1]) into an rgba8 image the window
  // blits (blocking).
  void uploadForWindow(gpu::Image& image, const io::ImageF& pixels);
  // The frame's pixel under the cursor (the frame is stretched over the
  // window); empty off the frame.
  std::optional<glm::uvec2> framePixelAt(glm::dvec2 cursor) const;
  void inspect(std::uint32_t x, std::uint32_t y);
  void measure();
  void saveGltf(const fs::path& file);
  void loadOtherSettings(const fs::path& file);
  // The frame's costs, sampled once a frame for the `timings` command.
  void recordCosts();
  void printCosts(const std::string& label);
  void writeStages(const std::string& name);
  void updateTitle();
  [[noreturn]] void scriptFailure(const ScriptCommand& command, const std::string& problem) const {
    throw std::runtime_error(options_.scriptName + ":" + std::to_string(command.line) + ": " + problem);
  }

  const scene::Scene& scene_;
  const ViewerOptions& options_;
  Window window_;
  gpu::Context& context_;
  // The renderer and the library (made anew when the GI mode or settings
  // change), frame by frame; renderer_ and loop_ are its parts.
  render::FramePipeline pipeline_;
  render::FrameRenderer& renderer_;
  gpu::FrameLoop& loop_;
  FlyCamera camera_;
  gpu::Image display_;
  gpu::ComputePass displayPass_;
  PanelState panels_;
  bool cut_ = true;             // the next frame reuses no history
  std::uint64_t rendered_ = 0;  // frames rendered since start
  ScriptPlayer script_;         // --script: its clock
  SessionRecorder recorder_;    // --record: the session as a script
  SplitView split_;             // the split screen's right half
  PixelInspector inspector_;
  bool stepOnce_ = false;
  bool quit_ = false;
  std::string pendingStages_;  // the next frame's stages go there
  std::vector<gpu::CapturedStage> captures_;
  std::chrono::steady_clock::time_point lastFrame_ = std::chrono::steady_clock::now();
  glm::dvec2 lastCursor_{0.0};
  bool dragging_ = false;
  bool captureOnce_ = false;  // the next frame is captured (a new library's validation views)
  // The picked material's BRDF plots, refined a little every frame.
  BrdfPlot brdfPlot_{kBrdfPlotPanelSize};
  gpu::Image brdfImage_;
  void refineBrdfPlot();
  std::map<std::string, std::size_t> timingCounts_;
  // The camera path (C, or a script's play) and its clock.
  float pathTime_ = 0.0f;
  int pathSegment_ = 0;
  // R: every frame as a numbered PNG (framesDir_ empty: not recording).
  void setFrameRecording(bool on);
  void writeRecordedFrame();
  fs::path framesDir_;
  std::uint32_t framesWritten_ = 0, recordings_ = 0;
  struct CostSamples {
    std::vector<double> frameGpuMs, giGpuMs, viewerGpuMs, presentGpuMs, cpuMs;
  } costs_;
  std::chrono::steady_clock::time_point lastCostSample_ = std::chrono::steady_clock::now();
};

void Session::makeGi() {
  pipeline_.setGi(panels_.mode == GiMode::Off
                      ? std::nullopt
                      : std::optional(std::pair(panels_.mode == GiMode::Hybrid ? options_.hybrid : options_.screenOnly,
                                                panels_.settings)));
  cut_ = true;  // a new library has no history
  // Its validation views are made on its first captured frame: capture one
  // so that they are in the stage list.
  captureOnce_ = gi() != nullptr;
  refreshStageNames();
}

std::vector<NamedImage> Session::namedImages() {
  std::vector<NamedImage> all;
  for (const render::Aov& aov : renderer_.aovs()) all.push_back({"render." + aov.name, aov.image});
  if (gi())
    for (const render::GiBridge::Named& named : gi()->images()) all.push_back({named.name, named.image});
  return all;
}

void Session::refreshStageNames() {
  const std::string shown = panels_.stageNames.empty() ? "final" : panels_.stageNames[std::size_t(panels_.stage)];
  panels_.stageNames = {"final"};
  for (const NamedImage& named : namedImages()) panels_.stageNames.push_back(named.name);
  const auto at = std::find(panels_.stageNames.begin(), panels_.stageNames.end(), shown);
  panels_.stage = at == panels_.stageNames.end() ? 0 : int(at - panels_.stageNames.begin());
}

void Session::uploadForWindow(gpu::Image& image, const io::ImageF& pixels) {
  gpuio::uploadImage(context_, image, pixels);
  context_.submitAndWait([&](gpu::Recorder& recorder) { handOverToWindow(recorder, image); });
}

std::optional<glm::uvec2> Session::framePixelAt(glm::dvec2 cursor) const {
  const VkExtent2D extent = window_.extent();
  const double x = cursor.x * options_.renderer.width / std::max(1u, extent.width);
  const double y = cursor.y * options_.renderer.height / std::max(1u, extent.height);
  if (x < 0.0 || y < 0.0 || x >= options_.renderer.width || y >= options_.renderer.height) return std::nullopt;
  return glm::uvec2(std::uint32_t(x), std::uint32_t(y));
}

void Session::showStage() {
  const std::string& name = panels_.stageNames[std::size_t(panels_.stage)];
  gpu::Image* image = nullptr;
  for (const NamedImage& named : namedImages())
    if (named.name == name) image = named.image;
  if (!image) {
    panels_.stage = 0;  // the image went with the GI (turned off)
    return;
  }
  loop_.finish();
  const io::ImageF pixels = gpuio::readbackImage(context_, *image);
  const gpuio::VisualizedImage shown = gpuio::visualize(pixels, image->desc().visualize);
  const io::ImageF display = io::toDisplay(shown.image, shown.encoding, panels_.exposure);
  // Half- and tile-resolution images fill the window too (nearest texel).
  io::ImageF rgba(int(display_.width()), int(display_.height()), {"R", "G", "B", "A"});
  for (std::uint32_t y = 0; y < display_.height(); ++y)
    for (std::uint32_t x = 0; x < display_.width(); ++x) {
      const std::size_t sx = std::size_t(x) * std::size_t(display.width) / display_.width();
      const std::size_t sy = std::size_t(y) * std::size_t(display.height) / display_.height();
      const float* in = &display.pixels[(sy * std::size_t(display.width) + sx) * 3];
      float* out = &rgba.pixels[(std::size_t(y) * display_.width() + x) * 4];
      out[0] = in[0], out[1] = in[1], out[2] = in[2], out[3] = 1.0f;
    }
  uploadForWindow(display_, rgba);
}

void Session::inspect(std::uint32_t x, std::uint32_t y) {
  loop_.finish();
  panels_.inspectedPixel = glm::uvec2(x, y);
  panels_.inspected = inspector_.inspect(namedImages(), x, y, display_.width(), display_.height());
}

void Session::measure() { split_.measure(panels_, frameImage()); }

void Session::saveGltf(const fs::path& file) {
  scene::Scene edited = scene_;
  edited.materials = renderer_.materials();
  // Nothing is replaced: the .bin and the textures beside the .gltf may be
  // the user's as much as the .gltf itself.
  scene::writeGltf(edited, file, scene::ExistingFiles::Refuse);
  panels_.materialMessage = "saved " + file.string();
  std::printf("wrote %s (the scene with its edited materials)\n", file.c_str());
}

// The split's other settings: the defaults, then the file (as --gi-settings
// applies one); its library starts anew with them.
void Session::loadOtherSettings(const fs::path& file) {
  gi::Settings loaded;
  gi::applySettingsFile(loaded, file);
  gi::validate(loaded);
  split_.setOtherSettings(panels_, loaded);
  recorder_.line("other-settings " + file.string());
}

bool Session::execute(const ScriptCommand& c) {
  using Kind = ScriptCommand::Kind;
  switch (c.kind) {
    case Kind::Camera:
    case Kind::Pose: {
      scene::CameraPose pose = camera_.pose();
      pose.position = glm::vec3(c.numbers[0], c.numbers[1], c.numbers[2]);
      pose.target = glm::vec3(c.numbers[3], c.numbers[4], c.numbers[5]);
      try {
        render::checkCamera(pose);
      } catch (const std::exception& error) {
        scriptFailure(c, error.what());
      }
      camera_.setPose(pose);
      cut_ = cut_ || c.kind == Kind::Camera;  // camera jumps; pose moves
      break;
    }
    case Kind::Play:  // the player waits its frames
      if (!options_.path) scriptFailure(c, "no camera path to play");
      panels_.playing = true;
      cut_ = true;  // from wherever the camera was to the path
      break;
    case Kind::Click:
      if (c.numbers[0] >= options_.renderer.width || c.numbers[1] >= options_.renderer.height)
        scriptFailure(c, "pixel (" + std::to_string(int(c.numbers[0])) + ", " + std::to_string(int(c.numbers[1])) +
                             ") is outside the " + std::to_string(options_.renderer.width) + "x" +
                             std::to_string(options_.renderer.height) + " frame");
      pick(std::uint32_t(c.numbers[0]), std::uint32_t(c.numbers[1]));
      break;
    case Kind::Set:
      try {
        gi::Settings edited = panels_.settings;
        gi::applySetting(edited, c.words[0], c.words[1]);
        // Hybrid traces through the scene: checked as the library built next will check it, with this line.
        gi::validate(edited, panels_.mode == GiMode::Hybrid);
        panels_.settings = edited;
      } catch (const std::exception& error) {
        scriptFailure(c, error.what());
      }
      makeGi();
      break;
    case Kind::Gi:
      panels_.mode = c.words[0] == "off"           ? GiMode::Off
                     : c.words[0] == "screen-only" ? GiMode::ScreenOnly
                                                   : GiMode::Hybrid;
      makeGi();
      break;
    case Kind::Material: {
      if (!panels_.pickedMaterial) scriptFailure(c, "no material is picked: 'click X Y' on a surface first");
      scene::Material edited = panels_.material;
      const std::string& field = c.words[0];
      if (field == "base_color")
        edited.baseColorFactor =
            glm::vec4(float(c.numbers[0]), float(c.numbers[1]), float(c.numbers[2]), edited.baseColorFactor.w);
      else if (field == "emission")
        edited.emissiveFactor = glm::vec3(float(c.numbers[0]), float(c.numbers[1]), float(c.numbers[2]));
      else if (field == "roughness")
        edited.roughnessFactor = float(c.numbers[0]);
      else if (field == "emission_strength")
        edited.emissiveStrength = float(c.numbers[0]);
      else
        edited.metallicFactor = float(c.numbers[0]);
      editMaterial(edited);
      break;
    }
    case Kind::Screenshot:
      screenshot(c.words[0]);
      break;
    case Kind::Stages:
      pendingStages_ = c.words[0];
      return true;  // the next frame is captured
    case Kind::Window:
      fs::create_directories(options_.out);
      window_.captureNextPresent(options_.out / (freeOutputName(options_.out, c.words[0], {".png"}) + ".png"));
      return true;  // this frame's window, as the commands so far left it
    case Kind::Timings:
      printCosts(c.words[0]);
      break;
    case Kind::Frames:
      setFrameRecording(c.words[0] == "on");
      break;
    case Kind::Panels:
      panels_.hidden = c.words[0] == "off";
      break;
    case Kind::Split:
      split_.set(panels_, c.words[0] == "none"     ? SplitMode::None
                          : c.words[0] == "gi-off" ? SplitMode::GiOff
                          : c.words[0] == "other"  ? SplitMode::Other
                                                   : SplitMode::Reference);
      break;
    case Kind::OtherSettings:
      try {
        loadOtherSettings(c.words[0]);
      } catch (const std::exception& error) {
        scriptFailure(c, error.what());
      }
      break;
    case Kind::Measure:
      if (!split_.reference()) scriptFailure(c, "no reference to measure against: 'split reference' and a frame first");
      measure();
      break;
    case Kind::Stage: {
      const auto at = std::find(panels_.stageNames.begin(), panels_.stageNames.end(), c.words[0]);
      if (at == panels_.stageNames.end()) {
        std::string known;
        for (const std::string& name : panels_.stageNames) known += (known.empty() ? "" : ", ") + name;
        scriptFailure(c, "no image '" + c.words[0] + "' (images: " + known + ")");
      }
      panels_.stage = int(at - panels_.stageNames.begin());
      break;
    }
    case Kind::Inspect: {
      if (c.numbers[0] >= options_.renderer.width || c.numbers[1] >= options_.renderer.height)
        scriptFailure(c, "pixel (" + std::to_string(int(c.numbers[0])) + ", " + std::to_string(int(c.numbers[1])) +
                             ") is outside the " + std::to_string(options_.renderer.width) + "x" +
                             std::to_string(options_.renderer.height) + " frame");
      inspect(std::uint32_t(c.numbers[0]), std::uint32_t(c.numbers[1]));
      for (const InspectedValue& v : panels_.inspected)
        std::printf("inspect (%u, %u) %s: %g %g %g %g\n", std::uint32_t(c.numbers[0]), std::uint32_t(c.numbers[1]),
                    v.image.c_str(), double(v.value.x), double(v.value.y), double(v.value.z), double(v.value.w));
      break;
    }
    case Kind::SaveGltf:
      try {
        fs::create_directories(options_.out);
        saveGltf(options_.out / c.words[0]);
      } catch (const std::exception& error) {
        scriptFailure(c, error.what());
      }
      break;
    case Kind::Wait:
    case Kind::Key:
    case Kind::Look:
    case Kind::Quit:
      break;  // the player's own (ScriptPlayer)
  }
  return false;
}

FlyInput Session::interactiveInput() {
  FlyInput input;
  GLFWwindow* w = window_.handle();
  const ImGuiIO& io = ImGui::GetIO();
  // Dear ImGui 1.86 indexes its key state by GLFW's key codes.
  if (!io.WantCaptureKeyboard) {
    input.forward = glfwGetKey(w, GLFW_KEY_W) == GLFW_PRESS;
    input.left = glfwGetKey(w, GLFW_KEY_A) == GLFW_PRESS;
    input.back = glfwGetKey(w, GLFW_KEY_S) == GLFW_PRESS;
    input.right = glfwGetKey(w, GLFW_KEY_D) == GLFW_PRESS;
    input.down = glfwGetKey(w, GLFW_KEY_Q) == GLFW_PRESS;
    input.up = glfwGetKey(w, GLFW_KEY_E) == GLFW_PRESS;
    input.fast = glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS;
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false)) quit_ = true;
    if (ImGui::IsKeyPressed(GLFW_KEY_H, false)) panels_.showHelp = !panels_.showHelp;
    if (ImGui::IsKeyPressed(GLFW_KEY_U, false)) panels_.hidden = !panels_.hidden;
    if (ImGui::IsKeyPressed(GLFW_KEY_P, false)) panels_.paused = !panels_.paused;
    if (ImGui::IsKeyPressed(GLFW_KEY_R, false)) setFrameRecording(framesDir_.empty());
    if (ImGui::IsKeyPressed(GLFW_KEY_C, false) && options_.path) {
      panels_.playing = !panels_.playing;
      cut_ = cut_ || panels_.playing;  // from wherever the camera was to the path
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_N, false)) stepOnce_ = true;
    if (ImGui::IsKeyPressed(GLFW_KEY_F12, false)) {
      static int shot = 0;
      const std::string name = "screenshot-" + std::to_string(shot++);
      screenshot(name);
      if (io.KeyShift) pendingStages_ = name;
    }
  }
  glm::dvec2 cursor;
  glfwGetCursorPos(w, &cursor.x, &cursor.y);
  const bool turning = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS && !io.WantCaptureMouse;
  if (turning && dragging_) input.turnPixels = glm::vec2(cursor - lastCursor_);
  dragging_ = turning;
  lastCursor_ = cursor;
  if (!io.WantCaptureMouse) {
    input.wheel = io.MouseWheel;
    const std::optional<glm::uvec2> pixel = framePixelAt(cursor);
    if (pixel && panels_.inspector) inspect(pixel->x, pixel->y);
    if (pixel && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) pick(pixel->x, pixel->y);
  }
  return input;
}

void Session::pick(std::uint32_t x, std::uint32_t y) {
  loop_.finish();  // the ids of the last frame are complete
  panels_.pickedMaterial = renderer_.materialAt(x, y);
  if (panels_.pickedMaterial) {
    panels_.material = renderer_.materials().at(*panels_.pickedMaterial);
    panels_.openMaterialPanel = true;
    recorder_.line("click " + std::to_string(x) + " " + std::to_string(y));
    std::printf("picked material %u (%s) at pixel (%u, %u)\n", *panels_.pickedMaterial, panels_.material.name.c_str(),
                x, y);
  } else {
    std::printf("no surface at pixel (%u, %u)\n", x, y);
  }
}

void Session::editMaterial(const scene::Material& material) {
  loop_.finish();  // no frame in flight reads the material table
  renderer_.setMaterial(*panels_.pickedMaterial, material);
  const scene::Material before = panels_.material;
  panels_.material = material;
  const glm::vec3 base(material.baseColorFactor);
  if (material.baseColorFactor != before.baseColorFactor)
    recorder_.line("material base_color" + scriptNumbers({base.x, base.y, base.z}));
  if (material.roughnessFactor != before.roughnessFactor)
    recorder_.line("material roughness" + scriptNumbers({material.roughnessFactor}));
  if (material.metallicFactor != before.metallicFactor)
    recorder_.line("material metallic" + scriptNumbers({material.metallicFactor}));
  const glm::vec3 emission = material.emissiveFactor;
  if (emission != before.emissiveFactor)
    recorder_.line("material emission" + scriptNumbers({emission.x, emission.y, emission.z}));
  if (material.emissiveStrength != before.emissiveStrength)
    recorder_.line("material emission_strength" + scriptNumbers({material.emissiveStrength}));
}

void Session::applyPanelActions(const PanelActions& actions) {
  if (actions.modeChanged || actions.settingsChanged) makeGi();
  if (actions.materialChanged && panels_.pickedMaterial) editMaterial(panels_.material);
  if (actions.screenshot) {
    static int shot = 0;
    screenshot("screenshot-ui-" + std::to_string(shot++));
  }
  if (actions.viewChanged) split_.set(panels_, panels_.split);
  if (actions.loadOtherSettings) {
    try {
      loadOtherSettings(panels_.otherSettingsFile);
      panels_.settingsMessage = std::string("other settings from ") + panels_.otherSettingsFile;
    } catch (const std::exception& error) {
      panels_.settingsMessage = error.what();
    }
  }
  if (actions.measure) measure();
  if (actions.saveGltf) {
    try {
      saveGltf(panels_.gltfFile);
    } catch (const std::exception& error) {
      panels_.materialMessage = error.what();
    }
  }
  if (actions.loadSettings) {
    try {
      gi::Settings loaded = panels_.settings;
      gi::applySettingsFile(loaded, panels_.settingsFile);
      gi::validate(loaded);
      panels_.settings = loaded;
      panels_.settingsMessage = std::string("loaded ") + panels_.settingsFile;
      makeGi();
    } catch (const std::exception& error) {
      panels_.settingsMessage = error.what();
    }
  }
  if (actions.saveSettings) {
    const fs::path file = panels_.settingsFile;
    std::error_code error;
    if (fs::exists(file, error)) {
      panels_.settingsMessage = file.string() + " exists; not overwritten (choose another name)";
    } else {
      std::ofstream out(file, std::ios::binary);
      out << settingsJson(panels_.settings);
      panels_.settingsMessage = out ? "saved " + file.string() : "cannot write " + file.string();
    }
  }
}

void Session::renderFrame(const FlyInput& input, bool capture) {
  const auto now = std::chrono::steady_clock::now();
  const float seconds =
      options_.scripted ? 1.0f / options_.fps : std::chrono::duration<float>(now - lastFrame_).count();
  lastFrame_ = now;
  if (panels_.playing && options_.path) {
    // The camera path's pose at its own clock; a change of segment is a cut.
    const int segment = options_.path->segment(pathTime_);
    if (segment != pathSegment_) cut_ = true;
    pathSegment_ = segment;
    camera_.setPose(options_.path->pose(pathTime_));
    pathTime_ += seconds;
  } else {
    camera_.update(input, std::min(seconds, 0.25f));
  }
  panels_.cameraSpeed = camera_.speed();
  recorder_.state(panels_);

  const float time = split_.prepare(panels_, rendered_, float(rendered_) / options_.fps);
  const render::FrameView view{camera_.pose(), time, cut_};
  gpu::Recorder& recorder = pipeline_.begin(view, {.captureStages = capture});
  gpu::Image* right = split_.record(recorder, loop_.frameIndex(), view, panels_);
  const DisplayParams params{display_.width(), display_.height(), panels_.exposure,
                             right ? display_.width() / 2 : display_.width()};
  recorder.dispatch(displayPass_, display_.width(), display_.height(),
                    {{"gIn_Frame", frameImage(), context_.nearestSampler()},
                     {"gIn_Right", right ? *right : frameImage(), context_.nearestSampler()},
                     {"gOut_Display", display_}},
                    params);
  handOverToWindow(recorder, display_);
  pipeline_.end();
  recorder_.frame(view.camera, view.cut);
  if (!framesDir_.empty()) writeRecordedFrame();
  cut_ = false;
  ++rendered_;
}

void Session::screenshot(const std::string& requested) {
  recorder_.line("screenshot " + requested);
  loop_.finish();
  fs::create_directories(options_.out);
  const io::ImageF frame = gpuio::readbackImage(context_, frameImage());
  const gpuio::VisualizedImage shown = gpuio::visualize(frame, gpu::Visualize::Radiance);
  const std::string name = freeOutputName(options_.out, requested, {".png", ".exr"});
  if (name != requested) std::printf("%s.png or .exr exists: the screenshot is %s\n", requested.c_str(), name.c_str());
  const fs::path png = options_.out / (name + ".png"), exr = options_.out / (name + ".exr");
  io::writePng(png, shown.image, shown.encoding, panels_.exposure);
  io::writeExr(exr, frame);
  std::printf("wrote %s and %s (frame %llu)\n", png.c_str(), exr.c_str(), (unsigned long long)rendered_);
}

void Session::writeStages(const std::string& name) {
  loop_.finish();
  for (gpu::CapturedStage& c : loop_.takeCaptures()) captures_.push_back(std::move(c));
  const fs::path dir = options_.out / (freeOutputName(options_.out, name, {"-stages"}) + "-stages");
  const std::vector<fs::path> files = gpuio::writeStageDumps(dir, captures_, panels_.exposure);
  captures_.clear();
  std::printf("wrote %zu stage images to %s\n", files.size(), dir.c_str());
}

void Session::updateTitle() {
  // The passes of the latest completed frame: those whose count of samples
  // grew (a pass that ran once, as the environment's prefilter, drops out).
  std::vector<gpu::LatestTiming> ran;
  for (const gpu::LatestTiming& t : loop_.timings().latest()) {
    std::size_t& seen = timingCounts_[t.pass];
    if (t.samples > seen) ran.push_back(t);
    seen = t.samples;
  }
  if (ran.empty()) return;  // no frame completed since the last look
  panels_.timings = std::move(ran);
  double frameMs = 0.0;
  for (const gpu::LatestTiming& t : panels_.timings) frameMs += t.ms;
  panels_.frameMs = frameMs;
  panels_.memoryBytes = context_.deviceLocalBytesInUse();
  if (rendered_ % 15 != 0) return;
  char title[512];
  std::snprintf(title, sizeof title, "bounce view - %s - %s - %ux%u - %.2f ms", scene_.name.c_str(),
                context_.deviceInfo().name.c_str(), options_.renderer.width, options_.renderer.height, frameMs);
  window_.setTitle(title);
}

void Session::recordCosts() {
  // Only a script's 'timings' reads them; an interactive session would grow them for ever.
  if (!options_.scripted) return;
  const auto now = std::chrono::steady_clock::now();
  costs_.cpuMs.push_back(std::chrono::duration<double, std::milli>(now - lastCostSample_).count());
  lastCostSample_ = now;
  double frame = 0.0, gi = 0.0, viewer = 0.0;
  for (const gpu::LatestTiming& t : panels_.timings) {
    frame += t.ms;
    if (t.pass.rfind("gi.", 0) == 0) gi += t.ms;
    if (t.pass.rfind("viewer.", 0) == 0) viewer += t.ms;
  }
  costs_.frameGpuMs.push_back(frame);
  costs_.giGpuMs.push_back(gi);
  costs_.viewerGpuMs.push_back(viewer + window_.lastPresentGpuMs());
  costs_.presentGpuMs.push_back(window_.lastPresentGpuMs());
}

void Session::printCosts(const std::string& label) {
  std::printf(
      "timings %s: %zu frames, median GPU ms: frame passes %.4f (GI library %.4f), viewer's own %.4f (display "
      "%.4f + blit and panels %.4f); CPU ms a frame %.3f\n",
      label.c_str(), costs_.cpuMs.size(), gpu::medianOf(costs_.frameGpuMs), gpu::medianOf(costs_.giGpuMs),
      gpu::medianOf(costs_.viewerGpuMs), gpu::medianOf(costs_.viewerGpuMs) - gpu::medianOf(costs_.presentGpuMs),
      gpu::medianOf(costs_.presentGpuMs), gpu::medianOf(costs_.cpuMs));
  costs_ = {};
}

void Session::refineBrdfPlot() {
  if (!panels_.pickedMaterial) return;
  const scene::Material& m = panels_.material;
  brdfPlot_.setMaterial(glm::vec3(m.baseColorFactor), m.roughnessFactor, m.metallicFactor);
  const bool first = brdfPlot_.samples() == 0;
  if (!brdfPlot_.refine(kBrdfSamplesPerFrame) && !first) return;
  panels_.brdfPlotSamples = brdfPlot_.samples();
  // The bytes are display values already: the UNORM image keeps them as they are.
  io::ImageF pixels(brdfPlot_.width(), brdfPlot_.height(), {"R", "G", "B", "A"});
  const std::vector<std::uint8_t>& bytes = brdfPlot_.rgba();
  for (std::size_t i = 0; i < bytes.size(); ++i) pixels.pixels[i] = float(bytes[i]) / 255.0f;
  uploadForWindow(brdfImage_, pixels);
}

void Session::setFrameRecording(bool on) {
  if (on && framesDir_.empty()) {
    // The next free recording-N: an earlier run's frames stay as they are.
    do framesDir_ = options_.out / ("recording-" + std::to_string(recordings_++));
    while (fs::exists(framesDir_));
    fs::create_directories(framesDir_);
    framesWritten_ = 0;
    std::printf("recording frames to %s\n", framesDir_.c_str());
  } else if (!on && !framesDir_.empty()) {
    std::printf("wrote %u frames to %s\n", framesWritten_, framesDir_.c_str());
    framesDir_.clear();
  }
  recorder_.line(on ? "frames on" : "frames off");
  panels_.recording = !framesDir_.empty() || recorder_.active();
}

void Session::writeRecordedFrame() {
  loop_.finish();  // the frame just submitted
  const io::ImageF frame = gpuio::readbackImage(context_, frameImage());
  const gpuio::VisualizedImage shown = gpuio::visualize(frame, gpu::Visualize::Radiance);
  char name[32];
  std::snprintf(name, sizeof name, "frame%04u.png", framesWritten_++);
  io::writePng(framesDir_ / name, shown.image, shown.encoding, panels_.exposure);
}

int Session::run() {
  bool scriptRunning = options_.scripted;
  while (!quit_ && !window_.closeRequested()) {
    window_.beginUiFrame();
    FlyInput input;
    bool lastPresent = false;  // the script ended: show (and capture) what there is, then close
    if (scriptRunning) {
      const ScriptPlayer::Step step =
          script_.step(input, [&](const ScriptCommand& command) { return execute(command); });
      if (step.stopPlaying) panels_.playing = false;
      scriptRunning = step.running;
      lastPresent = !scriptRunning;
    } else if (!window_.headless()) {
      input = interactiveInput();
    }
    PanelActions actions;
    drawPanels(panels_, actions);
    ImGui::Render();
    if (quit_) break;
    applyPanelActions(actions);
    // The validation views are drawn on captured frames only: the stage
    // view of one captures every frame it shows.
    const std::string& shown = panels_.stageNames[std::size_t(panels_.stage)];
    const bool capture = !pendingStages_.empty() || captureOnce_ || shown.find("validation") != std::string::npos;
    const bool render = !lastPresent && (!panels_.paused || stepOnce_ || options_.scripted);
    stepOnce_ = false;
    if (render) {
      renderFrame(input, capture);
      // The error readout at 4, 8, 16... samples per pixel: each doubling halves the reference's noise.
      if (split_.dueForMeasure(panels_)) measure();
      if (panels_.stage > 0) showStage();
      if (captureOnce_) {
        loop_.finish();
        captureOnce_ = false;
        refreshStageNames();
      }
      // Copies taken only to draw the validation views are not kept.
      if (capture && pendingStages_.empty()) {
        loop_.finish();
        loop_.takeCaptures();
      }
    }
    // Only a frame whose stages were asked for (shift+F12, a script's
    // "stages NAME") writes them: a capture for the validation views does not.
    if (capture && render && !pendingStages_.empty()) {
      writeStages(pendingStages_);
      pendingStages_.clear();
    }
    refineBrdfPlot();
    std::vector<Window::Overlay> overlays;
    if (panels_.brdfPlotAt && panels_.brdfPlotSamples > 0)
      overlays.push_back({&brdfImage_, panels_.brdfPlotAt->x, panels_.brdfPlotAt->y});
    window_.present(display_, ImGui::GetDrawData(), overlays);
    updateTitle();
    recordCosts();
    if (lastPresent) break;
  }
  recorder_.finish();
  if (!framesDir_.empty()) setFrameRecording(false);
  loop_.finish();
  window_.waitIdle();
  const std::size_t messages = context_.validationMessages().size();
  if (messages > 0) std::fprintf(stderr, "bounce view: %zu validation messages\n", messages);
  return messages > 0 ? 1 : 0;
}

}  // namespace

int runViewer(const scene::Scene& scene, const ViewerOptions& options) {
  Session session(scene, options);
  return session.run();
}

}  // namespace bounce::viewer
