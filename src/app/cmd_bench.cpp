// bounce bench: GPU timestamps of every pass over many frames at a given
// resolution, and the copy bandwidth the device reaches in compute.
#include <cstdio>
#include <fstream>

#include "app/commands.h"
#include "app/progress.h"
#include "gpu/copy_bandwidth.h"
#include "gpu/frame_loop.h"
#include "render/analytic_scene.h"

namespace bounce::app {

CLI::App* addBenchCommand(CLI::App& app, BenchOptions& options) {
  CLI::App* command = app.add_subcommand("bench", "Time every pass with GPU timestamps, and the copy bandwidth");
  addGpuOptions(*command, options.gpu);
  command->add_option("--width", options.width, "Image width in pixels")->check(CLI::Range(1u, 16384u));
  command->add_option("--height", options.height, "Image height in pixels")->check(CLI::Range(1u, 16384u));
  command->add_option("--frames", options.frames, "Timed frames")->check(CLI::Range(1u, 100000u));
  command->add_option("--warmup", options.warmup, "Untimed frames first (pipeline caches, clocks)")
      ->check(CLI::Range(0u, 100000u));
  command->add_option("--copy-mb", options.copyMegabytes, "Buffer size of the copy-bandwidth pass, MiB (0 = skip)")
      ->check(CLI::Range(0u, 4096u));
  command->add_option("--json", options.json, "Also write the results to this JSON file");
  return command;
}

int runBench(const BenchOptions& options) {
  std::unique_ptr<gpu::Context> context = openContext(options.gpu);
  const gpu::DeviceInfo& device = context->deviceInfo();
  std::printf("device: %s (%s), driver %s\n", device.name.c_str(), device.type.c_str(), device.driver.c_str());
  render::AnalyticRenderer renderer(*context, options.width, options.height, render::AnalyticScene::standard());
  std::unique_ptr<gpu::CopyBandwidthProbe> copy;
  if (options.copyMegabytes)
    copy = std::make_unique<gpu::CopyBandwidthProbe>(*context, VkDeviceSize(options.copyMegabytes) << 20);

  // Warm-up frames go to a loop whose timings are thrown away.
  {
    gpu::FrameLoop warmup(*context);
    for (std::uint32_t i = 0; i < options.warmup; ++i) {
      gpu::Recorder& recorder = warmup.beginFrame();
      renderer.record(recorder, render::Camera{});
      if (copy) copy->record(recorder);
      warmup.endFrame();
    }
    warmup.finish();
  }
  gpu::FrameLoop loop(*context);
  ProgressBar progress("bench", options.frames);
  for (std::uint32_t i = 0; i < options.frames; ++i) {
    gpu::Recorder& recorder = loop.beginFrame();
    renderer.record(recorder, render::Camera{});
    if (copy) copy->record(recorder);
    loop.endFrame();
    progress.update(i + 1);
  }
  loop.finish();
  progress.finish();

  std::printf("\nGPU time per pass, %ux%u, %u frames (%s):\n%s", options.width, options.height, options.frames,
              device.name.c_str(), loop.timings().table().c_str());
  double bandwidth = 0;
  for (const gpu::PassTiming& t : loop.timings().summary())
    if (copy && t.pass == gpu::CopyBandwidthProbe::kPassName)
      bandwidth = double(copy->bytesMoved()) / (t.medianMs * 1e-3) / 1e9;
  if (copy)
    std::printf("\ncopy bandwidth: %.1f GB/s (%u MiB read + %u MiB written per dispatch, median)\n", bandwidth,
                options.copyMegabytes, options.copyMegabytes);

  if (!options.json.empty()) {
    std::ofstream json(options.json);
    if (!json) throw std::runtime_error("cannot write " + options.json);
    json << "{\n  \"device\": \"" << device.name << "\",\n  \"driver\": \"" << device.driver << "\",\n"
         << "  \"width\": " << options.width << ",\n  \"height\": " << options.height << ",\n"
         << "  \"frames\": " << options.frames << ",\n  \"copy_bandwidth_gbps\": " << bandwidth << ",\n"
         << "  \"passes\": [\n";
    auto rows = loop.timings().summary();
    for (std::size_t i = 0; i < rows.size(); ++i)
      json << "    {\"name\": \"" << rows[i].pass << "\", \"median_ms\": " << rows[i].medianMs
           << ", \"min_ms\": " << rows[i].minMs << ", \"max_ms\": " << rows[i].maxMs << "}"
           << (i + 1 < rows.size() ? ",\n" : "\n");
    json << "  ]\n}\n";
  }
  return validationExitCode(*context);
}

}  // namespace bounce::app
