// bounce info: the Vulkan devices, their drivers and the limits Bounce cares about.
#include <cstdio>

#include "app/commands.h"
#include "gpu/context.h"

namespace bounce::app {

CLI::App* addInfoCommand(CLI::App& app, InfoOptions& options) {
  CLI::App* command = app.add_subcommand("info", "List Vulkan devices, drivers and limits");
  addGpuOptions(*command, options.gpu);
  return command;
}

int runInfo(const InfoOptions& options) {
  std::vector<gpu::DeviceInfo> devices = gpu::Context::enumerateDevices();
  std::printf("Vulkan devices:\n");
  for (const gpu::DeviceInfo& d : devices)
    std::printf("  %d: %s (%s), Vulkan %s, driver %s%s\n", d.index, d.name.c_str(), d.type.c_str(),
                gpu::versionString(d.apiVersion).c_str(), d.driver.c_str(),
                d.suitable ? "" : (" - cannot run Bounce: " + d.unsuitableReason).c_str());

  std::unique_ptr<gpu::Context> contextOwner = openContext(options.gpu);
  const gpu::Context& context = *contextOwner;
  const VkPhysicalDeviceLimits& limits = context.properties().limits;
  std::printf("\nselected: %d: %s\n", context.deviceInfo().index, context.deviceInfo().name.c_str());
  std::printf("  max image size          %u\n", limits.maxImageDimension2D);
  std::printf("  max workgroup size      %u x %u x %u (%u invocations)\n", limits.maxComputeWorkGroupSize[0],
              limits.maxComputeWorkGroupSize[1], limits.maxComputeWorkGroupSize[2],
              limits.maxComputeWorkGroupInvocations);
  std::printf("  max shared memory       %u bytes\n", limits.maxComputeSharedMemorySize);
  std::printf("  max push constants      %u bytes\n", limits.maxPushConstantsSize);
  std::printf("  max storage buffer      %u bytes\n", limits.maxStorageBufferRange);
  std::printf("  timestamp period        %.3f ns\n", limits.timestampPeriod);
  std::printf("  validation              %s\n", context.validationEnabled() ? "on (with synchronization)" : "off");
  return validationExitCode(context);
}

}  // namespace bounce::app
