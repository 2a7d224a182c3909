// bounce denoise: the GI library's denoiser on signals it did not make. A
// camera path is path-traced at a few samples per pixel a frame (1 by
// default, a new seed each frame); each frame's noisy indirect diffuse and
// specular (demodulated, first-hit distance in alpha) go to the library as
// an engine's own signals (FrameInputs::noisy), and
// the denoised result is measured against a converged reference of the
// last frame's view. Nothing of the library's ReSTIR branches runs: this is
// the test that the denoiser is a general one (issue 14: the 1-spp
// sequence of cornell at 1/10 of its input's relMSE after 32 frames), and
// the worked example of an engine handing the library its own signals.
// --checkerboard (or --gi.denoise.checkerboard on) hands them over as an
// engine in the denoiser's checkerboard mode would: each frame, of every
// pixel's samples, those of each signal's checkerboard parity, packed to
// half width; the noisy images and their relMSE stay every pixel's.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/checkerboard_pack.h"
#include "app/commands.h"
#include "app/images.h"
#include "app/option_checks.h"
#include "app/output_files.h"
#include "app/progress.h"
#include "app/reference_sampling.h"
#include "gpu/frame_loop.h"
#include "gpuio/gpu_images.h"
#include "gpuio/stage_dump.h"
#include "io/image_io.h"
#include "metrics/image_metrics.h"
#include "render/frame_memory.h"
#include "render/frame_pipeline.h"
#include "render/frame_renderer.h"
#include "render/gi_bridge.h"
#include "render/reference_renderer.h"
#include "scene/camera_path.h"

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

// The three images measured, as the library and the path tracer split the
// frame: the two signals the denoiser takes, and the frame they make.
enum Part { kDiffuse, kSpecular, kFrame, kPartCount };
constexpr const char* kPartNames[kPartCount] = {"diffuse", "specular", "frame"};
constexpr const char* kPartLabels[kPartCount] = {"indirect diffuse", "indirect specular", "frame"};
// File names: OUT/noisy.indirect-diffuse.exr, OUT/denoised.exr (the frame), ...
constexpr const char* kPartSuffixes[kPartCount] = {".indirect-diffuse", ".indirect-specular", ""};
constexpr const char* kVersions[] = {"noisy", "denoised", "reference"};

using PartImages = std::array<io::ImageF, kPartCount>;

struct Errors {
  double noisy = 0.0, denoised = 0.0;  // relMSE against the reference

  // denoised / noisy, undefined (empty) when the noisy relMSE is 0: nothing
  // to reduce (a black scene: 0 / 0 printed -nan in the table).
  std::optional<double> ratio() const {
    if (!(noisy > 0.0)) return std::nullopt;
    return denoised / noisy;
  }
};

double relMse(const io::ImageF& reference, const io::ImageF& test) {
  return metrics::valueErrors(reference.pixels, test.pixels).relMse;
}

io::ImageF rgbOf(gpu::Context& context, gpu::Image& image) {
  return io::firstChannels(gpuio::readbackImage(context, image), 3);
}

// Whether two poses are the same view, bit for bit (then so are their G-buffers).
bool sameView(const scene::CameraPose& a, const scene::CameraPose& b) {
  return a.position == b.position && a.target == b.target && a.up == b.up && a.fovYDegrees == b.fovYDegrees;
}

nlohmann::json errorsJson(const std::array<Errors, kPartCount>& errors) {
  nlohmann::json parts;
  for (int part = 0; part < kPartCount; ++part)
    parts[kPartNames[part]] = {
        {"noisy_relmse", errors[part].noisy},
        {"denoised_relmse", errors[part].denoised},
        {"ratio", errors[part].ratio() ? nlohmann::json(*errors[part].ratio()) : nlohmann::json(nullptr)}};
  return parts;
}

