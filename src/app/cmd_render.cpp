// bounce render: renders a built-in or glTF scene along a camera path: the
// G-buffer and direct light of every frame. Writes the final frame (PNG for
// people, EXR for comparisons), every frame when asked (--hdr, numbered PNGs
// and an MP4 when ffmpeg is installed), any AOVs, every pass's output
// (--dump-stages), and prints the per-pass GPU timings.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "app/commands.h"
#include "app/progress.h"
#include "gpu/frame_loop.h"
#include "gpu/stage_dump.h"
#include "gpu/transfer.h"
#include "io/image_io.h"
#include "render/frame_renderer.h"
#include "scene/builtin_scenes.h"
#include "scene/camera_path.h"

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

const std::set<std::string>& knownAovs() {
  static const std::set<std::string> names = {"viewZ",  "normal", "geometric-normal", "albedo",    "emissive",
                                              "motion", "ids",    "direct",           "roughness", "metallic"};
  return names;
}

// Lays display images out left to right, top to bottom, `columns` to a row,
// each shrunk by `shrink` (box filter), on black.
io::ImageF contactSheet(const std::vector<io::ImageF>& cells, int columns, int shrink) {
  const int cellWidth = cells.front().width / shrink, cellHeight = cells.front().height / shrink;
  const int rows = (int(cells.size()) + columns - 1) / columns;
  io::ImageF sheet(cellWidth * columns, cellHeight * rows, {"R", "G", "B"});
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const int ox = int(i) % columns * cellWidth, oy = int(i) / columns * cellHeight;
    for (int y = 0; y < cellHeight; ++y)
      for (int x = 0; x < cellWidth; ++x)
        for (int c = 0; c < 3; ++c) {
          float sum = 0.0f;
          for (int sy = 0; sy < shrink; ++sy)
            for (int sx = 0; sx < shrink; ++sx) sum += cells[i].at(x * shrink + sx, y * shrink + sy, c);
          sheet.at(ox + x, oy + y, c) = sum / float(shrink * shrink);
        }
  }
  return sheet;
}

// Writes each asked-for AOV of the last frame as EXR + false-colour PNG, and
// all of them side by side on OUT/aov/sheet.png (in the order printed).
void writeAovs(gpu::Context& context, render::FrameRenderer& renderer, const std::vector<std::string>& wanted,
               const fs::path& dir, float exposure) {
  fs::create_directories(dir);
  const bool all = std::find(wanted.begin(), wanted.end(), "all") != wanted.end();
  const auto wants = [&](const std::string& name) {
    return all || std::find(wanted.begin(), wanted.end(), name) != wanted.end();
  };
  std::vector<io::ImageF> cells;
  std::string order;
  const auto write = [&](const std::string& name, const io::ImageF& pixels, gpu::Visualize how) {
    io::writeExr(dir / (name + ".exr"), pixels);
    const gpu::VisualizedImage view = gpu::visualize(pixels, how);
    io::writePng(dir / (name + ".png"), view.image, view.encoding, exposure);
    cells.push_back(io::toDisplay(view.image, view.encoding, exposure));
    order += (order.empty() ? "" : ", ") + name;
  };
  for (const render::Aov& aov : renderer.aovs()) {
    // roughness and metallic live in the alpha channels of normal and albedo.
    const bool roughness = aov.name == "normal" && wants("roughness");
    const bool metallic = aov.name == "albedo" && wants("metallic");
    if (!wants(aov.name) && !roughness && !metallic) continue;
    const io::ImageF image = gpu::readbackImage(context, *aov.image);
    if (wants(aov.name)) write(aov.name, image, aov.image->desc().visualize);
    if (roughness || metallic) {
      io::ImageF channel(image.width, image.height, {roughness ? "roughness" : "metallic"});
      for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) channel.at(x, y, 0) = image.at(x, y, 3);
      write(roughness ? "roughness" : "metallic", channel, gpu::Visualize::Raw);
    }
  }
  const int shrink = cells.front().width > 480 ? 2 : 1;
  io::writePng(dir / "sheet.png", contactSheet(cells, 4, shrink), io::PngEncoding::Linear);
  std::printf("wrote AOVs to %s; sheet.png shows, left to right, top to bottom: %s\n", dir.c_str(), order.c_str());
}

// Frames of an animation kept for the APNG: up to this many pixels over all
// frames (about 0.4 GB as floats); longer or larger runs keep only the
// numbered PNGs (and the MP4 when ffmpeg exists).
constexpr double kMaxAnimationPixels = 32.0e6;

