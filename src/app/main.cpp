// bounce: the command-line renderer and tools.
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>

#include "app/commands.h"
#include "app/option_checks.h"
#include "bounce/version.h"
#include "util/edit_distance.h"
#include "util/printable.h"

namespace bounce::app {

void addGpuOptions(CLI::App& command, GpuOptions& options) {
  command
      .add_option("--device", options.device,
                  "Vulkan device index from 'bounce info' (default: BOUNCE_DEVICE, else the best GPU, "
                  "else lavapipe)")
      ->check(CLI::Range(0, 1023));
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

void checkDeviceMemoryFits(const gpu::Context& context, std::uint32_t width, std::uint32_t height) {
  const double inUse = double(context.deviceLocalBytesInUse());
  const double heap = double(context.largestDeviceLocalHeap());
  if (heap == 0.0 || inUse <= heap) return;
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  char message[256];
  std::snprintf(message, sizeof message,
                "a %ux%u frame needs %.1f GiB of device memory for its images and buffers; %s has %.1f GiB: "
                "render smaller (--width, --height) or choose another --device",
                width, height, inUse / kGiB, context.deviceInfo().name.c_str(), heap / kGiB);
  throw std::runtime_error(message);
}

namespace {

// CLI11 answers a mistyped command ("bounce rendr") with "A subcommand is
// required"; this names the word and the closest command instead. Empty
// when the first word is an option or a known command.
std::string unknownCommandMessage(const CLI::App& app, int argc, const char* const* argv) {
  if (argc < 2 || argv[1][0] == '-') return "";
  const std::string word = argv[1];
  std::string closest, names;
  std::size_t closestDistance = word.size();
  for (const CLI::App* command : app.get_subcommands({})) {
    const std::string& name = command->get_name();
    if (name == word) return "";
    names += (names.empty() ? "" : ", ") + name;
    const std::size_t distance = bounce::util::editDistance(word, name);
    if (distance < closestDistance) {
      closestDistance = distance;
      closest = name;
    }
  }
  std::string message = "unknown command '" + word + "'";
  if (!closest.empty() && closestDistance <= std::max<std::size_t>(2, word.size() / 3))
    message += "; did you mean '" + closest + "'?";
  return message + " (commands: " + names + ")";
}

}  // namespace

}  // namespace bounce::app

int main(int argc, char** argv) {
  using namespace bounce::app;
  // Line by line even into a file or pipe, so a log shows how far a long run got.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  CLI::App app{"Bounce: real-time screen-space global illumination (Vulkan compute)", "bounce"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("bounce ") + BOUNCE_VERSION_STRING);
  InfoOptions info;
  RenderOptions render;
  BenchOptions bench;
  BrdfVizOptions brdfViz;
  CompareOptions compare;
  ReferenceCommandOptions reference;
  SheetOptions sheet;
  DenoiseOptions denoise;
  GhostingOptions ghosting;
  ViewOptions view;
  CLI::App* infoCommand = addInfoCommand(app, info);
  CLI::App* renderCommand = addRenderCommand(app, render);
  CLI::App* benchCommand = addBenchCommand(app, bench);
  CLI::App* brdfVizCommand = addBrdfVizCommand(app, brdfViz);
  CLI::App* compareCommand = addCompareCommand(app, compare);
  CLI::App* referenceCommand = addReferenceCommand(app, reference);
  CLI::App* sheetCommand = addSheetCommand(app, sheet);
  CLI::App* denoiseCommand = addDenoiseCommand(app, denoise);
  CLI::App* ghostingCommand = addGhostingCommand(app, ghosting);
  CLI::App* viewCommand = addViewCommand(app, view);

  if (const std::string unknown = unknownCommandMessage(app, argc, argv); !unknown.empty()) {
    std::fprintf(stderr, "bounce: error: %s\n", bounce::util::printable(unknown).c_str());
    return 2;
  }
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
      std::fprintf(stderr, "bounce: error: %s (docs/gi-settings.md lists them)\n",
                   bounce::util::printable(unknownSetting).c_str());
      return 2;
    }
    std::fprintf(stderr, "bounce: error: %s (see bounce --help)\n", bounce::util::printable(e.what()).c_str());
    return 2;
  }

  try {
    if (infoCommand->parsed()) return runInfo(info);
    if (renderCommand->parsed()) {
      render.sizeGiven = renderCommand->count("--width") + renderCommand->count("--height") > 0;
      render.warmupGiven = renderCommand->count("--gi-warmup") > 0;
      return runRender(render);
    }
    if (benchCommand->parsed()) return runBench(bench);
    if (brdfVizCommand->parsed()) return runBrdfViz(brdfViz);
    if (compareCommand->parsed()) return runCompare(compare);
    if (referenceCommand->parsed()) return runReference(reference);
    if (sheetCommand->parsed()) return runSheet(sheet);
    if (denoiseCommand->parsed()) return runDenoise(denoise);
    if (ghostingCommand->parsed()) return runGhosting(ghosting);
    if (viewCommand->parsed()) return runView(view);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "bounce: error: %s\n", bounce::util::printable(e.what()).c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bounce: error: %s\n", bounce::util::printable(e.what()).c_str());
    // compare's 1 means "differs beyond a threshold"; trouble is 2, as for cmp and diff.
    return compareCommand->parsed() ? 2 : 1;
  }
  return 2;
}