// The settings the run used: every denoiser key, and any other that is not
// the library's default (the branches are off here, whatever they say).
nlohmann::json settingsJson(const gi::Settings& settings) {
  nlohmann::json json = nlohmann::json::object();
  const gi::Settings defaults;
  for (const gi::SettingInfo& info : gi::settingKeys()) {
    const std::string value = gi::settingValue(settings, info.key);
    if (info.key.rfind("denoise.", 0) == 0 || value != gi::settingValue(defaults, info.key)) json[info.key] = value;
  }
  return json;
}

}  // namespace

CLI::App* addDenoiseCommand(CLI::App& app, DenoiseOptions& options) {
  CLI::App* command = app.add_subcommand(
      "denoise",
      "Denoise a path-traced sequence with the GI library's denoiser alone: a camera path at --spp samples a "
      "frame, its noisy indirect diffuse and specular handed to the library as an engine's own signals; writes "
      "the last frame noisy, denoised and against a converged reference, and their relMSE");
  addGpuOptions(*command, options.gpu);
  addSceneOptions(*command, options.view);
  addGiSettingsOptions(*command, options.gi);
  command->add_option("--frames", options.frames, "Frames of the camera path; the last one is measured")
      ->check(CLI::Range(1u, kMaxFrames))
      ->capture_default_str();
  command->add_option("--spp", options.spp, "Path samples per pixel of each frame's noisy signals")
      ->check(CLI::Range(1u, 1u << 16))
      ->capture_default_str();
  command->add_option("--reference-spp", options.referenceSpp, "Samples per pixel of the last frame's reference")
      ->check(CLI::Range(1u, 1u << 24))
      ->capture_default_str();
  command->add_option("--seed", options.seed, "Random seed: another seed gives independent noise")
      ->capture_default_str();
  command->add_option("--max-bounces", options.maxBounces, "Surfaces a path may bounce off after the primary hit")
      ->check(CLI::Range(1u, 1000u))
      ->capture_default_str();
  command->add_option("--out", options.out, "Output directory (created if missing)")->capture_default_str();
  command->add_option("--exposure", options.exposure, "Exposure multiplier of the PNGs")->check(finitePositive());
  command->add_flag("--checkerboard", options.checkerboard,
                    "Hand the denoiser checkerboarded signals (sets --gi.denoise.checkerboard on): of each frame's "
                    "path-traced signals the pixels of each signal's checkerboard parity, packed to half width, as "
                    "an engine tracing every other pixel would; the noisy images and relMSE stay every pixel's");
  command->add_flag("--dump-stages", options.dumpStages,
                    "Write every pass's output of the last frame (EXR + PNG) to OUT/stages/, the denoiser's "
                    "and its validation sheet among them");
  addOverwriteFlag(*command, options.overwrite);
  return command;
}

