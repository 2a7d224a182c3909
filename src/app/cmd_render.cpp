// bounce render: renders a built-in or glTF scene along a camera path: the
// G-buffer and direct light of every frame. Writes the final frame (PNG for
// people, EXR for comparisons), every frame when asked (--hdr, numbered PNGs
// and an MP4 when ffmpeg is installed), any AOVs, every pass's output
// (--dump-stages), and prints the per-pass GPU timings.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "app/commands.h"
#include "app/images.h"
#include "app/option_checks.h"
#include "app/output_files.h"
#include "app/process.h"
#include "app/progress.h"
#include "gpu/frame_loop.h"
#include "gpu/transfer.h"
#include "gpuio/gpu_images.h"
#include "gpuio/stage_dump.h"
#include "io/image_io.h"
#include "render/frame_memory.h"
#include "render/frame_pipeline.h"
#include "render/frame_renderer.h"
#include "render/gi_bridge.h"
#include "scene/builtin_scenes.h"
#include "scene/camera_path.h"

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

// Frames of an animation kept for the APNG: up to this many pixels over all
// frames (about 0.4 GB as floats); longer or larger runs keep only the
// numbered PNGs (and the MP4 when ffmpeg exists).
constexpr double kMaxAnimationPixels = 32.0e6;

// Numbered PNGs into an MP4 when ffmpeg is installed; otherwise they stay.
// ffmpeg gets its arguments as a list, never through a shell: an output
// folder named "x'; rm -rf ~" is a file name, not a command.
void encodeVideo(const fs::path& framesDir, const fs::path& video, float fps) {
  // ffmpeg opens the name it is given and follows a link there, so it
  // writes a new file of this process's own making (under a name no one can
  // predict), which is then renamed into place as every output is.
  const io::TemporaryFile temporary = io::createTemporaryBeside(video);
  if (temporary.fd < 0) {
    std::printf("cannot write %s (%s); frames stay as numbered PNGs in %s\n", video.c_str(),
                std::strerror(temporary.error), framesDir.c_str());
    return;
  }
  ::close(temporary.fd);
  const std::optional<int> status =
      runProgram({"ffmpeg", "-nostdin", "-loglevel", "error", "-y", "-framerate", std::to_string(fps), "-i",
                  (framesDir / "frame%04d.png").string(), "-c:v", "libx264", "-pix_fmt", "yuv420p", "-crf", "18", "-f",
                  "mp4", temporary.path.string()});
  if (status && *status == 0) {
    io::moveIntoPlace(temporary.path, video);
    std::printf("wrote %s\n", video.c_str());
    return;
  }
  ::unlink(temporary.path.c_str());
  if (status) std::printf("ffmpeg failed; frames stay as numbered PNGs in %s\n", framesDir.c_str());
  // (no status: no ffmpeg on this machine)
}

// On a CPU device what the command line left unset (the size, the GI
// warm-up) is chosen smaller, kCpuQuickStart's, and said on the console.
// Whether anything changed.
bool applyCpuQuickStart(const gpu::DeviceInfo& device, const RenderOptions& options, bool gi, SceneOptions& shot,
                        GiOptions& giOptions) {
  const bool size = !options.sizeGiven, warmup = gi && !options.warmupGiven;
  if (device.type != "CPU" || (!size && !warmup)) return false;
  std::string chosen, instead;
  const auto add = [](std::string& list, const std::string& item) { list += (list.empty() ? "" : " and ") + item; };
  if (size) {
    add(instead, std::to_string(shot.width) + "x" + std::to_string(shot.height));
    shot.width = kCpuQuickStart.width;
    shot.height = kCpuQuickStart.height;
    add(chosen, std::to_string(shot.width) + "x" + std::to_string(shot.height));
  }
  if (warmup) {
    add(instead, std::to_string(giOptions.warmup));
    giOptions.warmup = kCpuQuickStart.warmup;
    add(chosen, std::to_string(giOptions.warmup) + " GI warm-up frames");
  }
  std::printf(
      "on a CPU device: %s instead of %s, to finish within a minute (--width, --height and --gi-warmup "
      "choose)\n",
      chosen.c_str(), instead.c_str());
  return true;
}

}  // namespace