// Numbered PNGs into an MP4 when ffmpeg is installed; otherwise they stay.
void encodeVideo(const fs::path& framesDir, const fs::path& video, float fps) {
  if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0) return;
  const std::string command = "ffmpeg -loglevel error -y -framerate " + std::to_string(fps) + " -i '" +
                              (framesDir / "frame%04d.png").string() + "' -c:v libx264 -pix_fmt yuv420p -crf 18 '" +
                              video.string() + "'";
  if (std::system(command.c_str()) == 0)
    std::printf("wrote %s\n", video.c_str());
  else
    std::printf("ffmpeg failed; frames stay as numbered PNGs in %s\n", framesDir.c_str());
}

}  // namespace

CLI::App* addRenderCommand(CLI::App& app, RenderOptions& options) {
  CLI::App* command = app.add_subcommand(
      "render", "Render a scene (built-in name or .gltf/.glb) along a camera path: G-buffer and direct light");
  addGpuOptions(*command, options.gpu);
  std::string names;
  for (const std::string& n : scene::builtinSceneNames()) names += (names.empty() ? "" : ", ") + n;
  command->add_option(
      "scene", options.scene,
      "Built-in scene (" + names + "; default " + scene::defaultBuiltinScene() + ") or a .gltf/.glb file");
  command->add_option("--camera", options.camera,
                      "Camera path: orbit, dolly, fly, static, gltf, or a JSON keyframe file (default: the scene's "
                      "first glTF camera, else its suggested view)");
  command->add_option("--width", options.width, "Image width in pixels")->check(CLI::Range(1u, 16384u));
  command->add_option("--height", options.height, "Image height in pixels")->check(CLI::Range(1u, 16384u));
  command->add_option("--frames", options.frames, "Frames to render along the camera path")
      ->check(CLI::Range(1u, 1000000u));
  command->add_option("--fps", options.fps, "Frames per second of scene time (animation and camera)")
      ->check(CLI::Range(0.001f, 10000.0f));
  command->add_option("--out", options.out, "Output directory (created if missing)");
  command->add_option("--exposure", options.exposure, "Exposure multiplier before tonemapping for PNGs")
      ->check(CLI::PositiveNumber);
  command->add_option("--env", options.env, "Equirectangular environment map (.exr/.hdr); default: procedural sky");
  command->add_option("--env-intensity", options.envIntensity, "Multiplier of the environment")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--env-rotation", options.envRotation, "Rotation of the environment map about +Y, degrees");
  command->add_option("--sun-elevation", options.sunElevation, "Sun elevation above the horizon, degrees")
      ->check(CLI::Range(-90.0f, 90.0f));
  command->add_option("--sun-azimuth", options.sunAzimuth, "Sun azimuth from +Z towards +X, degrees");
  command->add_flag("--no-sun", options.noSun,
                    "No sunlight (e.g. when the --env map already shows its sun, which would then count twice)");
  command
      ->add_option("--aov", options.aovs,
                   "Also write these images of the last frame as EXR + false-colour PNG to OUT/aov/: viewZ, "
                   "normal, geometric-normal, albedo, roughness, metallic, emissive, motion, ids, direct, all")
      ->delimiter(',');
  command->add_flag("--hdr", options.hdr, "Write every final frame as linear EXR to OUT/frames/");
  command->add_flag("--jitter", options.jitter, "Sub-pixel camera jitter (Halton 2,3) per frame");
  command->add_flag("--dump-stages", options.dumpStages,
                    "Write every pass's output (EXR + PNG) for the dump frames to OUT/stages/");
  command->add_option("--dump-frames", options.dumpFrames, "Frames to dump with --dump-stages (default: the last)")
      ->delimiter(',');
  return command;
}

