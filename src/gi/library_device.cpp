#include "gi/library_device.h"

#include <string>

#include "gpu/error.h"

namespace bounce::gi {

std::unique_ptr<gpu::Context> openLibraryContext(const Device& device) {
  const auto missing = [](const char* handle) {
    return Error(std::string("gi: Device::") + handle + " is VK_NULL_HANDLE; give the engine's");
  };
  if (device.instance == VK_NULL_HANDLE) throw missing("instance (VkInstance)");
  if (device.physicalDevice == VK_NULL_HANDLE) throw missing("physicalDevice (VkPhysicalDevice)");
  if (device.device == VK_NULL_HANDLE) throw missing("device (VkDevice)");
  try {
    return std::make_unique<gpu::Context>(gpu::ExternalDevice{.instance = device.instance,
                                                              .physicalDevice = device.physicalDevice,
                                                              .device = device.device,
                                                              .queueFamily = device.queueFamily,
                                                              .debugUtils = device.debugUtils});
  } catch (const gpu::GpuError& e) {
    throw Error(std::string("gi: ") + e.what());
  }
}

}  // namespace bounce::gi