int runDenoise(const DenoiseOptions& options) {
  const fs::path outDir = options.out;
  checkWritableDirectory(outDir, "--out");  // before the minutes of tracing, not after
  std::vector<fs::path> written;            // every file this command writes by name, all in OUT
  for (const char* version : kVersions)
    for (const char* suffix : kPartSuffixes)
      for (const char* extension : {".exr", ".png"}) written.push_back(std::string(version) + suffix + extension);
  written.push_back("sheet.png");
  written.push_back("denoise.json");

  // The denoiser on; the branches off: every signal comes from the path
  // tracer (an engine that wants the denoiser alone does the same). The
  // user's settings file and flags apply on top, but may not turn it off.
  gi::Settings base;
  base.denoise.enabled = true;
  base.diffuse.enabled = false;
  base.specular.enabled = false;
  base.denoise.checkerboard = options.checkerboard;
  const gi::Settings settings = giSettings(options.gi, base);
  const bool checkerboard = settings.denoise.checkerboard;
  if (!settings.denoise.enabled)
    throw std::runtime_error("bounce denoise runs the denoiser: gi.denoise.enabled off (from " +
                             std::string(options.gi.settingsFile.empty() ? "--gi.denoise.enabled"
                                                                         : "--gi-settings or --gi.denoise.enabled") +
                             ") leaves nothing to measure");

  const SceneOptions& shot = options.view;
  const scene::Scene scene = loadScene(shot);
  const std::unique_ptr<scene::CameraPath> path = cameraPathOf(scene, shot);
  const std::vector<scene::CameraFrame> cameraFrames = checkedCameraFrames(*path, 0, options.frames, shot);
  const render::FrameRendererOptions rendererOptions = frameRendererOptions(scene, shot);

  // No output may replace an input or a file no Bounce run wrote; an
  // earlier run's stage dump would mix with this one's and is removed.
  OutputFolder folder(outDir, "--out", options.overwrite);
  const std::vector<fs::path> filledFolders =
      options.dumpStages ? std::vector<fs::path>{"stages"} : std::vector<fs::path>{};
  if (const std::size_t removed = folder.prepare(written, filledFolders, inputFiles(scene, shot, &options.gi));
      removed > 0)
    std::printf("removed %zu file%s an earlier run wrote in %s\n", removed, removed == 1 ? "" : "s", outDir.c_str());

  std::unique_ptr<gpu::Context> context = openContext(options.gpu);
  std::printf("device: %s (%s)\n", context->deviceInfo().name.c_str(), context->deviceInfo().type.c_str());
  // The library as an engine has it: no scene bridge, nothing but images.
  const gi::ContextDesc giDesc{
      .maxWidth = shot.width, .maxHeight = shot.height, .framesInFlight = render::FrameRenderer::kFramesInFlight};
  render::requireFrameMemory(*context, shot.width, shot.height, std::pair(giDesc, settings), true);
  // The library is handed signals made here (below), not the renderer's frame alone.
  render::FramePipeline pipeline(*context, scene, {.renderer = rendererOptions, .gi = std::pair(giDesc, settings)});
  render::FrameRenderer& renderer = pipeline.renderer();
  gpu::FrameLoop& loop = pipeline.loop();
  render::GiBridge& gi = *pipeline.gi();
  const auto start = std::chrono::steady_clock::now();

  // The reference comes first: of the last frame's view, so that every
  // frame that shows the same view (all of a static camera's) is measured
  // as it is made, without keeping the frames.
  const std::uint32_t last = options.frames - 1;
  const float lastTime = float(last) / shot.fps;
  const scene::CameraPose& lastPose = cameraFrames[last].pose;
  pipeline.frame({lastPose, lastTime, true}, {.gi = false});
  loop.finish();
  render::ReferenceOptions tracing;
  tracing.seed = options.seed;
  tracing.maxBounces = options.maxBounces;
  render::ReferenceRenderer pathTracer(*context, renderer, scene, loop.frameIndex(), lastTime, tracing);
  checkDeviceMemoryFits(*context, shot.width, shot.height);
  std::printf("scene: %s, %zu triangles, %zu emissive; %u frames at %ux%u, %u spp each; reference %u spp\n",
              scene.name.c_str(), renderer.triangleCount(), pathTracer.emissiveTriangleCount(), options.frames,
              shot.width, shot.height, options.spp, options.referenceSpp);
  std::unique_ptr<CheckerboardPacker> packer;
  if (checkerboard) {
    packer = std::make_unique<CheckerboardPacker>(*context, shot.width, shot.height);
    std::printf("checkerboard: the denoiser gets every other pixel of each signal, packed to half width "
                "(gi.denoise.checkerboard); the noisy images and relMSE are every pixel's\n");
  }
  PartImages reference;
  {
    gpu::FrameLoop sampling(*context, render::FrameRenderer::kFramesInFlight);
    render::ReferenceImages images = sampleReference(pathTracer, sampling, options.referenceSpp, "reference spp");
    reference = {std::move(images.indirectDiffuse), std::move(images.indirectSpecular), std::move(images.radiance)};
  }

  // The sequence. Each frame: the G-buffer, the noisy signals traced from
  // it with samples no earlier frame drew, then the library, which takes
  // them as an engine's own.
  struct Measured {
    std::uint32_t frame;
    std::array<Errors, kPartCount> errors;
  };
  std::vector<Measured> measured;
  PartImages noisy, denoised;
  std::vector<gpu::CapturedStage> captures;
  std::uint64_t firstIndex = 0;
  ProgressBar progress("denoise", options.frames);
  for (std::uint32_t frame = 0; frame < options.frames; ++frame) {
    const scene::CameraFrame& camera = cameraFrames[frame];
    const render::FrameView view{camera.pose, float(frame) / shot.fps, frame == 0 || camera.cut};
    // An animated scene's lights are placed anew for each frame, blocking:
    // the frames that traced the old ones must be done.
    if (scene::isAnimated(scene)) loop.finish();
    const bool dump = options.dumpStages && frame == last;
    gpu::Recorder& recorder = pipeline.begin(view, {.captureStages = dump, .gi = false});
    const std::uint64_t index = loop.frameIndex();
    if (frame == 0) firstIndex = index;
    pathTracer.restart(recorder, index, view.time);
    while (pathTracer.samplesPerPixel() < options.spp)
      pathTracer.record(recorder, std::uint32_t(options.spp - pathTracer.samplesPerPixel()));
    pathTracer.recordResolve(recorder);
    render::RendererInputs made =
        render::rendererInputs(renderer, index, view, pipeline.previousView(), {.captureStages = dump});
    gpu::Image* given[2] = {&pathTracer.indirectDiffuseImage(), &pathTracer.indirectSpecularImage()};
    if (packer)
      for (std::size_t signal = 0; signal < CheckerboardPacker::kSignals; ++signal) {
        packer->record(recorder, signal, *given[signal], made.inputs.frameIndex);
        given[signal] = &packer->packed(signal);
      }
    made.inputs.noisy = {render::imageRef(*given[gi::kDiffuseSignal]), render::imageRef(*given[gi::kSpecularSignal])};
    made.images.push_back(given[0]);
    made.images.push_back(given[1]);
    gi.record(recorder, made.inputs, made.images);
    pipeline.end();

    const bool showsReference =
        frame == last || (sameView(camera.pose, lastPose) && !scene::isAnimated(scene));
    if (showsReference) {
      loop.finish();
      noisy = {rgbOf(*context, pathTracer.indirectDiffuseImage()), rgbOf(*context, pathTracer.indirectSpecularImage()),
               rgbOf(*context, pathTracer.radianceImage())};
      denoised = {rgbOf(*context, gi.indirect(gi::kDiffuseSignal)), rgbOf(*context, gi.indirect(gi::kSpecularSignal)),
                  rgbOf(*context, gi.composite())};
      Measured m{frame, {}};
      for (int part = 0; part < kPartCount; ++part)
        m.errors[part] = {relMse(reference[part], noisy[part]), relMse(reference[part], denoised[part])};
      measured.push_back(m);
    }
    progress.update(frame + 1);
  }
  loop.finish();
  progress.finish();
  for (gpu::CapturedStage& c : loop.takeCaptures()) {
    c.frame -= firstIndex;
    captures.push_back(std::move(c));
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // The last frame, three ways, each part on its own and side by side.
  const std::array<const PartImages*, 3> versions = {&noisy, &denoised, &reference};
  for (std::size_t v = 0; v < versions.size(); ++v)
    for (int part = 0; part < kPartCount; ++part) {
      const fs::path exr = outDir / (std::string(kVersions[v]) + kPartSuffixes[part] + ".exr");
      io::writeExr(exr, (*versions[v])[part]);
      io::writePng(fs::path(exr).replace_extension(".png"), (*versions[v])[part], io::PngEncoding::Tonemapped,
                   options.exposure);
    }
  const std::array<Errors, kPartCount>& errors = measured.back().errors;
  std::vector<io::ImageF> cells;
  std::vector<std::string> labels;
  for (int part = 0; part < kPartCount; ++part) {
    // Short labels: a cell is as wide as the image (96 pixels in the tests).
    char noisyLabel[96], denoisedLabel[96], referenceLabel[96];
    std::snprintf(noisyLabel, sizeof noisyLabel, "%s %u spp: relmse %.3g", kPartNames[part], options.spp,
                  errors[part].noisy);
    std::snprintf(denoisedLabel, sizeof denoisedLabel, "denoised: relmse %.3g", errors[part].denoised);
    std::snprintf(referenceLabel, sizeof referenceLabel, "reference %u spp", options.referenceSpp);
    for (const PartImages* version : versions)
      cells.push_back(io::toDisplay((*version)[part], io::PngEncoding::Tonemapped, options.exposure));
    labels.insert(labels.end(), {noisyLabel, denoisedLabel, referenceLabel});
  }
  io::writePng(outDir / "sheet.png", labelledSheet(cells, labels, 3), io::PngEncoding::Linear);
  if (!captures.empty()) {
    const auto files = gpuio::writeStageDumps(outDir / "stages", captures, options.exposure);
    folder.wrote(files);
    std::printf("wrote %zu stage images to %s\n", files.size(), (outDir / "stages").c_str());
    const std::vector<fs::path> sheets = writeValidationSheets(outDir / "stages", captures, options.exposure,
                                                               float(settings.denoise.maxAccumulatedFrames));
    folder.wrote(sheets);
    for (const fs::path& sheet : sheets)
      std::printf("wrote %s (validation: viewZ, normals, motion, history length, lost histories in red)\n",
                  sheet.c_str());
  }

  nlohmann::json perFrame = nlohmann::json::array();
  for (const Measured& m : measured) {
    perFrame.push_back({{"frame", m.frame}, {"relmse", errorsJson(m.errors)}});
  }
  const nlohmann::json meta = {{"scene", scene.name},
                               {"camera", shot.camera.empty() ? "default" : shot.camera},
                               {"frames", options.frames},
                               {"width", shot.width},
                               {"height", shot.height},
                               {"spp", options.spp},
                               {"checkerboard", checkerboard},
                               {"reference_spp", options.referenceSpp},
                               {"seed", options.seed},
                               {"max_bounces", options.maxBounces},
                               {"seconds", seconds},
                               {"device", context->deviceInfo().name},
                               {"settings", settingsJson(settings)},
                               {"last_frame", last},
                               {"relmse", errorsJson(errors)},
                               {"measured_frames", perFrame}};
  writeTextFile(outDir / "denoise.json", meta.dump(2) + "\n");

  std::printf("wrote noisy, denoised and reference images of frame %u (each part: .indirect-diffuse, "
              ".indirect-specular, the frame; EXR + PNG), sheet.png and denoise.json to %s\n",
              last, outDir.c_str());
  std::printf("\nrelMSE against the reference (%u spp), frame %u of %u frames at %u spp (%.1f s):\n",
              options.referenceSpp, last, options.frames, options.spp, seconds);
  std::printf("  %-18s %12s %12s %18s\n", "", "noisy", "denoised", "denoised / noisy");
  bool undefined = false;
  for (int part = 0; part < kPartCount; ++part) {
    char ratio[32] = "undefined";
    if (const std::optional<double> r = errors[part].ratio())
      std::snprintf(ratio, sizeof ratio, "%.4f", *r);
    else
      undefined = true;
    std::printf("  %-18s %12.4g %12.4g %18s\n", kPartLabels[part], errors[part].noisy, errors[part].denoised, ratio);
  }
  if (undefined) {
    bool black = true;
    for (const io::ImageF& image : reference)
      for (float v : image.pixels) black = black && v == 0.0f;
    std::printf("  (denoised / noisy is undefined where the noisy relMSE is 0: %s)\n",
                black ? "the reference is black" : "the noisy image equals the reference");
  }
  if (measured.size() > 1)
    std::printf("(every frame showing the last one's view is in denoise.json: %zu frames)\n", measured.size());
  std::printf("\nGPU time per pass (%s):\n%s", context->deviceInfo().name.c_str(), loop.timings().table().c_str());
  return validationExitCode(*context);
}

}  // namespace bounce::app
