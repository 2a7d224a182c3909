// The Vulkan instance, the chosen device and its compute queue, and the
// validation layer's message log. One Context per process is the normal case.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace bounce::gpu {

class Recorder;

struct ContextOptions {
  // Enable the Khronos validation layer with synchronization validation.
  // Every message is recorded (validationMessages()) and printed to stderr.
  bool validation = false;
  // Index into enumerateDevices(); empty = the environment variable
  // BOUNCE_DEVICE if set, else the best device (discrete GPU first, lavapipe last).
  std::optional<int> deviceIndex;
  // Print validation messages to stderr as they arrive (tests turn this off
  // and assert on the log instead).
  bool printValidationMessages = true;
  // Which variant of the shaders to run (shaders/gpu/constant_block.glsl):
  // constant blocks as read-only storage buffers, or as uniform blocks.
  // Empty = the environment variable BOUNCE_CONSTANT_BLOCKS (storage or
  // uniform) if set, else storage buffers on lavapipe, uniform blocks elsewhere.
  std::optional<bool> constantsInStorageBuffers;
  // What a window needs besides (bounce view): instance extensions (the
  // window system's surface ones), device extensions (VK_KHR_swapchain), and
  // which queue families can serve it (present to the window's surface).
  // A device without the extensions, or without a family that passes the
  // test, cannot be chosen.
  std::vector<std::string> instanceExtensions;
  std::vector<std::string> deviceExtensions;
  std::function<bool(VkInstance, VkPhysicalDevice, std::uint32_t family)> queueFamilyUsable;
};

// A device someone else made (an engine's): the context uses it and
// destroys nothing of it. It must be Vulkan 1.3 with synchronization2 and
// maintenance4 on and VK_KHR_push_descriptor enabled.
struct ExternalDevice {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  std::uint32_t queueFamily = 0;
  // A queue of that family for submitAndWait (uploads, readbacks); without
  // one, submitAndWait throws and all work goes into the owner's command buffers.
  VkQueue queue = VK_NULL_HANDLE;
  bool debugUtils = false;  // VK_EXT_debug_utils is enabled on the instance: name objects, label passes
  // As ContextOptions::constantsInStorageBuffers.
  std::optional<bool> constantsInStorageBuffers;
};

struct DeviceInfo {
  int index = 0;
  std::string name;
  std::string type;    // "discrete GPU", "integrated GPU", "virtual GPU", "CPU", "other"
  std::string driver;  // driver name and version
  std::uint32_t apiVersion = 0;
  bool suitable = false;
  std::string unsuitableReason;  // why it cannot run Bounce, when !suitable
};

std::string versionString(std::uint32_t apiVersion);

