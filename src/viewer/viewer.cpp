#include "viewer/viewer.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
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
#include "render/gi_bridge.h"
#include "viewer/fly_camera.h"
#include "viewer/viewer_shaders.h"

namespace bounce::viewer {
namespace {

namespace fs = std::filesystem;

struct DisplayParams {
  std::uint32_t width;
  std::uint32_t height;
  float exposure;
};

gpu::PassDesc displayPassDesc() {
  return gpu::PassDesc{.name = "viewer.display",
                       .shader = "viewer/display",
                       .shaders = viewer::shaders(),
                       .resources = {{"gIn_Frame", gpu::Access::Read, VK_FORMAT_UNDEFINED,
                                      "the frame: linear HDR radiance", gpu::ResourceKind::SampledImage},
                                     {"gOut_Display", gpu::Access::Write, gpu::formats::kRgba8,
                                      "tonemapped, sRGB-encoded: what the window shows"}},
                       .constants = {BOUNCE_CONSTANTS_LAYOUT("", DisplayParams, width, height, exposure)}};
}

// The viewer's state between frames.
class Session {
 public:
  Session(const scene::Scene& scene, const ViewerOptions& options)
      : scene_(scene),
        options_(options),
        window_(options.window),
        context_(window_.context()),
        renderer_(context_, scene, options.renderer),
        loop_(context_, render::FrameRenderer::kFramesInFlight),
        camera_(options.camera, sceneSize(scene)),
        display_(context_, gpu::ImageDesc{.name = "viewer.display",
                                          .width = options.renderer.width,
                                          .height = options.renderer.height,
                                          .format = gpu::formats::kRgba8,
                                          .visualize = gpu::Visualize::Color}),
        displayPass_(context_, displayPassDesc()) {
    panels_.mode = options.mode;
    panels_.settings = options.settings;
    panels_.exposure = options.exposure;
    makeGi();
  }

  int run();

 private:
  static float sceneSize(const scene::Scene& scene) {
    const scene::Bounds bounds = scene::worldBounds(scene, 0.0f);
    return glm::length(bounds.max - bounds.min);
  }
  void makeGi();
  // Script: runs commands until one takes frames; false when it has ended.
  bool stepScript(FlyInput& input);
  FlyInput interactiveInput();
  void applyPanelActions(const PanelActions& actions);
  void renderFrame(const FlyInput& input, bool capture);
  gpu::Image& frameImage() { return gi_ ? gi_->composite() : renderer_.direct(); }
  void pick(std::uint32_t x, std::uint32_t y);
  void editMaterial(const scene::Material& material);
  void screenshot(const std::string& name);
  void writeStages(const std::string& name);
  void updateTitle();
  [[noreturn]] void scriptFailure(const ScriptCommand& command, const std::string& problem) const {
    throw std::runtime_error("script line " + std::to_string(command.line) + ": " + problem);
  }

