// bounce reference: the path-traced ground truth of one frame of a camera
// path, with the frame's G-buffer and the reference split the way the GI
// passes split light (direct, indirect diffuse, indirect specular; see
// docs/reference.md). Progressive: Ctrl-C stops it cleanly and writes what
// it has accumulated.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/images.h"
#include "app/option_checks.h"
#include "app/output_files.h"
#include "app/progress.h"
#include "gpu/frame_loop.h"
#include "gpuio/stage_dump.h"
#include "io/image_io.h"
#include "metrics/image_metrics.h"
#include "render/frame_memory.h"
#include "render/reference_renderer.h"
#include "scene/camera_path.h"

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t gInterrupted = 0;
void onInterrupt(int) { gInterrupted = 1; }

// Installs the Ctrl-C handler for its lifetime, then puts the old one back.
class InterruptGuard {
 public:
  InterruptGuard() : previous_(std::signal(SIGINT, onInterrupt)) { gInterrupted = 0; }
  ~InterruptGuard() { std::signal(SIGINT, previous_); }
  bool interrupted() const { return gInterrupted != 0; }

 private:
  void (*previous_)(int);
};

// OUT.exr's siblings: OUT.direct.exr and the like.
fs::path sibling(const fs::path& out, const std::string& suffix) {
  return out.parent_path() / (out.stem().string() + suffix);
}

void writeImage(const fs::path& exr, const io::ImageF& image, float exposure) {
  io::writeExr(exr, image);
  fs::path png = exr;
  png.replace_extension(".png");
  io::writePng(png, image, io::PngEncoding::Tonemapped, exposure);
}

double relMseBetween(const io::ImageF& reference, const io::ImageF& test) {
  return metrics::valueErrors(reference.pixels, test.pixels).relMse;
}

}  // namespace

CLI::App* addReferenceCommand(CLI::App& app, ReferenceCommandOptions& options) {
  CLI::App* command = app.add_subcommand(
      "reference",
      "Path-trace the ground truth of one frame: OUT.exr, its direct / indirect diffuse / indirect specular parts "
      "(demodulated, as the GI passes output them) and the frame's G-buffer");
  addGpuOptions(*command, options.gpu);
  addSceneOptions(*command, options.view);
  command->add_option("--frame", options.frame, "Frame of the camera path to render (0 = the first)")
      ->check(CLI::Range(0u, kMaxFrames - 1))
      ->capture_default_str();
  command->add_option("--spp", options.spp, "Samples per pixel (each: one diffuse and one specular path)")
      ->check(CLI::Range(1u, 1u << 24))
      ->capture_default_str();
  command
      ->add_option("--target-relmse", options.targetRelMse,
                   "Stop early once the relMSE between the two independent halves of the samples is below "
                   "this (checked at every power of two spp from 16); --spp is then the most it takes")
      ->check(finitePositive());
  command->add_option("--max-bounces", options.maxBounces, "Surfaces a path may bounce off after the primary hit")
      ->check(CLI::Range(1u, 1000u))
      ->capture_default_str();
  command->add_option("--seed", options.seed, "Random seed: another seed gives independent noise")
      ->capture_default_str();
  command
      ->add_option("--lobes", options.lobes,
                   "Material lobes the paths follow: all; diffuse (what a diffuse-only GI converges to, and a "
                   "Lambert furnace); specular. Direct light always uses the whole material")
      ->check(CLI::IsMember({"all", "diffuse", "specular"}))
      ->capture_default_str();
  command->add_option("--out", options.out, "Output EXR; its siblings get the parts and the G-buffer")
      ->check(outputExtension(".exr", "OpenEXR"))
      ->capture_default_str();
  command->add_option("--exposure", options.exposure, "Exposure multiplier of the PNG previews")
      ->check(finitePositive());
  command->add_flag("--halves", options.halves,
                    "Also write the two independent halves of the samples (OUT.halfA.exr, OUT.halfB.exr)");
  command->add_flag("--dump-stages", options.dumpStages,
                    "Write the G-buffer and light passes of the frame (EXR + PNG) to OUT.stages/");
  command->add_flag("--overwrite", options.overwrite,
                    "Replace files of OUT (OUT.exr, its siblings, OUT.gbuffer/...) that no Bounce run wrote (by "
                    "default such a file stops the run before it starts; files an earlier run wrote, listed in "
                    ".bounce-written beside OUT, are always replaced)");
  return command;
}