CLI::App* addRenderCommand(CLI::App& app, RenderOptions& options) {
  CLI::App* command = app.add_subcommand(
      "render",
      "Render a scene (built-in name or .gltf/.glb) along a camera path: G-buffer, direct light and the GI library");
  addGpuOptions(*command, options.gpu);
  addSceneOptions(*command, options.view);
  addGiOptions(*command, options.gi);
  command->add_option("--frames", options.frames, "Frames to render along the camera path")
      ->check(CLI::Range(1u, kMaxFrames));
  command->add_option("--out", options.out, "Output directory (created if missing)");
  command->add_option("--exposure", options.exposure, "Exposure multiplier before tonemapping for PNGs")
      ->check(finitePositive());
  command
      ->add_option("--aov", options.aovs,
                   "Also write these images of the last frame as EXR + false-colour PNG to OUT/aov/: viewZ, "
                   "normal, geometric-normal, albedo, roughness, metallic, emissive, motion, ids, direct, all")
      ->delimiter(',');
  command->add_flag("--hdr", options.hdr,
                    "Write every final frame as linear EXR to OUT/frames/ (with GI, its indirect diffuse too)");
  command->add_flag("--jitter", options.jitter, "Sub-pixel camera jitter (Halton 2,3) per frame");
  command->add_flag("--dump-stages", options.dumpStages,
                    "Write every pass's output (EXR + PNG) for the dump frames to OUT/stages/");
  command->add_option("--dump-frames", options.dumpFrames, "Frames to dump with --dump-stages (default: the last)")
      ->delimiter(',');
  command
      ->add_option("--cut-frames", options.cutFrames,
                   "Flag these frames as camera cuts (no history is reused), besides the camera path's own")
      ->delimiter(',');
  addOverwriteFlag(*command, options.overwrite);
  return command;
}

