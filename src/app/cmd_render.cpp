// bounce render: renders the scene along a camera path, writes the final frame
// (PNG for people, EXR for comparisons), optionally every pass's output, and
// prints the per-pass GPU timings.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/commands.h"
#include "app/progress.h"
#include "gpu/frame_loop.h"
#include "gpu/stage_dump.h"
#include "gpu/transfer.h"
#include "io/image_io.h"
#include "render/analytic_scene.h"

namespace bounce::app {
namespace {

// The quick start's camera path: a slow orbit around the spheres, 0.5 degree
// per frame, so a multi-frame render shows camera motion.
render::Camera orbitCamera(std::uint32_t frame) {
  render::Camera camera;
  const float angle = glm::radians(0.5f * float(frame));
  const glm::vec3 offset = camera.position - camera.target;
  camera.position = camera.target + glm::vec3(offset.x * std::cos(angle) + offset.z * std::sin(angle), offset.y,
                                              -offset.x * std::sin(angle) + offset.z * std::cos(angle));
  return camera;
}

}  // namespace

CLI::App* addRenderCommand(CLI::App& app, RenderOptions& options) {
  CLI::App* command = app.add_subcommand("render", "Render the built-in analytic scene (ground, spheres, sun)");
  addGpuOptions(*command, options.gpu);
  command->add_option("--width", options.width, "Image width in pixels")->check(CLI::Range(1u, 16384u));
  command->add_option("--height", options.height, "Image height in pixels")->check(CLI::Range(1u, 16384u));
  command->add_option("--frames", options.frames, "Frames to render along the camera path")
      ->check(CLI::Range(1u, 1000000u));
  command->add_option("--out", options.out, "Output directory (created if missing)");
  command->add_option("--exposure", options.exposure, "Exposure multiplier before tonemapping for PNGs")
      ->check(CLI::PositiveNumber);
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
  const std::filesystem::path outDir = options.out;
  std::filesystem::create_directories(outDir);

  std::unique_ptr<gpu::Context> context = openContext(options.gpu);
  std::printf("device: %s (%s)\n", context->deviceInfo().name.c_str(), context->deviceInfo().type.c_str());
  render::AnalyticRenderer renderer(*context, options.width, options.height, render::AnalyticScene::standard());
  gpu::FrameLoop loop(*context);

  auto isDumpFrame = [&](std::uint32_t frame) {
    if (!options.dumpStages) return false;
    if (options.dumpFrames.empty()) return frame + 1 == options.frames;
    return std::find(options.dumpFrames.begin(), options.dumpFrames.end(), frame) != options.dumpFrames.end();
  };
  std::vector<gpu::CapturedStage> captures;
  ProgressBar progress("render", options.frames);
  for (std::uint32_t frame = 0; frame < options.frames; ++frame) {
    gpu::Recorder& recorder = loop.beginFrame(isDumpFrame(frame));
    renderer.record(recorder, orbitCamera(frame));
    loop.endFrame();
    for (gpu::CapturedStage& c : loop.takeCaptures()) captures.push_back(std::move(c));
    progress.update(frame + 1);
  }
  loop.finish();
  progress.finish();
  for (gpu::CapturedStage& c : loop.takeCaptures()) captures.push_back(std::move(c));

  io::ImageF frame = gpu::readbackImage(*context, renderer.directLight());
  gpu::VisualizedImage view = gpu::visualize(frame, gpu::Visualize::Radiance);
  io::writePng(outDir / "render.png", view.image, view.encoding, options.exposure);
  io::writeExr(outDir / "render.exr", view.image);
  std::printf("wrote %s and %s (%ux%u, %u frame%s)\n", (outDir / "render.png").c_str(), (outDir / "render.exr").c_str(),
              options.width, options.height, options.frames, options.frames == 1 ? "" : "s");
  if (!captures.empty()) {
    auto files = gpu::writeStageDumps(outDir / "stages", captures, options.exposure);
    std::printf("wrote %zu stage images to %s\n", files.size(), (outDir / "stages").c_str());
  }
  std::printf("\nGPU time per pass (%s):\n%s", context->deviceInfo().name.c_str(), loop.timings().table().c_str());
  return validationExitCode(*context);
}

}  // namespace bounce::app