int runReference(const ReferenceCommandOptions& options) {
  const fs::path out = options.out;
  checkWritableFile(out, "--out");  // before the minutes of sampling, not after

  const SceneOptions& view = options.view;
  const scene::Scene scene = loadScene(view);
  // Inputs are never overwritten: OUT.exr, each of its siblings and the
  // folders beside it must not be, or hold, a file the scene, camera or
  // environment was read from.
  const std::vector<fs::path> inputs = inputFiles(scene, view, nullptr);
  std::vector<fs::path> outputs = {out, sibling(out, ".png"), sibling(out, ".sheet.png"), sibling(out, ".json")};
  for (const char* part : {".direct", ".indirect-diffuse", ".indirect-specular", ".halfA", ".halfB"})
    for (const char* extension : {".exr", ".png"}) outputs.push_back(sibling(out, std::string(part) + extension));
  for (const fs::path& output : outputs) refuseToOverwriteInputs(output, "--out", inputs);
  for (const char* folder : {".gbuffer", ".stages"}) refuseInputsInside(sibling(out, folder), "--out", inputs);
  const std::unique_ptr<scene::CameraPath> path = cameraPathOf(scene, view);
  // The frame before (for its motion vectors) and the frame itself.
  const std::uint32_t first = options.frame > 0 ? options.frame - 1 : 0;
  const std::vector<scene::CameraFrame> cameraFrames = checkedCameraFrames(*path, first, options.frame - first + 1, view);
  const render::FrameRendererOptions rendererOptions = frameRendererOptions(scene, view);
  // OUT.exr shares its folder with whatever else is there, so what this run
  // writes is recorded in that folder's .bounce-written like render's files
  // (and nothing else there is removed): a file no Bounce run wrote is not
  // replaced, a link is never written through, a rerun replaces its own.
  std::vector<fs::path> written = {out.filename(), sibling(out, ".png").filename(),
                                   sibling(out, ".sheet.png").filename(), sibling(out, ".json").filename()};
  for (const char* part : {".direct", ".indirect-diffuse", ".indirect-specular", ".halfA", ".halfB"}) {
    if (!options.halves && std::string(part).starts_with(".half")) continue;
    for (const char* extension : {".exr", ".png"})
      written.push_back(sibling(out, std::string(part) + extension).filename());
  }
  std::vector<fs::path> filled = {sibling(out, ".gbuffer").filename()};
  if (options.dumpStages) filled.push_back(sibling(out, ".stages").filename());
  OutputFolder folder(out.parent_path().empty() ? fs::path(".") : out.parent_path(), "--out", options.overwrite,
                      OutputFolder::Use::Shared);
  folder.prepare(written, filled, inputs);

  std::unique_ptr<gpu::Context> context = openContext(options.gpu);
  std::printf("device: %s (%s)\n", context->deviceInfo().name.c_str(), context->deviceInfo().type.c_str());
  render::requireFrameMemory(*context, view.width, view.height, std::nullopt, true);
  // The renderer alone: the path tracer starts from its G-buffer.
  render::FramePipeline pipeline(*context, scene, {.renderer = rendererOptions});
  render::FrameRenderer& renderer = pipeline.renderer();
  gpu::FrameLoop& loop = pipeline.loop();

  std::vector<gpu::CapturedStage> captures;
  for (std::uint32_t frame = first; frame <= options.frame; ++frame) {
    const scene::CameraFrame& camera = cameraFrames[frame - first];
    pipeline.frame({camera.pose, float(frame) / view.fps, camera.cut},
                   {.captureStages = options.dumpStages && frame == options.frame});
  }
  loop.finish();
  const std::uint64_t frameIndex = loop.frameIndex();
  for (gpu::CapturedStage& c : loop.takeCaptures()) captures.push_back(std::move(c));

  render::ReferenceOptions referenceOptions;
  referenceOptions.maxBounces = options.maxBounces;
  referenceOptions.seed = options.seed;
  referenceOptions.lobes = options.lobes == "diffuse"    ? shared::kLobeDiffuse
                           : options.lobes == "specular" ? shared::kLobeSpecular
                                                         : shared::kLobesAll;
  render::ReferenceRenderer reference(*context, renderer, scene, frameIndex, float(options.frame) / view.fps,
                                      referenceOptions);
  checkDeviceMemoryFits(*context, view.width, view.height);
  std::printf("scene: %s, %zu triangles, %zu emissive; frame %u at %ux%u; environment %s\n", scene.name.c_str(),
              renderer.triangleCount(), reference.emissiveTriangleCount(), options.frame, view.width, view.height,
              reference.samplesEnvironment() ? "sampled as a light" : "black");

  gpu::FrameLoop sampling(*context, render::FrameRenderer::kFramesInFlight);
  const InterruptGuard interrupt;
  ProgressBar progress("reference spp", options.spp);
  const auto start = std::chrono::steady_clock::now();
  std::uint64_t nextCheck = 16;
  std::optional<double> convergedRelMse;
  while (reference.samplesPerPixel() < options.spp && !interrupt.interrupted()) {
    // Stop at the next check point so that both halves hold the same samples there.
    const std::uint64_t goal = options.targetRelMse ? std::min<std::uint64_t>(nextCheck, options.spp) : options.spp;
    reference.record(sampling.beginFrame(), std::uint32_t(goal - reference.samplesPerPixel()));
    sampling.endFrame();
    progress.update(reference.samplesPerPixel());
    if (options.targetRelMse && reference.samplesPerPixel() == goal && goal < options.spp) {
      const double relMse = relMseBetween(reference.resolve(sampling, render::ReferenceHalf::A).radiance,
                                          reference.resolve(sampling, render::ReferenceHalf::B).radiance);
      if (relMse < *options.targetRelMse) {
        convergedRelMse = relMse;
        break;
      }
      nextCheck *= 2;
    }
  }
  sampling.finish();
  progress.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const bool interrupted = interrupt.interrupted();
  const std::uint64_t spp = reference.samplesPerPixel();
  if (spp == 0) throw std::runtime_error("interrupted before the first sample: nothing written");

  const render::ReferenceImages images = reference.resolve(sampling, render::ReferenceHalf::Both);
  writeImage(out, images.radiance, options.exposure);
  writeImage(sibling(out, ".direct.exr"), images.direct, options.exposure);
  writeImage(sibling(out, ".indirect-diffuse.exr"), images.indirectDiffuse, options.exposure);
  writeImage(sibling(out, ".indirect-specular.exr"), images.indirectSpecular, options.exposure);
  double halvesRelMse = -1.0;
  if (reference.samplesPerPixel(render::ReferenceHalf::B) > 0) {
    const io::ImageF halfA = reference.resolve(sampling, render::ReferenceHalf::A).radiance;
    const io::ImageF halfB = reference.resolve(sampling, render::ReferenceHalf::B).radiance;
    halvesRelMse = relMseBetween(halfA, halfB);
    if (options.targetRelMse && halvesRelMse < *options.targetRelMse) convergedRelMse = halvesRelMse;
    if (options.halves) {
      writeImage(sibling(out, ".halfA.exr"), halfA, options.exposure);
      writeImage(sibling(out, ".halfB.exr"), halfB, options.exposure);
    }
  }
  folder.wrote(writeAovs(*context, renderer, {"all"}, sibling(out, ".gbuffer"), options.exposure));
  // The picture to look at first: what direct light alone gives, each
  // indirect part, and the whole.
  const auto display = [&](const io::ImageF& image) {
    return io::toDisplay(image, io::PngEncoding::Tonemapped, options.exposure);
  };
  io::writePng(sibling(out, ".sheet.png"),
               labelledSheet({display(images.direct), display(images.indirectDiffuse), display(images.indirectSpecular),
                              display(images.radiance)},
                             {"direct light only", "indirect diffuse (demodulated)", "indirect specular (demodulated)",
                              "reference: all light"},
                             2),
               io::PngEncoding::Linear);
  if (!captures.empty()) {
    const auto files = gpuio::writeStageDumps(sibling(out, ".stages"), captures, options.exposure);
    folder.wrote(files);
    std::printf("wrote %zu stage images to %s\n", files.size(), sibling(out, ".stages").c_str());
  }

  // GPU throughput from the path pass's timestamps (median dispatch).
  double pathMs = 0.0;
  for (const gpu::PassTiming& t : sampling.timings().summary())
    if (t.pass == "render.reference_path") pathMs = t.medianMs;
  const double pixels = double(view.width) * double(view.height);
  const double gpuSppPerSecond = pathMs > 0.0 ? reference.samplesPerDispatch() / (pathMs * 1e-3) : 0.0;

  nlohmann::json meta = {{"scene", scene.name},
                         {"camera", view.camera.empty() ? "default" : view.camera},
                         {"frame", options.frame},
                         {"width", view.width},
                         {"height", view.height},
                         {"spp", spp},
                         {"seed", options.seed},
                         {"max_bounces", options.maxBounces},
                         {"lobes", options.lobes},
                         {"interrupted", interrupted},
                         {"seconds", seconds},
                         {"gpu_spp_per_second", gpuSppPerSecond},
                         {"gpu_megapaths_per_second", 2.0 * gpuSppPerSecond * pixels * 1e-6},
                         {"halves_relmse", halvesRelMse},
                         {"dropped_samples", images.droppedSamples},
                         {"device", context->deviceInfo().name}};
  writeTextFile(sibling(out, ".json"), meta.dump(2) + "\n");

  std::printf("wrote %s (+ .png), its parts %s, %s, %s, the G-buffer in %s and %s\n", out.c_str(),
              sibling(out, ".direct.exr").filename().c_str(), sibling(out, ".indirect-diffuse.exr").filename().c_str(),
              sibling(out, ".indirect-specular.exr").filename().c_str(), sibling(out, ".gbuffer").c_str(),
              sibling(out, ".json").filename().c_str());
  std::printf("%llu spp in %.1f s; GPU: %.1f spp/s at %ux%u (render.reference_path, %u spp per dispatch in %.2f ms)\n",
              static_cast<unsigned long long>(spp), seconds, gpuSppPerSecond, view.width, view.height,
              reference.samplesPerDispatch(), pathMs);
  if (halvesRelMse >= 0.0) std::printf("relMSE between the two halves of the samples: %.3g\n", halvesRelMse);
  if (options.targetRelMse)
    std::printf(convergedRelMse ? "reached --target-relmse %g at %llu spp\n"
                                : "did not reach --target-relmse %g within %llu spp\n",
                *options.targetRelMse, static_cast<unsigned long long>(spp));
  if (images.droppedSamples > 0)
    std::fprintf(stderr, "warning: %llu path samples were not finite and were left out\n",
                 static_cast<unsigned long long>(images.droppedSamples));
  if (interrupted) {
    std::fprintf(stderr, "interrupted: wrote the %llu spp accumulated so far\n", static_cast<unsigned long long>(spp));
    return 130;
  }
  return validationExitCode(*context);
}

}  // namespace bounce::app