int runRender(const RenderOptions& options) {
  for (const auto& [flag, frames] :
       {std::pair{"--dump-frames", &options.dumpFrames}, {"--cut-frames", &options.cutFrames}})
    for (std::uint32_t f : *frames)
      if (f >= options.frames)
        throw UsageError(std::string(flag) + " " + std::to_string(f) + " is past the last frame (" +
                         std::to_string(options.frames - 1) + ")");
  for (const std::string& aov : options.aovs)
    if (aov != "all" && !knownAovs().count(aov))
      throw UsageError("--aov: unknown image '" + aov + "' (known: " + knownAovList() + ", all)");

  const fs::path outDir = options.out;
  // Before anything slow: a read-only or mistyped output folder fails now.
  checkWritableDirectory(outDir, "--out");
  warnIgnoredGiOptions(options.gi);
  const bool gi = giEnabled(options.gi);
  const gi::Settings settings = gi ? giSettings(options.gi) : gi::Settings{};

  SceneOptions shot = options.view;
  GiOptions giOptions = options.gi;
  const scene::Scene scene = loadScene(shot);
  const std::unique_ptr<scene::CameraPath> path = cameraPathOf(scene, shot);
  const std::vector<scene::CameraFrame> cameraFrames = checkedCameraFrames(*path, 0, options.frames, shot);
  render::FrameRendererOptions rendererOptions = frameRendererOptions(scene, shot);
  rendererOptions.jitter = options.jitter;

  const bool everyFrame = options.frames > 1 || options.hdr;
  // Every file this render writes, known before it starts: none may replace
  // an input, or a file in OUT that no Bounce run wrote. What an earlier
  // render left here and this one does not write again is removed, so the
  // folder never mixes two renders.
  std::vector<fs::path> outputs = {"render.png", "render.exr"};
  if (options.frames > 1) outputs.insert(outputs.end(), {"animation.png", "render.mp4"});
  for (std::uint32_t frame = 0; everyFrame && frame < options.frames; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "frames/frame%04u", frame);
    if (options.frames > 1) outputs.push_back(std::string(name) + ".png");
    if (options.hdr) outputs.push_back(std::string(name) + ".exr");
    if (options.hdr && gi)
      outputs.insert(outputs.end(),
                     {std::string(name) + ".indirect-diffuse.exr", std::string(name) + ".indirect-specular.exr"});
  }
  std::vector<fs::path> filledFolders;
  if (options.dumpStages) filledFolders.push_back("stages");
  if (!options.aovs.empty()) filledFolders.push_back("aov");
  OutputFolder folder(outDir, "--out", options.overwrite);
  const std::size_t removed = folder.prepare(outputs, filledFolders, inputFiles(scene, shot, &giOptions));
  if (removed > 0)
    std::printf("removed %zu file%s an earlier render wrote in %s\n", removed, removed == 1 ? "" : "s", outDir.c_str());

  std::unique_ptr<gpu::Context> context = openContext(options.gpu);
  std::printf("device: %s (%s)\n", context->deviceInfo().name.c_str(), context->deviceInfo().type.c_str());
  // Everything checked before the device opened holds for a quick-start
  // size too: the camera's checks and the output files do not depend on
  // it, and the aspect stays 16:9.
  if (applyCpuQuickStart(context->deviceInfo(), options, gi, shot, giOptions)) {
    rendererOptions.width = shot.width;
    rendererOptions.height = shot.height;
  }
  const bool animate =
      options.frames > 1 && double(shot.width) * double(shot.height) * options.frames <= kMaxAnimationPixels;
  render::requireFrameMemory(
      *context, shot.width, shot.height,
      gi ? std::optional(std::pair(giContextDesc(shot.width, shot.height, giOptions), settings)) : std::nullopt, false);
  // The renderer and the GI library on this device, through its public interface (render/frame_pipeline.h).
  render::FramePipeline pipeline(
      *context, scene,
      {.renderer = rendererOptions,
       .gi = gi ? std::optional(std::pair(giContextDesc(shot.width, shot.height, giOptions), settings)) : std::nullopt,
       .giFrame = {.jitter = options.jitter}});
  render::FrameRenderer& renderer = pipeline.renderer();
  render::GiBridge* giBridge = pipeline.gi();
  gpu::FrameLoop& loop = pipeline.loop();
  std::printf("scene: %s, %zu triangles, %zu textures\n", scene.name.c_str(), renderer.triangleCount(),
              scene.textures.size());

  auto isDumpFrame = [&](std::uint32_t frame) {
    if (!options.dumpStages) return false;
    if (options.dumpFrames.empty()) return frame + 1 == options.frames;
    return std::find(options.dumpFrames.begin(), options.dumpFrames.end(), frame) != options.dumpFrames.end();
  };
  std::vector<io::ImageF> animation;
  const fs::path framesDir = outDir / "frames";
  if (everyFrame) fs::create_directories(framesDir);
  std::vector<gpu::CapturedStage> captures;
  checkDeviceMemoryFits(*context, shot.width, shot.height);
  const bool warmUp = gi && giOptions.warmup > 0;
  if (warmUp) {
    // Light needs frames to bounce (each frame gathers the last one) and the
    // histories to fill: render them at the first camera, unseen.
    ProgressBar warming("gi warm-up", giOptions.warmup);
    for (std::uint32_t i = 0; i < giOptions.warmup; ++i) {
      pipeline.frame({cameraFrames[0].pose, 0.0f, i == 0});
      warming.update(i + 1);
    }
    warming.finish();
  }
  // Dumps are numbered by output frame, whatever warm-up came before.
  const std::uint64_t firstOutputIndex = loop.frameIndex() + (warmUp ? 1 : 0);
  const auto takeCaptures = [&] {
    for (gpu::CapturedStage& c : loop.takeCaptures()) {
      c.frame -= firstOutputIndex;
      captures.push_back(std::move(c));
    }
  };
  ProgressBar progress("render", options.frames);
  for (std::uint32_t frame = 0; frame < options.frames; ++frame) {
    const bool dump = isDumpFrame(frame);
    const scene::CameraFrame& camera = cameraFrames[frame];
    // The path's first frame is a cut, unless the warm-up already stood there.
    const bool asked = std::find(options.cutFrames.begin(), options.cutFrames.end(), frame) != options.cutFrames.end();
    const bool cut = asked || (camera.cut && !(frame == 0 && warmUp));
    pipeline.frame({camera.pose, float(frame) / shot.fps, cut}, {.captureStages = dump});
    takeCaptures();
    if (everyFrame) {
      // Each frame's image is read back before the next reuses it.
      loop.finish();
      const io::ImageF image = gpuio::readbackImage(*context, pipeline.frameImage());
      char name[32];
      std::snprintf(name, sizeof name, "frame%04u", frame);
      if (options.frames > 1) {
        const gpuio::VisualizedImage view = gpuio::visualize(image, gpu::Visualize::Radiance);
        io::writePng(framesDir / (std::string(name) + ".png"), view.image, view.encoding, options.exposure);
        if (animate) animation.push_back(io::toDisplay(view.image, view.encoding, options.exposure));
      }
      if (options.hdr) {
        io::writeExr(framesDir / (std::string(name) + ".exr"), image);
        if (gi) {
          io::writeExr(framesDir / (std::string(name) + ".indirect-diffuse.exr"),
                       gpuio::readbackImage(*context, giBridge->indirect(gi::kDiffuseSignal)));
          io::writeExr(framesDir / (std::string(name) + ".indirect-specular.exr"),
                       gpuio::readbackImage(*context, giBridge->indirect(gi::kSpecularSignal)));
        }
      }
    }
    progress.update(frame + 1);
  }
  loop.finish();
  progress.finish();
  takeCaptures();

  const io::ImageF final = gpuio::readbackImage(*context, pipeline.frameImage());
  const gpuio::VisualizedImage view = gpuio::visualize(final, gpu::Visualize::Radiance);
  io::writePng(outDir / "render.png", view.image, view.encoding, options.exposure);
  io::writeExr(outDir / "render.exr", final);
  std::printf("wrote %s and %s (%ux%u, %u frame%s)\n", (outDir / "render.png").c_str(), (outDir / "render.exr").c_str(),
              shot.width, shot.height, options.frames, options.frames == 1 ? "" : "s");
  if (options.frames > 1) {
    std::printf("wrote %u frames as numbered PNGs to %s\n", options.frames, framesDir.c_str());
    if (animate) {
      io::writeApng(outDir / "animation.png", animation, shot.fps);
      std::printf("wrote %s (animated PNG)\n", (outDir / "animation.png").c_str());
    } else {
      std::printf("no animated PNG: %u frames of %ux%u is more than it keeps in memory\n", options.frames, shot.width,
                  shot.height);
    }
    encodeVideo(framesDir, outDir / "render.mp4", shot.fps);
  }
  if (!options.aovs.empty()) {
    std::vector<render::Aov> giAovs;
    if (gi) {
      giAovs.push_back({"indirect-diffuse", &giBridge->indirect(gi::kDiffuseSignal)});
      giAovs.push_back({"indirect-specular", &giBridge->indirect(gi::kSpecularSignal)});
    }
    folder.wrote(writeAovs(*context, renderer, options.aovs, outDir / "aov", options.exposure, giAovs));
  }
  if (!captures.empty()) {
    auto files = gpuio::writeStageDumps(outDir / "stages", captures, options.exposure);
    folder.wrote(files);
    std::printf("wrote %zu stage images to %s\n", files.size(), (outDir / "stages").c_str());
    // The longest diffuse history: the denoiser's when it runs, else the filter's.
    float historyCap = 1.0f;
    if (giBridge) {
      const gi::Settings& settings = giBridge->library().settings();
      historyCap = float(settings.denoise.enabled ? settings.denoise.maxAccumulatedFrames
                                                  : settings.diffuse.temporalFilterFrames);
    }
    const std::vector<fs::path> sheets =
        writeValidationSheets(outDir / "stages", captures, options.exposure, historyCap);
    folder.wrote(sheets);
    for (const fs::path& sheet : sheets)
      std::printf("wrote %s (validation: viewZ, normals, motion, history length, reprojection failures in red)\n",
                  sheet.c_str());
  }
  std::printf("\nGPU time per pass (%s):\n%s", context->deviceInfo().name.c_str(), loop.timings().table().c_str());
  return validationExitCode(*context);
}

}  // namespace bounce::app
