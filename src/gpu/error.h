// Errors of the gpu layer. Every failure becomes a GpuError whose message says
// what was being done and, for Vulkan calls, which VkResult came back.
#pragma once

#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

namespace bounce::gpu {

class GpuError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

const char* resultName(VkResult result);

// Throws GpuError("<what>: <VkResult name>") unless result is VK_SUCCESS.
void check(VkResult result, const char* what);

}  // namespace bounce::gpu