class Context {
 public:
  // Creates its own instance and device (and destroys them).
  explicit Context(const ContextOptions& options = {});
  // Works on another's device; throws GpuError when the device lacks what
  // Bounce needs (VK_KHR_push_descriptor, Vulkan 1.3).
  explicit Context(const ExternalDevice& device);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Every Vulkan device on this machine, suitable or not (creates a
  // throw-away instance; throws GpuError when Vulkan itself is missing).
  static std::vector<DeviceInfo> enumerateDevices();

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physicalDevice_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  std::uint32_t queueFamily() const { return queueFamily_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  // The largest single vkAllocateMemory the device promises (Vulkan 1.1's
  // maxMemoryAllocationSize, at least 1 GiB).
  VkDeviceSize maxAllocationBytes() const { return maxAllocationBytes_; }
  const DeviceInfo& deviceInfo() const { return deviceInfo_; }
  double timestampPeriodNs() const { return properties_.limits.timestampPeriod; }
  // Whether the queue family writes timestamps (a context of its own picks one that does).
  bool hasTimestamps() const { return timestampValidBits_ > 0; }
  bool validationEnabled() const { return validation_; }
  // Whether passes run the shader variant whose constant blocks are storage
  // buffers (ContextOptions::constantsInStorageBuffers).
  bool constantsInStorageBuffers() const { return constantsInStorageBuffers_; }
  bool debugLabelsAvailable() const { return debugUtils_; }

  // Validation messages (warnings and errors) received so far.
  std::vector<std::string> validationMessages() const;
  void clearValidationMessages();

  // Memory type index for the requirements; throws GpuError if none fits.
  std::uint32_t findMemoryType(std::uint32_t typeBits, VkMemoryPropertyFlags required,
                               VkMemoryPropertyFlags preferred = 0) const;

  // Device-local memory: the bytes this context's buffers and images hold
  // now, and the size of the largest device-local heap (on lavapipe, a share
  // of the machine's RAM), to refuse work that cannot fit before it starts.
  VkDeviceSize deviceLocalBytesInUse() const { return deviceLocalBytes_; }
  VkDeviceSize largestDeviceLocalHeap() const;
  // Before making a frame's images: throws GpuError when `bytes` (an
  // estimate of what they will hold, `what` saying of what: "a 640x360
  // frame with GI") is more than the largest device-local heap, with both
  // numbers, so that nothing is allocated for work that cannot fit.
  void requireDeviceMemory(std::uint64_t bytes, const std::string& what) const;
  // Called by Buffer and Image for each allocation (bytes > 0) and its release (bytes < 0).
  void trackAllocation(std::uint32_t memoryType, std::int64_t bytes);

  // Records work with `record` into a fresh command buffer, submits it and
  // waits. For uploads, readbacks and set-up; never for per-frame work.
  void submitAndWait(const std::function<void(Recorder&)>& record);

  VkSampler linearSampler() const { return linearSampler_; }
  VkSampler nearestSampler() const { return nearestSampler_; }
  // Bilinear at texel coordinates (unnormalised, clamped to the edge): a
  // filtered fetch whose result does not depend on the image's size (an
  // image made for a larger render size filters a render size's texels as
  // one made for it does). For single-level images, sampled at lod 0.
  VkSampler texelLinearSampler() const { return texelLinearSampler_; }

  // Extension entry points the layer needs.
  PFN_vkCmdPushDescriptorSetKHR cmdPushDescriptorSet = nullptr;
  PFN_vkCmdBeginDebugUtilsLabelEXT cmdBeginDebugLabel = nullptr;
  PFN_vkCmdEndDebugUtilsLabelEXT cmdEndDebugLabel = nullptr;
  PFN_vkSetDebugUtilsObjectNameEXT setObjectName = nullptr;

  // Gives a Vulkan object a debug name (shows in validation messages).
  void nameObject(VkObjectType type, std::uint64_t handle, const std::string& name) const;

 private:
  void release();
  // What both constructors do once the device exists: properties, entry
  // points, samplers, the set-up command pool.
  void initialiseDeviceObjects(std::optional<bool> constantsInStorageBuffers);
  static VkBool32 VKAPI_PTR onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                           VkDebugUtilsMessageTypeFlagsEXT types,
                                           const VkDebugUtilsMessengerCallbackDataEXT* data, void* self);

  bool validation_ = false;
  bool ownsDevice_ = true;
  std::uint32_t timestampValidBits_ = 0;
  bool constantsInStorageBuffers_ = false;
  bool printMessages_ = true;
  bool debugUtils_ = false;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memoryProperties_{};
  VkDeviceSize maxAllocationBytes_ = VkDeviceSize(1) << 30;
  DeviceInfo deviceInfo_;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queueFamily_ = 0;
  VkCommandPool setupPool_ = VK_NULL_HANDLE;
  VkSampler linearSampler_ = VK_NULL_HANDLE;
  VkSampler nearestSampler_ = VK_NULL_HANDLE;
  VkSampler texelLinearSampler_ = VK_NULL_HANDLE;
  std::atomic<VkDeviceSize> deviceLocalBytes_{0};
  mutable std::mutex messagesMutex_;
  std::vector<std::string> messages_;
};

}  // namespace bounce::gpu
