// bounce: the command-line renderer and tools.
#include <cstdio>
#include <exception>

#include "app/commands.h"

namespace bounce::app {

void addGpuOptions(CLI::App& command, GpuOptions& options) {
  command
      .add_option("--device", options.device,
                  "Vulkan device index from 'bounce info' (default: BOUNCE_DEVICE, else the best GPU, "
                  "else lavapipe)")
      ->check(CLI::NonNegativeNumber);
  command.add_flag("--validate", options.validate,
                   "Enable the Khronos validation layer with synchronization validation; any message makes the "
                   "command fail");
}

std::unique_ptr<gpu::Context> openContext(const GpuOptions& options) {
  gpu::ContextOptions contextOptions;
  contextOptions.deviceIndex = options.device;
  contextOptions.validation = options.validate;
  return std::make_unique<gpu::Context>(contextOptions);
}

int validationExitCode(const gpu::Context& context) {
  const std::size_t count = context.validationMessages().size();
  if (count == 0) return 0;
  std::fprintf(stderr, "bounce: error: %zu Vulkan validation message(s), see above\n", count);
  return 1;
}

}  // namespace bounce::app

int main(int argc, char** argv) {
  using namespace bounce::app;
  // Line by line even into a file or pipe, so a log shows how far a long run got.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  CLI::App app{"Bounce: real-time screen-space global illumination (Vulkan compute)", "bounce"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "bounce 0.1.0");
  InfoOptions info;
  RenderOptions render;
  BenchOptions bench;
  BrdfVizOptions brdfViz;
  CompareOptions compare;
  ReferenceCommandOptions reference;
  CLI::App* infoCommand = addInfoCommand(app, info);
  CLI::App* renderCommand = addRenderCommand(app, render);
  CLI::App* benchCommand = addBenchCommand(app, bench);
  CLI::App* brdfVizCommand = addBrdfVizCommand(app, brdfViz);
  CLI::App* compareCommand = addCompareCommand(app, compare);
  CLI::App* referenceCommand = addReferenceCommand(app, reference);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::string unknownSetting = unknownGiSettingFlag(argc, argv);
    if (!unknownSetting.empty()) {
      std::fprintf(stderr, "bounce: error: %s (docs/gi-settings.md lists them)\n", unknownSetting.c_str());
      return 2;
    }
    std::fprintf(stderr, "bounce: error: %s (see bounce --help)\n", e.what());
    return 2;
  }

  try {
    if (infoCommand->parsed()) return runInfo(info);
    if (renderCommand->parsed()) return runRender(render);
    if (benchCommand->parsed()) return runBench(bench);
    if (brdfVizCommand->parsed()) return runBrdfViz(brdfViz);
    if (compareCommand->parsed()) return runCompare(compare);
    if (referenceCommand->parsed()) return runReference(reference);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bounce: error: %s\n", e.what());
    return 1;
  }
  return 2;
}
