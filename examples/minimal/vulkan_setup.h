// What any Vulkan engine already has, kept apart from main.cpp so that the
// example shows the GI library's part: an instance (with validation and
// synchronization validation when the layer is installed), a device with what
// the library needs (Vulkan 1.3, synchronization2, maintenance4,
// VK_KHR_push_descriptor), images whose layout and last use it tracks, uploads
// recorded as copies, and a readback.
#pragma once

#include <bounce/gi.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

inline void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS) throw std::runtime_error(std::string(what) + " failed: VkResult " + std::to_string(result));
}

// A host-visible buffer (staging data for uploads, readbacks).
struct HostBuffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;
};

// An image of the engine, with the state its last use left it in.
struct GpuImage {
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  std::uint32_t width = 0, height = 0;
  HostBuffer staging;  // what recordUpload copies in; none: cleared to black
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags2 stage = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 access = VK_ACCESS_2_NONE;

  bounce::gi::ImageRef ref() const { return {image, view, format, width, height, 1, layout, stage, access}; }
};

class Vulkan {
 public:
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t queueFamily = 0;
  bool debugUtils = false;

  int messages() const { return messages_; }
  bool validated() const { return validated_; }

  GpuImage& image(VkFormat format, std::uint32_t width, std::uint32_t height) {
    auto made = std::make_unique<GpuImage>();
    made->format = format;
    made->width = width;
    made->height = height;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {width, height, 1};
    info.mipLevels = info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    check(vkCreateImage(device, &info, nullptr, &made->image), "vkCreateImage");
    VkMemoryRequirements needs;
    vkGetImageMemoryRequirements(device, made->image, &needs);
    made->memory = allocate(needs, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    check(vkBindImageMemory(device, made->image, made->memory, 0), "vkBindImageMemory");
    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = made->image;
    viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
    viewInfo.format = format;
    viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    check(vkCreateImageView(device, &viewInfo, nullptr, &made->view), "vkCreateImageView");
    images_.push_back(std::move(made));
    return *images_.back();
  }

  void upload(GpuImage& image, const void* data, std::size_t bytes) {
    if (bytes == 0) return;
    image.staging = hostBuffer(bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
    std::memcpy(image.staging.mapped, data, bytes);
  }

  // A transfer write of the image (its staging data, or black), after a
  // barrier from its last use.
  void recordUpload(VkCommandBuffer cmd, GpuImage& image) {
    const VkPipelineStageFlags2 stage = image.staging.buffer ? VK_PIPELINE_STAGE_2_COPY_BIT : VK_PIPELINE_STAGE_2_CLEAR_BIT;
    barrier(cmd, image.image, image.layout, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, image.stage, image.access, stage,
            VK_ACCESS_2_TRANSFER_WRITE_BIT);
    if (image.staging.buffer) {
      VkBufferImageCopy region{};
      region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      region.imageExtent = {image.width, image.height, 1};
      vkCmdCopyBufferToImage(cmd, image.staging.buffer, image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    } else {
      const VkClearColorValue black{};
      const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
      vkCmdClearColorImage(cmd, image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &black, 1, &range);
    }
    image.layout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    image.stage = stage;
    image.access = VK_ACCESS_2_TRANSFER_WRITE_BIT;
  }

  VkCommandBuffer begin() {
    VkCommandBufferBeginInfo info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkResetCommandBuffer(commandBuffer_, 0), "vkResetCommandBuffer");
    check(vkBeginCommandBuffer(commandBuffer_, &info), "vkBeginCommandBuffer");
    return commandBuffer_;
  }

  void submitAndWait(VkCommandBuffer cmd) {
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    check(vkResetFences(device, 1, &fence_), "vkResetFences");
    check(vkQueueSubmit(queue, 1, &submit, fence_), "vkQueueSubmit");
    check(vkWaitForFences(device, 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  }

  // Copies `count` 16-bit values of an image the library left in GENERAL
  // after a compute write (LibraryImage's contract) to the host, and gives
  // it back in GENERAL with the copy done before any later compute shader.
  std::vector<std::uint16_t> readback(const bounce::gi::ImageRef& image, std::size_t count) {
    HostBuffer buffer = hostBuffer(count * 2, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    VkCommandBuffer cmd = begin();
    barrier(cmd, image.image, image.layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image.stage, image.access,
            VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {image.width, image.height, 1};
    vkCmdCopyImageToBuffer(cmd, image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer.buffer, 1, &region);
    // Back to GENERAL, the transition visible to every way the library's
    // passes read and write their images (LibraryImage's contract).
    barrier(cmd, image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image.layout, VK_PIPELINE_STAGE_2_COPY_BIT,
            VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, bounce::gi::kLibraryImageAccess);
    submitAndWait(cmd);
    std::vector<std::uint16_t> values(count);
    std::memcpy(values.data(), buffer.mapped, count * 2);
    return values;
  }

  Vulkan() { open(); }
  Vulkan(const Vulkan&) = delete;
  Vulkan& operator=(const Vulkan&) = delete;
  void close();

 private:
  void open();
  VkDeviceMemory allocate(const VkMemoryRequirements& needs, VkMemoryPropertyFlags properties) {
    VkPhysicalDeviceMemoryProperties memory;
    vkGetPhysicalDeviceMemoryProperties(physicalDevice, &memory);
    for (std::uint32_t i = 0; i < memory.memoryTypeCount; ++i)
      if ((needs.memoryTypeBits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & properties) == properties) {
        VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        info.allocationSize = needs.size;
        info.memoryTypeIndex = i;
        VkDeviceMemory allocated;
        check(vkAllocateMemory(device, &info, nullptr, &allocated), "vkAllocateMemory");
        memories_.push_back(allocated);
        return allocated;
      }
    throw std::runtime_error("no suitable memory type");
  }

  HostBuffer hostBuffer(std::size_t bytes, VkBufferUsageFlags usage) {
    HostBuffer made;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = bytes;
    info.usage = usage;
    check(vkCreateBuffer(device, &info, nullptr, &made.buffer), "vkCreateBuffer");
    buffers_.push_back(made.buffer);
    VkMemoryRequirements needs;
    vkGetBufferMemoryRequirements(device, made.buffer, &needs);
    made.memory = allocate(needs, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    check(vkBindBufferMemory(device, made.buffer, made.memory, 0), "vkBindBufferMemory");
    check(vkMapMemory(device, made.memory, 0, bytes, 0, &made.mapped), "vkMapMemory");
    return made;
  }

  static void barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                      VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
                      VkAccessFlags2 dstAccess) {
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.srcStageMask = srcStage;
    b.srcAccessMask = srcAccess;
    b.dstStageMask = dstStage;
    b.dstAccessMask = dstAccess;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dependency.imageMemoryBarrierCount = 1;
    dependency.pImageMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &dependency);
  }

  static VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                  VkDebugUtilsMessageTypeFlagsEXT,
                                                  const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    std::fprintf(stderr, "validation: %s\n", data->pMessage);
    ++static_cast<Vulkan*>(user)->messages_;
    return VK_FALSE;
  }

  std::vector<std::unique_ptr<GpuImage>> images_;
  std::vector<VkBuffer> buffers_;
  std::vector<VkDeviceMemory> memories_;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer commandBuffer_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  int messages_ = 0;
  bool validated_ = false;
};

inline bool hasLayer(const char* name) {
  std::uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  for (const VkLayerProperties& layer : layers)
    if (std::strcmp(layer.layerName, name) == 0) return true;
  return false;
}

inline void Vulkan::open() {
  Vulkan& vk = *this;
  vk.validated_ = hasLayer("VK_LAYER_KHRONOS_validation");
  vk.debugUtils = true;
  const char* layers[] = {"VK_LAYER_KHRONOS_validation"};
  const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME};
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "bounce minimal example";
  app.apiVersion = VK_API_VERSION_1_3;
  const VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;
  VkDebugUtilsMessengerCreateInfoEXT messengerInfo{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messengerInfo.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
  messengerInfo.pfnUserCallback = &Vulkan::onMessage;
  messengerInfo.pUserData = this;
  features.pNext = &messengerInfo;  // messages of vkCreateInstance itself too
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pNext = vk.validated_ ? &features : nullptr;
  info.pApplicationInfo = &app;
  info.enabledLayerCount = vk.validated_ ? 1 : 0;
  info.ppEnabledLayerNames = layers;
  info.enabledExtensionCount = 1;
  info.ppEnabledExtensionNames = extensions;
  check(vkCreateInstance(&info, nullptr, &vk.instance), "vkCreateInstance");
  if (vk.validated_) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(vk.instance, "vkCreateDebugUtilsMessengerEXT"));
    check(create(vk.instance, &messengerInfo, nullptr, &vk.messenger_), "vkCreateDebugUtilsMessengerEXT");
  }

  std::uint32_t count = 1;
  VkResult listed = vkEnumeratePhysicalDevices(vk.instance, &count, &vk.physicalDevice);
  if ((listed != VK_SUCCESS && listed != VK_INCOMPLETE) || count == 0)
    throw std::runtime_error("no Vulkan device");
  std::vector<VkQueueFamilyProperties> families(8);
  count = 8;
  vkGetPhysicalDeviceQueueFamilyProperties(vk.physicalDevice, &count, families.data());
  while (vk.queueFamily < count && !(families[vk.queueFamily].queueFlags & VK_QUEUE_COMPUTE_BIT)) ++vk.queueFamily;

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queueInfo.queueFamilyIndex = vk.queueFamily;
  queueInfo.queueCount = 1;
  queueInfo.pQueuePriorities = &priority;
  VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  features13.synchronization2 = VK_TRUE;
  features13.maintenance4 = VK_TRUE;
  const char* deviceExtensions[] = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
  VkDeviceCreateInfo deviceInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  deviceInfo.pNext = &features13;
  deviceInfo.queueCreateInfoCount = 1;
  deviceInfo.pQueueCreateInfos = &queueInfo;
  deviceInfo.enabledExtensionCount = 1;
  deviceInfo.ppEnabledExtensionNames = deviceExtensions;
  check(vkCreateDevice(vk.physicalDevice, &deviceInfo, nullptr, &vk.device), "vkCreateDevice");
  vkGetDeviceQueue(vk.device, vk.queueFamily, 0, &vk.queue);

  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  poolInfo.queueFamilyIndex = vk.queueFamily;
  check(vkCreateCommandPool(vk.device, &poolInfo, nullptr, &vk.pool_), "vkCreateCommandPool");
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = vk.pool_;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(vk.device, &allocate, &vk.commandBuffer_), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  check(vkCreateFence(vk.device, &fenceInfo, nullptr, &vk.fence_), "vkCreateFence");
}

inline void Vulkan::close() {
  vkDeviceWaitIdle(device);
  for (const std::unique_ptr<GpuImage>& image : images_) {
    vkDestroyImageView(device, image->view, nullptr);
    vkDestroyImage(device, image->image, nullptr);
  }
  for (VkBuffer buffer : buffers_) vkDestroyBuffer(device, buffer, nullptr);
  for (VkDeviceMemory memory : memories_) vkFreeMemory(device, memory, nullptr);
  vkDestroyFence(device, fence_, nullptr);
  vkDestroyCommandPool(device, pool_, nullptr);
  vkDestroyDevice(device, nullptr);
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance, messenger_, nullptr);
  }
  vkDestroyInstance(instance, nullptr);
}