int runRender(const RenderOptions& options) {
  for (std::uint32_t f : options.dumpFrames)
    if (f >= options.frames)
      throw std::runtime_error("--dump-frames " + std::to_string(f) + " is past the last frame (" +
                               std::to_string(options.frames - 1) + ")");
  for (const std::string& aov : options.aovs)
    if (aov != "all" && !knownAovs().count(aov))
      throw std::runtime_error("--aov: unknown image '" + aov +
                               "' (known: viewZ, normal, geometric-normal, albedo, roughness, metallic, emissive, "
                               "motion, ids, direct, all)");

  const scene::Scene scene = loadSceneArgument(options.scene);
  const std::unique_ptr<scene::CameraPath> path =
      options.camera.empty() ? scene::defaultCameraPath(scene) : scene::makeCameraPath(options.camera, scene);
  const std::vector<scene::CameraFrame> cameraFrames = scene::sampleCameraPath(*path, int(options.frames), options.fps);

  render::FrameRendererOptions rendererOptions;
  rendererOptions.width = options.width;
  rendererOptions.height = options.height;
  rendererOptions.jitter = options.jitter;
  render::EnvironmentDesc& environment = rendererOptions.environment;
  environment.map = options.env;
  environment.intensity = options.envIntensity;
  environment.rotationDegrees = options.envRotation;
  environment.sun = scene.sun;
  environment.hasSun = scene.hasSun;
  if (options.sunElevation) {
    environment.sun.elevationDegrees = *options.sunElevation;
    environment.hasSun = true;
  }
  if (options.sunAzimuth) environment.sun.azimuthDegrees = *options.sunAzimuth;
  if (options.noSun) {
    if (options.sunElevation || options.sunAzimuth)
      throw std::runtime_error("--no-sun contradicts --sun-elevation/--sun-azimuth");
    environment.hasSun = false;
  }

  const fs::path outDir = options.out;
  fs::create_directories(outDir);
  std::unique_ptr<gpu::Context> context = openContext(options.gpu);
  std::printf("device: %s (%s)\n", context->deviceInfo().name.c_str(), context->deviceInfo().type.c_str());
  render::FrameRenderer renderer(*context, scene, rendererOptions);
  std::printf("scene: %s, %zu triangles, %zu textures\n", scene.name.c_str(), renderer.triangleCount(),
              scene.textures.size());
  gpu::FrameLoop loop(*context, render::FrameRenderer::kFramesInFlight);

  auto isDumpFrame = [&](std::uint32_t frame) {
    if (!options.dumpStages) return false;
    if (options.dumpFrames.empty()) return frame + 1 == options.frames;
    return std::find(options.dumpFrames.begin(), options.dumpFrames.end(), frame) != options.dumpFrames.end();
  };
  const bool everyFrame = options.frames > 1 || options.hdr;
  const bool animate =
      options.frames > 1 && double(options.width) * double(options.height) * options.frames <= kMaxAnimationPixels;
  std::vector<io::ImageF> animation;
  const fs::path framesDir = outDir / "frames";
  if (everyFrame) fs::create_directories(framesDir);
  std::vector<gpu::CapturedStage> captures;
  ProgressBar progress("render", options.frames);
  for (std::uint32_t frame = 0; frame < options.frames; ++frame) {
    gpu::Recorder& recorder = loop.beginFrame(isDumpFrame(frame));
    const scene::CameraFrame& camera = cameraFrames[frame];
    renderer.record(recorder, loop.frameIndex(), {camera.pose, float(frame) / options.fps, camera.cut});
    loop.endFrame();
    for (gpu::CapturedStage& c : loop.takeCaptures()) captures.push_back(std::move(c));
    if (everyFrame) {
      // Each frame's image is read back before the next reuses it.
      loop.finish();
      const io::ImageF image = gpu::readbackImage(*context, renderer.direct());
      char name[32];
      std::snprintf(name, sizeof name, "frame%04u", frame);
      if (options.frames > 1) {
        const gpu::VisualizedImage view = gpu::visualize(image, gpu::Visualize::Radiance);
        io::writePng(framesDir / (std::string(name) + ".png"), view.image, view.encoding, options.exposure);
        if (animate) animation.push_back(io::toDisplay(view.image, view.encoding, options.exposure));
      }
      if (options.hdr) io::writeExr(framesDir / (std::string(name) + ".exr"), image);
    }
    progress.update(frame + 1);
  }
  loop.finish();
  progress.finish();
  for (gpu::CapturedStage& c : loop.takeCaptures()) captures.push_back(std::move(c));

  const io::ImageF final = gpu::readbackImage(*context, renderer.direct());
  const gpu::VisualizedImage view = gpu::visualize(final, gpu::Visualize::Radiance);
  io::writePng(outDir / "render.png", view.image, view.encoding, options.exposure);
  io::writeExr(outDir / "render.exr", final);
  std::printf("wrote %s and %s (%ux%u, %u frame%s)\n", (outDir / "render.png").c_str(), (outDir / "render.exr").c_str(),
              options.width, options.height, options.frames, options.frames == 1 ? "" : "s");
  if (options.frames > 1) {
    std::printf("wrote %u frames as numbered PNGs to %s\n", options.frames, framesDir.c_str());
    if (animate) {
      io::writeApng(outDir / "animation.png", animation, options.fps);
      std::printf("wrote %s (animated PNG)\n", (outDir / "animation.png").c_str());
    } else {
      std::printf("no animated PNG: %u frames of %ux%u is more than it keeps in memory\n", options.frames,
                  options.width, options.height);
    }
    encodeVideo(framesDir, outDir / "render.mp4", options.fps);
  }
  if (!options.aovs.empty()) {
    writeAovs(*context, renderer, options.aovs, outDir / "aov", options.exposure);
  }
  if (!captures.empty()) {
    auto files = gpu::writeStageDumps(outDir / "stages", captures, options.exposure);
    std::printf("wrote %zu stage images to %s\n", files.size(), (outDir / "stages").c_str());
  }
  std::printf("\nGPU time per pass (%s):\n%s", context->deviceInfo().name.c_str(), loop.timings().table().c_str());
  return validationExitCode(*context);
}

}  // namespace bounce::app