  const scene::Scene& scene_;
  const ViewerOptions& options_;
  Window window_;
  gpu::Context& context_;
  render::FrameRenderer renderer_;
  gpu::FrameLoop loop_;
  std::unique_ptr<render::GiBridge> gi_;
  FlyCamera camera_;
  gpu::Image display_;
  gpu::ComputePass displayPass_;
  PanelState panels_;
  render::FrameView previous_{};
  bool cut_ = true;             // the next frame reuses no history
  std::uint64_t rendered_ = 0;  // frames rendered since start
  // Script progress.
  std::size_t next_ = 0;
  std::uint32_t waitFrames_ = 0;
  std::string heldKey_;
  std::uint32_t heldFrames_ = 0;
  bool stepOnce_ = false;
  bool quit_ = false;
  std::string pendingStages_;  // the next frame's stages go there
  std::vector<gpu::CapturedStage> captures_;
  std::chrono::steady_clock::time_point lastFrame_ = std::chrono::steady_clock::now();
  glm::dvec2 lastCursor_{0.0};
  bool dragging_ = false;
};

void Session::makeGi() {
  loop_.finish();
  gi_.reset();
  if (panels_.mode != GiMode::Off)
    gi_ = std::make_unique<render::GiBridge>(
        context_, panels_.mode == GiMode::Hybrid ? options_.hybrid : options_.screenOnly, panels_.settings);
  cut_ = true;  // a new library has no history
}

bool Session::stepScript(FlyInput& input) {
  if (waitFrames_ > 0) {
    --waitFrames_;
    return true;
  }
  if (heldFrames_ > 0) {
    --heldFrames_;
    input.forward = heldKey_ == "w";
    input.left = heldKey_ == "a";
    input.back = heldKey_ == "s";
    input.right = heldKey_ == "d";
    input.down = heldKey_ == "q";
    input.up = heldKey_ == "e";
    input.fast = heldKey_ == "shift";
    return true;
  }
  using Kind = ScriptCommand::Kind;
  while (next_ < options_.script.size()) {
    const ScriptCommand& c = options_.script[next_++];
    switch (c.kind) {
      case Kind::Wait:
        waitFrames_ = std::uint32_t(c.numbers[0]) - 1;
        return true;
      case Kind::Key:
        heldKey_ = c.words[0];
        heldFrames_ = std::uint32_t(c.numbers[0]);
        return stepScript(input);
      case Kind::Look:
        input.turnPixels += glm::vec2(float(c.numbers[0]), float(c.numbers[1]));
        break;
      case Kind::Camera: {
        scene::CameraPose pose = camera_.pose();
        pose.position = glm::vec3(c.numbers[0], c.numbers[1], c.numbers[2]);
        pose.target = glm::vec3(c.numbers[3], c.numbers[4], c.numbers[5]);
        try {
          render::checkCamera(pose);
        } catch (const std::exception& error) {
          scriptFailure(c, error.what());
        }
        camera_.setPose(pose);
        cut_ = true;
        break;
      }
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
          gi::validate(edited);
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
        window_.captureNextPresent(options_.out / (c.words[0] + ".png"));
        break;
      case Kind::Quit:
        return false;
    }
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
    if (ImGui::IsKeyPressed(GLFW_KEY_P, false)) panels_.paused = !panels_.paused;
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
    if (ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
      // Window pixels to frame pixels: the frame is stretched over the window.
      const VkExtent2D extent = window_.extent();
      const double x = cursor.x * options_.renderer.width / std::max(1u, extent.width);
      const double y = cursor.y * options_.renderer.height / std::max(1u, extent.height);
      if (x >= 0.0 && y >= 0.0 && x < options_.renderer.width && y < options_.renderer.height)
        pick(std::uint32_t(x), std::uint32_t(y));
    }
  }
  return input;
}

void Session::pick(std::uint32_t x, std::uint32_t y) {
  loop_.finish();  // the ids of the last frame are complete
  panels_.pickedMaterial = renderer_.materialAt(x, y);
  if (panels_.pickedMaterial) {
    panels_.material = renderer_.materials().at(*panels_.pickedMaterial);
    std::printf("picked material %u (%s) at pixel (%u, %u)\n", *panels_.pickedMaterial, panels_.material.name.c_str(),
                x, y);
  } else {
    std::printf("no surface at pixel (%u, %u)\n", x, y);
  }
}

void Session::editMaterial(const scene::Material& material) {
  loop_.finish();  // no frame in flight reads the material table
  renderer_.setMaterial(*panels_.pickedMaterial, material);
  panels_.material = material;
}

void Session::applyPanelActions(const PanelActions& actions) {
  if (actions.modeChanged || actions.settingsChanged) makeGi();
  if (actions.materialChanged && panels_.pickedMaterial) editMaterial(panels_.material);
  if (actions.screenshot) {
    static int shot = 0;
    screenshot("screenshot-ui-" + std::to_string(shot++));
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
  camera_.update(input, std::min(seconds, 0.25f));
  panels_.cameraSpeed = camera_.speed();

  const render::FrameView view{camera_.pose(), float(rendered_) / options_.fps, cut_};
  gpu::Recorder& recorder = loop_.beginFrame(capture);
  const std::uint64_t index = loop_.frameIndex();
  renderer_.record(recorder, index, view);
  if (gi_) gi_->record(recorder, renderer_, index, view, previous_, {.captureStages = capture});
  const DisplayParams params{display_.width(), display_.height(), panels_.exposure};
  recorder.dispatch(displayPass_, display_.width(), display_.height(),
                    {{"gIn_Frame", frameImage(), context_.nearestSampler()}, {"gOut_Display", display_}}, params);
  recorder.handOver(display_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_READ_BIT);
  recorder.flush();
  loop_.endFrame();
  previous_ = view;
  cut_ = false;
  ++rendered_;
}

void Session::screenshot(const std::string& name) {
  loop_.finish();
  fs::create_directories(options_.out);
  const io::ImageF frame = gpuio::readbackImage(context_, frameImage());
  const gpuio::VisualizedImage shown = gpuio::visualize(frame, gpu::Visualize::Radiance);
  const fs::path png = options_.out / (name + ".png"), exr = options_.out / (name + ".exr");
  io::writePng(png, shown.image, shown.encoding, panels_.exposure);
  io::writeExr(exr, frame);
  std::printf("wrote %s and %s (frame %llu)\n", png.c_str(), exr.c_str(), (unsigned long long)rendered_);
}

void Session::writeStages(const std::string& name) {
  loop_.finish();
  for (gpu::CapturedStage& c : loop_.takeCaptures()) captures_.push_back(std::move(c));
  const fs::path dir = options_.out / (name + "-stages");
  const std::vector<fs::path> files = gpuio::writeStageDumps(dir, captures_, panels_.exposure);
  captures_.clear();
  std::printf("wrote %zu stage images to %s\n", files.size(), dir.c_str());
}

void Session::updateTitle() {
  double frameMs = 0.0;
  panels_.timings = loop_.timings().summary();
  for (const gpu::PassTiming& t : panels_.timings) frameMs += t.lastMs;
  panels_.frameMs = frameMs;
  panels_.memoryBytes = context_.deviceLocalBytesInUse();
  if (rendered_ % 15 != 0) return;
  char title[512];
  std::snprintf(title, sizeof title, "bounce view - %s - %s - %ux%u - %.2f ms", scene_.name.c_str(),
                context_.deviceInfo().name.c_str(), options_.renderer.width, options_.renderer.height, frameMs);
  window_.setTitle(title);
}

int Session::run() {
  bool scriptRunning = options_.scripted;
  while (!quit_ && !window_.closeRequested()) {
    glfwPollEvents();
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    FlyInput input;
    bool lastPresent = false;  // the script ended: show (and capture) what there is, then close
    if (scriptRunning) {
      scriptRunning = stepScript(input);
      lastPresent = !scriptRunning;
    } else {
      input = interactiveInput();
    }
    PanelActions actions;
    drawPanels(panels_, actions);
    ImGui::Render();
    if (quit_) break;
    applyPanelActions(actions);
    const bool capture = !pendingStages_.empty();
    const bool render = !lastPresent && (!panels_.paused || stepOnce_ || options_.scripted);
    stepOnce_ = false;
    if (render) renderFrame(input, capture);
    if (capture && render) {
      writeStages(pendingStages_);
      pendingStages_.clear();
    }
    window_.present(display_, ImGui::GetDrawData());
    updateTitle();
    if (lastPresent) break;
  }
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
