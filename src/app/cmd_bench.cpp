// bounce bench: GPU timestamps of every pass of the frame renderer and the GI
// library over many frames of a scene at a given resolution, the BVH's ray
// throughput (primary, shadow and incoherent rays), and the copy bandwidth
// the device reaches in compute.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/copy_bandwidth.h"
#include "app/option_checks.h"
#include "app/output_files.h"
#include "app/progress.h"
#include "gpu/frame_loop.h"
#include "gpu/transfer.h"
#include "render/benchmark_rays.h"
#include "render/frame_memory.h"
#include "render/frame_pipeline.h"
#include "render/frame_renderer.h"
#include "render/gi_bridge.h"
#include "render/gpu_bvh.h"
#include "scene/camera_path.h"

namespace bounce::app {
namespace {

// How many of the --rays the CPU walks to count the walk's work.
constexpr std::size_t kWalkStatsRays = 65536;

// Each GI pass against its traffic floor (docs/benchmarks.md, "Traffic
// floors"): the bytes of the images its binds cover, each once, over the
// device's bandwidth is the least time it could take; the share of that in
// its median time says how far it is from bandwidth-bound (100 %). Storage
// buffers are shown apart (counted whole: some are sized for the worst case).
void printTrafficFloors(std::FILE* report, const std::vector<gpu::PassTiming>& timings, double bandwidthGbps,
                        const char* bandwidthSource) {
  std::size_t width = 4;
  for (const gpu::PassTiming& t : timings)
    if (t.pass.starts_with("gi.")) width = std::max(width, t.pass.size());
  std::fprintf(report,
               "\ntraffic floors of the GI passes (images each once, at %.0f GB/s: %s bandwidth):\n"
               "%-*s  %9s  %10s  %9s  %10s  %8s  %8s\n",
               bandwidthGbps, bandwidthSource, int(width), "pass", "median ms", "images MB", "floor ms", "buffers MB",
               "of floor", "GB/s");
  double ms = 0.0, floorMs = 0.0, imageMb = 0.0;
  for (const gpu::PassTiming& t : timings) {
    if (!t.pass.starts_with("gi.")) continue;
    const double mb = double(t.traffic.imageBytes) / 1e6;
    const double floor = mb / bandwidthGbps;  // MB / (GB/s) = ms
    std::fprintf(report, "%-*s  %9.4f  %10.1f  %9.4f  %10.1f  %7.1f%%  %8.0f\n", int(width), t.pass.c_str(), t.medianMs,
                 mb, floor, double(t.traffic.bufferBytes) / 1e6, t.medianMs > 0 ? 100.0 * floor / t.medianMs : 0.0,
                 t.medianMs > 0 ? mb / t.medianMs : 0.0);
    ms += t.medianMs;
    floorMs += floor;
    imageMb += mb;
  }
  std::fprintf(report, "%-*s  %9.4f  %10.1f  %9.4f  %10s  %7.1f%%  %8.0f\n", int(width), "all gi.*", ms, imageMb,
               floorMs, "", ms > 0 ? 100.0 * floorMs / ms : 0.0, ms > 0 ? imageMb / ms : 0.0);
}

}  // namespace

CLI::App* addBenchCommand(CLI::App& app, BenchOptions& options) {
  CLI::App* command =
      app.add_subcommand("bench", "Time every pass with GPU timestamps; BVH rays per second; copy bandwidth");
  addGpuOptions(*command, options.gpu);
  command->add_option("scene", options.scene, "Built-in scene or .gltf/.glb file (default: the default built-in)");
  addAllowOutsideAssetsFlag(*command, options.allowOutsideAssets);
  command->add_option("--width", options.width, "Image width in pixels")->check(CLI::Range(1u, 16384u));
  command->add_option("--height", options.height, "Image height in pixels")->check(CLI::Range(1u, 16384u));
  command->add_option("--frames", options.frames, "Timed frames")->check(CLI::Range(1u, 100000u));
  command->add_option("--warmup", options.warmup, "Untimed frames first (pipeline caches, clocks)")
      ->check(CLI::Range(0u, 100000u));
  command->add_option("--copy-mb", options.copyMegabytes, "Buffer size of the copy-bandwidth pass, MiB (0 = skip)")
      ->check(CLI::Range(0u, 4096u));
  command
      ->add_option("--bandwidth-gbps", options.bandwidthGbps,
                   "Device bandwidth, GB/s, for the passes' traffic floors when the copy pass is skipped (--copy-mb "
                   "0); else the copy pass's measured bandwidth")
      ->check(CLI::Range(1.0, 100000.0));
  command->add_option("--rays", options.rays, "Incoherent rays per frame through render.bvh_trace_rays (0 = skip)")
      ->check(CLI::Range(0u, 1u << 26));
  command
      ->add_option("--ray-origins", options.rayOrigins,
                   "Where the --rays start: visible (off the surfaces the camera sees, one cosine-distributed "
                   "ray a pixel in 8x8 tiles: the GI's rays), surfaces (anywhere on the triangles, "
                   "cosine-distributed off them: GI bounces) or bounds (uniformly in the scene's box, uniform "
                   "directions)")
      ->check(CLI::IsMember({"visible", "surfaces", "bounds"}))
      ->capture_default_str();
  command
      ->add_option("--json", options.json,
                   "Also write the results to this JSON file ('-': JSON on stdout, the table on stderr)")
      ->check(outputExtension(".json", "JSON", "-"));
  command->add_option("--sun-elevation", options.sunElevation, "Sun elevation above the horizon, degrees")
      ->check(finiteRange(-90.0, 90.0));
  command->add_option("--sun-azimuth", options.sunAzimuth, "Sun azimuth from +Z towards +X, degrees")
      ->check(finiteNumber());
  addGiOptions(*command, options.gi, /*warmup=*/false);
  return command;
}

int runBench(const BenchOptions& options) {
  // With the JSON on stdout, what people read goes to stderr.
  const bool jsonToStdout = options.json == "-";
  FILE* const report = jsonToStdout ? stderr : stdout;
  if (!options.json.empty() && !jsonToStdout) checkWritableFile(options.json, "--json");
  warnIgnoredGiOptions(options.gi);
  const std::optional<gi::Settings> settings =
      giEnabled(options.gi) ? std::optional(giSettings(options.gi)) : std::nullopt;
  const scene::Scene scene = loadSceneArgument(options.scene, {.allowOutsideAssets = options.allowOutsideAssets});
  if (!options.json.empty() && !jsonToStdout) {
    std::vector<std::filesystem::path> inputs = scene.files;
    if (!options.gi.settingsFile.empty()) inputs.push_back(options.gi.settingsFile);
    refuseToOverwriteInputs(options.json, "--json", inputs);
  }
  std::unique_ptr<gpu::Context> context = openContext(options.gpu);
  const gpu::DeviceInfo& device = context->deviceInfo();
  std::fprintf(report, "device: %s (%s), driver %s\n", device.name.c_str(), device.type.c_str(), device.driver.c_str());

  render::FrameRendererOptions rendererOptions;
  rendererOptions.width = options.width;
  rendererOptions.height = options.height;
  rendererOptions.environment.sun = scene.sun;
  rendererOptions.environment.hasSun = scene.hasSun;
  if (options.sunElevation) {
    rendererOptions.environment.sun.elevationDegrees = *options.sunElevation;
    rendererOptions.environment.hasSun = true;
  }
  if (options.sunAzimuth) rendererOptions.environment.sun.azimuthDegrees = *options.sunAzimuth;
  render::requireFrameMemory(
      *context, options.width, options.height,
      settings ? std::optional(std::pair(giContextDesc(options.width, options.height, options.gi), *settings))
               : std::nullopt,
      false);
  render::FramePipeline pipeline(
      *context, scene,
      {.renderer = rendererOptions,
       .gi = settings ? std::optional(std::pair(giContextDesc(options.width, options.height, options.gi), *settings))
                      : std::nullopt});
  render::FrameRenderer& renderer = pipeline.renderer();
  render::GiBridge* gi = pipeline.gi();
  checkDeviceMemoryFits(*context, options.width, options.height);
  std::fprintf(report, "scene: %s, %zu triangles\n", scene.name.c_str(), renderer.triangleCount());
  const render::SceneBvh& bvh = renderer.bvh();
  const double bvhBuildMs = bvh.blasBuildSeconds() * 1e3;
  std::fprintf(report,
               "BVH: %.2f MiB of device memory, %zu 8-wide BLAS nodes; BLASes built in %.0f ms (%u CPU threads), "
               "binary depth %u, TLAS depth %u\n",
               double(bvh.deviceBytes()) / (1 << 20), bvh.blasNodes().size(), bvhBuildMs, bvh.blasBuildThreads(),
               bvh.blasDepth(), bvh.tlasDepth());
  nlohmann::json memoryByUnit = nlohmann::json::object();
  if (gi) {
    std::fprintf(report, "GI library: %.1f MiB of device memory at %ux%u (",
                 double(gi->library().memoryBytes()) / double(1 << 20), options.width, options.height);
    const char* separator = "";
    for (const gi::UnitMemory& unit : gi->library().memoryByUnit()) {
      std::fprintf(report, "%s%s %.1f", separator, unit.unit.c_str(), double(unit.bytes) / double(1 << 20));
      memoryByUnit[unit.unit] = unit.bytes;
      separator = ", ";
    }
    std::fprintf(report, " MiB)\n");
  }
  const scene::CameraPose camera = scene::defaultCameraPath(scene)->pose(0.0f);

  std::unique_ptr<CopyBandwidthProbe> copy;
  if (options.copyMegabytes)
    copy = std::make_unique<CopyBandwidthProbe>(*context, VkDeviceSize(options.copyMegabytes) << 20);
  std::unique_ptr<render::BvhRayTracer> tracer;
  std::unique_ptr<gpu::Buffer> rays, results;
  nlohmann::json walkStats = nlohmann::json::object();
  std::string rayOriginsText = options.rayOrigins == "surfaces" ? "off the scene's surfaces" : "in the scene bounds";
  if (options.rays) {
    std::vector<render::BvhRay> rayData;
    if (options.rayOrigins == "visible") {
      // Every pixel's primary hit on the CPU: seconds at 1080p on a few cores.
      ProgressBar tracing("surfaces the camera sees", std::uint64_t(options.width) * options.height);
      render::VisibleSurfaceRays visible =
          render::visibleSurfaceRays(bvh, camera, options.width, options.height, options.rays,
                                     [&](std::uint64_t done, std::uint64_t) { tracing.update(done); });
      tracing.finish();
      rayData = std::move(visible.rays);
      if (rayData.empty()) {
        rayData = render::surfaceRays(scene, options.rays);
        rayOriginsText = "off the scene's surfaces (the camera sees no surface)";
      } else {
        rayOriginsText = "off the surfaces the camera sees (" + std::to_string(visible.visiblePixels) + " of " +
                         std::to_string(visible.pixels) + " pixels)";
      }
    } else if (options.rayOrigins == "surfaces") {
      rayData = render::surfaceRays(scene, options.rays);
    } else {
      rayData = render::boundsRays(scene, options.rays);
    }
    // What the walk does for these rays, counted on the CPU (the same walk)
    // over an even sample of them: where its time goes.
    std::vector<render::BvhRay> sample;
    const std::size_t sampleStride = std::max<std::size_t>(1, rayData.size() / kWalkStatsRays);
    for (std::size_t i = 0; i < rayData.size(); i += sampleStride) sample.push_back(rayData[i]);
    for (const bool anyHit : {false, true}) {
      const render::BvhWalkStats stats = bvh.walkStats(sample, anyHit);
      std::fprintf(report, "BVH walk (CPU, %zu of the rays), %s: %.1f nodes, %.2f instances, %.1f triangles a ray\n",
                   sample.size(), anyHit ? "any hit" : "closest hit", stats.perRay(stats.nodes),
                   stats.perRay(stats.instances), stats.perRay(stats.triangles));
      walkStats[anyHit ? "any_hit" : "closest_hit"] = {{"rays", stats.rays},
                                                       {"nodes_per_ray", stats.perRay(stats.nodes)},
                                                       {"instances_per_ray", stats.perRay(stats.instances)},
                                                       {"triangles_per_ray", stats.perRay(stats.triangles)}};
    }
    rays = std::make_unique<gpu::Buffer>(*context, "bench.rays", rayData.size() * sizeof(render::BvhRay),
                                         gpu::BufferUsage::DeviceLocal);
    gpu::uploadBuffer(*context, *rays, rayData.data(), rayData.size() * sizeof(render::BvhRay));
    results = std::make_unique<gpu::Buffer>(
        *context, "bench.ray_results", rayData.size() * sizeof(render::BvhTraceResult), gpu::BufferUsage::DeviceLocal);
    tracer = std::make_unique<render::BvhRayTracer>(*context);
  }
  // The closest-hit and any-hit variants get their own timestamp names.
  std::unique_ptr<render::BvhRayTracer> anyTracer;
  if (options.rays)
    anyTracer = std::make_unique<render::BvhRayTracer>(
        *context, render::bvhTraceRaysPassDesc("render.bvh_trace_rays_any", "render/bvh_trace_rays"));

  // One still camera: after the first frame each reprojects the one before.
  const auto recordFrame = [&] {
    gpu::Recorder& recorder = pipeline.begin({camera, 0.0f, pipeline.framesRecorded() == 0});
    if (tracer) {
      tracer->record(recorder, renderer.gpuBvh(), *rays, *results, options.rays, render::BvhTraceMode::Closest);
      anyTracer->record(recorder, renderer.gpuBvh(), *rays, *results, options.rays, render::BvhTraceMode::Any);
    }
    if (copy) copy->record(recorder);
    pipeline.end();
  };
  gpu::FrameLoop& loop = pipeline.loop();
  for (std::uint32_t i = 0; i < options.warmup; ++i) recordFrame();
  // The warm-up frames' timings and rays are thrown away.
  loop.finish();
  loop.timings() = gpu::TimingStats{};
  if (gi) gi->resetWorldRays();
  ProgressBar progress("bench", options.frames);
  for (std::uint32_t i = 0; i < options.frames; ++i) {
    recordFrame();
    progress.update(i + 1);
  }
  loop.finish();
  progress.finish();

  std::fprintf(report, "\nGPU time per pass, %ux%u, %u frames (%s):\n%s", options.width, options.height, options.frames,
               device.name.c_str(), loop.timings().table().c_str());
  double bandwidth = 0.0, primaryRays = 0.0, incoherentClosest = 0.0, incoherentAny = 0.0, wholeGiMs = 0.0;
  const double pixels = double(options.width) * double(options.height);
  for (const gpu::PassTiming& t : loop.timings().summary()) {
    const double seconds = t.medianMs * 1e-3;
    if (copy && t.pass == CopyBandwidthProbe::kPassName) bandwidth = double(copy->bytesMoved()) / seconds / 1e9;
    if (t.pass == "render.gbuffer") primaryRays = pixels / seconds;
    if (t.pass == "render.bvh_trace_rays") incoherentClosest = double(options.rays) / seconds;
    if (t.pass == "render.bvh_trace_rays_any") incoherentAny = double(options.rays) / seconds;
    if (t.pass.starts_with("gi.")) wholeGiMs += t.medianMs;
  }
  if (gi) {
    std::fprintf(report, "\nwhole GI (every gi.* pass, medians added): %.3f ms\n", wholeGiMs);
    printTrafficFloors(report, loop.timings().summary(), copy ? bandwidth : options.bandwidthGbps,
                       copy ? "the copy pass's" : "--bandwidth-gbps");
  }
  nlohmann::json worldRays = nlohmann::json::object();
  nlohmann::json worldRaysByPass = nlohmann::json::object();
  if (gi && gi->worldRays().frames > 0) {
    const render::GiBridge::WorldRayTally& tally = gi->worldRays();
    const double frames = double(tally.frames);
    std::fprintf(report, "\nworld rays per frame (mean of %llu frames), by purpose:\n",
                 static_cast<unsigned long long>(tally.frames));
    for (std::size_t p = 0; p < gi::kWorldRayPurposeCount; ++p) {
      const char* name = gi::worldRayPurposeName(gi::WorldRayPurpose(p));
      const double perFrame = double(tally.sum.rays[p]) / frames;
      std::fprintf(report, "  %-20s %12.0f  %.3f per pixel\n", name, perFrame, perFrame / pixels);
      worldRays[name] = perFrame;
    }
    const double total = double(tally.sum.total()) / frames;
    std::fprintf(report, "  %-20s %12.0f  %.3f per pixel\n", "total", total, total / pixels);
    const gi::WorldRayPlan plan = gi::planWorldRays(gi->library().settings());
    std::fprintf(report,
                 "  budget (gi.world_ray_budget): %.2f per pixel; at most %.2f planned (%u ray candidates, %u sky "
                 "tests per spatial pass, per reservoir of 4 pixels), cache updates and hit shadows apart\n",
                 double(gi->library().settings().worldRayBudget), double(plan.perReservoir()) / 4.0,
                 plan.diffuseCandidates, plan.skyReuseRays);
    worldRays["total"] = total;
    // Each pass's own rays (its rays of every purpose, the shadow rays that
    // light its hits among them) over its median time: the rate the GI sees,
    // to hold against the walk's own in a dense pass (--rays).
    std::fprintf(report,
                 "\nworld rays per second, by the pass that cast them (rays a frame / median pass time; a pass "
                 "that traces a queue left by an earlier one: its entries a frame):\n");
    const std::vector<gpu::PassTiming> timings = loop.timings().summary();
    for (std::size_t p = 0; p < gi::kWorldRayPassCount; ++p) {
      const double perFrame = double(tally.sum.passRays[p]) / frames;
      if (perFrame == 0.0) continue;
      const char* pass = gi::worldRayPassName(p);
      const auto timing = std::find_if(timings.begin(), timings.end(),
                                       [&](const gpu::PassTiming& t) { return t.pass == pass; });
      const double medianMs = timing != timings.end() ? timing->medianMs : 0.0;
      const double queued = double(tally.sum.passQueued[p]) / frames;
      std::fprintf(report, "  %-32s %12.0f rays  %8.4f ms  %7.0f M rays/s", pass, perFrame, medianMs,
                   medianMs > 0.0 ? perFrame / (medianMs * 1e-3) / 1e6 : 0.0);
      if (queued > 0.0) std::fprintf(report, "  %10.0f queued, %.2f rays each", queued, perFrame / queued);
      std::fprintf(report, "\n");
      worldRaysByPass[pass] = {{"rays_per_frame", perFrame},
                               {"queued_per_frame", queued},
                               {"median_ms", medianMs},
                               {"rays_per_second", medianMs > 0.0 ? perFrame / (medianMs * 1e-3) : 0.0}};
    }
  }
  std::fprintf(report, "\nrays per second (median pass time): primary %.0f M (whole G-buffer pass, 1 ray per pixel)",
               primaryRays / 1e6);
  if (tracer)
    std::fprintf(report, ", incoherent closest-hit %.0f M, incoherent any-hit %.0f M (%u random rays %s)",
                 incoherentClosest / 1e6, incoherentAny / 1e6, options.rays, rayOriginsText.c_str());
  std::fprintf(report, "\n");
  if (copy)
    std::fprintf(
        report, "copy bandwidth: %.1f GB/s (%.0f MiB read + %.0f MiB written per dispatch, median)%s\n", bandwidth,
        double(copy->bytes()) / (1 << 20), double(copy->bytes()) / (1 << 20),
        copy->bytes() < (VkDeviceSize(options.copyMegabytes) << 20) ? "; the device binds no more at once" : "");

  if (!options.json.empty()) {
    nlohmann::json passes = nlohmann::json::array();
    for (const gpu::PassTiming& t : loop.timings().summary())
      passes.push_back({{"name", t.pass},
                        {"median_ms", t.medianMs},
                        {"min_ms", t.minMs},
                        {"max_ms", t.maxMs},
                        {"image_bytes", t.traffic.imageBytes},
                        {"buffer_bytes", t.traffic.bufferBytes}});
    const nlohmann::json results = {{"device", device.name},
                                    {"driver", device.driver},
                                    {"scene", scene.name},
                                    {"triangles", renderer.triangleCount()},
                                    {"width", options.width},
                                    {"height", options.height},
                                    {"frames", options.frames},
                                    {"copy_bandwidth_gbps", bandwidth},
                                    {"primary_rays_per_s", primaryRays},
                                    {"incoherent_closest_rays_per_s", incoherentClosest},
                                    {"incoherent_any_rays_per_s", incoherentAny},
                                    {"ray_origins", options.rayOrigins},
                                    {"bvh_walk", walkStats},
                                    {"bvh_bytes", bvh.deviceBytes()},
                                    {"bvh_build_ms", bvhBuildMs},
                                    {"scene_bridge", gi ? options.gi.sceneBridge : "off"},
                                    {"whole_gi_ms", wholeGiMs},
                                    {"gi_memory_bytes", gi ? gi->library().memoryBytes() : 0},
                                    {"gi_memory_bytes_by_unit", memoryByUnit},
                                    {"world_rays_per_frame", worldRays},
                                    {"world_rays_by_pass", worldRaysByPass},
                                    {"passes", passes}};
    if (jsonToStdout)
      std::cout << results.dump(2) << "\n" << std::flush;
    else
      writeTextFile(options.json, results.dump(2) + "\n");
  }
  return validationExitCode(*context);
}

}  // namespace bounce::app
