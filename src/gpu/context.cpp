#include "gpu/context.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>

#include "gpu/error.h"
#include "gpu/recorder.h"

namespace bounce::gpu {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr const char* kNoDeviceHelp =
    "Install a GPU driver, or Mesa's CPU driver (lavapipe) for machines without a GPU: "
    "apt-get install mesa-vulkan-drivers";

bool hasInstanceExtension(const char* name) {
  std::uint32_t count = 0;
  vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateInstanceExtensionProperties(nullptr, &count, extensions.data());
  return std::any_of(extensions.begin(), extensions.end(),
                     [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

bool hasLayer(const char* name) {
  std::uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  return std::any_of(layers.begin(), layers.end(),
                     [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

VkInstance createInstance(bool validation, bool debugUtils, void* pNext,
                          const std::vector<std::string>& extraExtensions = {}) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "bounce";
  app.pEngineName = "bounce";
  app.apiVersion = VK_API_VERSION_1_3;

  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  if (validation) {
    if (!hasLayer(kValidationLayer))
      throw GpuError(std::string("validation was asked for but ") + kValidationLayer +
                     " is not installed: apt-get install vulkan-validationlayers");
    layers.push_back(kValidationLayer);
  }
  if (debugUtils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  for (const std::string& name : extraExtensions) {
    if (!hasInstanceExtension(name.c_str()))
      throw GpuError("the Vulkan loader does not offer the instance extension " + name);
    extensions.push_back(name.c_str());
  }

  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pNext = pNext;
  info.pApplicationInfo = &app;
  info.enabledLayerCount = std::uint32_t(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = std::uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  VkResult result = vkCreateInstance(&info, nullptr, &instance);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw GpuError(std::string("no Vulkan driver found (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER). ") +
                   kNoDeviceHelp);
  check(result, "vkCreateInstance");
  return instance;
}

const char* deviceTypeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

int typeRank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 3;
    default:
      return 4;
  }
}

// The queue family Bounce uses: compute with timestamps; a universal
// (graphics+compute) family is preferred because it is the fast path on most
// drivers and lets an engine share its queue.
// `usable`, when given, must also accept the family (a window's present test).
std::optional<std::uint32_t> chooseQueueFamily(VkPhysicalDevice device,
                                               const std::function<bool(std::uint32_t)>& usable = {}) {
  std::uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  std::optional<std::uint32_t> best;
  for (std::uint32_t i = 0; i < count; ++i) {
    const auto& f = families[i];
    if (!(f.queueFlags & VK_QUEUE_COMPUTE_BIT) || f.timestampValidBits == 0) continue;
    if (usable && !usable(i)) continue;
    if (!best || (f.queueFlags & VK_QUEUE_GRAPHICS_BIT)) best = i;
    if (f.queueFlags & VK_QUEUE_GRAPHICS_BIT) break;
  }
  return best;
}

bool hasDeviceExtension(VkPhysicalDevice device, const char* name) {
  std::uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data());
  return std::any_of(extensions.begin(), extensions.end(),
                     [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

DeviceInfo describe(VkPhysicalDevice device, int index) {
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES, &driver};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &subgroup};
  vkGetPhysicalDeviceProperties2(device, &props);
  VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features13};
  vkGetPhysicalDeviceFeatures2(device, &features);

  DeviceInfo info;
  info.index = index;
  info.name = props.properties.deviceName;
  info.type = deviceTypeName(props.properties.deviceType);
  info.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  info.apiVersion = props.properties.apiVersion;
  if (VK_API_VERSION_MAJOR(info.apiVersion) == 1 && VK_API_VERSION_MINOR(info.apiVersion) < 3)
    info.unsuitableReason = "needs Vulkan 1.3, device has " + versionString(info.apiVersion);
  else if (!features13.synchronization2 || !features13.maintenance4)
    info.unsuitableReason = "no synchronization2 or maintenance4 feature";
  else if (!(subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
           !(subgroup.supportedOperations & VK_SUBGROUP_FEATURE_BALLOT_BIT))
    // The GI library counts world rays with one atomic per subgroup (gi/world_ray_count.glsl).
    info.unsuitableReason = "no subgroup ballot in compute shaders";
  else if (!hasDeviceExtension(device, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME))
    info.unsuitableReason = "no VK_KHR_push_descriptor";
  else if (!chooseQueueFamily(device))
    info.unsuitableReason = "no compute queue with timestamps";
  info.suitable = info.unsuitableReason.empty();
  return info;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
  std::uint32_t count = 0;
  check(vkEnumeratePhysicalDevices(instance, &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  check(vkEnumeratePhysicalDevices(instance, &count, devices.data()), "vkEnumeratePhysicalDevices");
  return devices;
}

std::optional<int> deviceIndexFromEnvironment() {
  const char* value = std::getenv("BOUNCE_DEVICE");
  if (!value || !*value) return std::nullopt;
  char* end = nullptr;
  long index = std::strtol(value, &end, 10);
  if (*end != '\0' || index < 0) throw GpuError(std::string("BOUNCE_DEVICE='") + value + "' is not a device index");
  return int(index);
}

}  // namespace

std::string versionString(std::uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

std::vector<DeviceInfo> Context::enumerateDevices() {
  VkInstance instance = createInstance(false, false, nullptr);
  std::vector<DeviceInfo> infos;
  try {
    std::vector<VkPhysicalDevice> devices = physicalDevices(instance);
    for (std::size_t i = 0; i < devices.size(); ++i) infos.push_back(describe(devices[i], int(i)));
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
  vkDestroyInstance(instance, nullptr);
  return infos;
}

Context::Context(const ContextOptions& options)
    : validation_(options.validation), printMessages_(options.printValidationMessages) {
  debugUtils_ = hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  if (validation_ && !debugUtils_)
    throw GpuError("validation needs VK_EXT_debug_utils, which this Vulkan loader does not offer");

  // Synchronization validation is off by default in the layer; it is what
  // catches a missing barrier, so every validated run turns it on.
  VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;
  VkDebugUtilsMessengerCreateInfoEXT messengerInfo{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messengerInfo.messageSeverity =
      VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT |
                              VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
  messengerInfo.pfnUserCallback = &Context::onDebugMessage;
  messengerInfo.pUserData = this;
  // Chained into instance creation too, so messages from vkCreateInstance
  // itself are caught.
  features.pNext = &messengerInfo;

  instance_ = createInstance(validation_, debugUtils_, validation_ ? &features : nullptr, options.instanceExtensions);
  try {
    if (validation_) {
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      check(create(instance_, &messengerInfo, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
    }

    std::vector<VkPhysicalDevice> devices = physicalDevices(instance_);
    if (devices.empty()) throw GpuError(std::string("no Vulkan device found. ") + kNoDeviceHelp);
    std::vector<DeviceInfo> infos;
    // A window's family test, bound to one device.
    const auto usableFamily = [&](VkPhysicalDevice device) -> std::function<bool(std::uint32_t)> {
      if (!options.queueFamilyUsable) return {};
      return [&, device](std::uint32_t family) { return options.queueFamilyUsable(instance_, device, family); };
    };
    for (std::size_t i = 0; i < devices.size(); ++i) {
      DeviceInfo info = describe(devices[i], int(i));
      for (const std::string& name : options.deviceExtensions)
        if (info.suitable && !hasDeviceExtension(devices[i], name.c_str())) info.unsuitableReason = "no " + name;
      if (info.suitable && info.unsuitableReason.empty() && !chooseQueueFamily(devices[i], usableFamily(devices[i])))
        info.unsuitableReason = "no compute queue family that can present to the window";
      info.suitable = info.unsuitableReason.empty();
      infos.push_back(std::move(info));
    }
    // One line, like every error: "0: NAME (TYPE); 1: ...".
    auto listing = [&] {
      std::string text;
      for (const DeviceInfo& d : infos)
        text += std::string(text.empty() ? " " : "; ") + std::to_string(d.index) + ": " + d.name + " (" + d.type + ")" +
                (d.suitable ? "" : " - unsuitable: " + d.unsuitableReason);
      return text;
    };

    std::optional<int> wanted = options.deviceIndex ? options.deviceIndex : deviceIndexFromEnvironment();
    int chosen = -1;
    if (wanted) {
      if (*wanted < 0 || *wanted >= int(devices.size()))
        throw GpuError("device " + std::to_string(*wanted) + " does not exist; devices:" + listing());
      if (!infos[*wanted].suitable)
        throw GpuError("device " + std::to_string(*wanted) + " cannot run Bounce: " + infos[*wanted].unsuitableReason);
      chosen = *wanted;
    } else {
      for (std::size_t i = 0; i < devices.size(); ++i) {
        if (!infos[i].suitable) continue;
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(devices[i], &p);
        VkPhysicalDeviceProperties best;
        if (chosen >= 0) vkGetPhysicalDeviceProperties(devices[chosen], &best);
        if (chosen < 0 || typeRank(p.deviceType) < typeRank(best.deviceType)) chosen = int(i);
      }
      if (chosen < 0) throw GpuError("no Vulkan device can run Bounce; devices:" + listing());
    }
    physicalDevice_ = devices[chosen];
    deviceInfo_ = infos[chosen];
    queueFamily_ = *chooseQueueFamily(physicalDevice_, usableFamily(physicalDevice_));
    timestampValidBits_ = 64;  // chooseQueueFamily takes only families with timestamps

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = queueFamily_;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;
    VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    features13.synchronization2 = VK_TRUE;
    // Required by Vulkan 1.3, and needed because glslc states workgroup
    // sizes as LocalSizeId when it targets 1.3.
    features13.maintenance4 = VK_TRUE;
    VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    features12.pNext = &features13;
    std::vector<const char*> deviceExtensions = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    for (const std::string& name : options.deviceExtensions) deviceExtensions.push_back(name.c_str());
    VkDeviceCreateInfo deviceCreate{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    deviceCreate.pNext = &features12;
    deviceCreate.queueCreateInfoCount = 1;
    deviceCreate.pQueueCreateInfos = &queueInfo;
    deviceCreate.enabledExtensionCount = std::uint32_t(deviceExtensions.size());
    deviceCreate.ppEnabledExtensionNames = deviceExtensions.data();
    check(vkCreateDevice(physicalDevice_, &deviceCreate, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
    initialiseDeviceObjects(options.constantsInStorageBuffers);
  } catch (...) {
    release();
    throw;
  }
}

Context::Context(const ExternalDevice& external) : ownsDevice_(false) {
  if (!external.instance || !external.physicalDevice || !external.device)
    throw GpuError("the device to use is missing its instance, physical device or device handle");
  instance_ = external.instance;
  physicalDevice_ = external.physicalDevice;
  device_ = external.device;
  queue_ = external.queue;
  queueFamily_ = external.queueFamily;
  debugUtils_ = external.debugUtils;
  deviceInfo_ = describe(physicalDevice_, -1);
  if (VK_API_VERSION_MAJOR(deviceInfo_.apiVersion) == 1 && VK_API_VERSION_MINOR(deviceInfo_.apiVersion) < 3)
    throw GpuError("the device is Vulkan " + versionString(deviceInfo_.apiVersion) + "; Bounce needs 1.3");
  std::uint32_t families = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice_, &families, nullptr);
  if (queueFamily_ >= families)
    throw GpuError("queue family " + std::to_string(queueFamily_) + " does not exist on the device");
  std::vector<VkQueueFamilyProperties> familyProperties(families);
  vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice_, &families, familyProperties.data());
  if (!(familyProperties[queueFamily_].queueFlags & VK_QUEUE_COMPUTE_BIT))
    throw GpuError("queue family " + std::to_string(queueFamily_) + " cannot run compute shaders");
  timestampValidBits_ = familyProperties[queueFamily_].timestampValidBits;
  try {
    initialiseDeviceObjects(external.constantsInStorageBuffers);
  } catch (...) {
    release();
    throw;
  }
}

void Context::initialiseDeviceObjects(std::optional<bool> constantsInStorageBuffers) {
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES,
                                                      &driver};
  VkPhysicalDeviceProperties2 driverProperties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &maintenance3};
  vkGetPhysicalDeviceProperties2(physicalDevice_, &driverProperties);
  maxAllocationBytes_ = maintenance3.maxMemoryAllocationSize;
  constantsInStorageBuffers_ = constantsInStorageBuffers.value_or(driver.driverID == VK_DRIVER_ID_MESA_LLVMPIPE);
  // The GI library opens its context on the engine's device and cannot be
  // given the option; the variable lets one compare the variants there too.
  if (!constantsInStorageBuffers) {
    const char* forced = std::getenv("BOUNCE_CONSTANT_BLOCKS");
    if (forced && std::string_view(forced) == "storage") constantsInStorageBuffers_ = true;
    if (forced && std::string_view(forced) == "uniform") constantsInStorageBuffers_ = false;
  }
  vkGetPhysicalDeviceProperties(physicalDevice_, &properties_);
  vkGetPhysicalDeviceMemoryProperties(physicalDevice_, &memoryProperties_);

  cmdPushDescriptorSet =
      reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));
  if (!cmdPushDescriptorSet)
    throw GpuError("the device was created without VK_KHR_push_descriptor, which Bounce records its bindings with");
  if (debugUtils_) {
    cmdBeginDebugLabel = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance_, "vkCmdBeginDebugUtilsLabelEXT"));
    cmdEndDebugLabel = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance_, "vkCmdEndDebugUtilsLabelEXT"));
    setObjectName = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
  }

  if (queue_) {
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
    poolInfo.queueFamilyIndex = queueFamily_;
    check(vkCreateCommandPool(device_, &poolInfo, nullptr, &setupPool_), "vkCreateCommandPool");
  }

  VkSamplerCreateInfo sampler{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  sampler.addressModeU = sampler.addressModeV = sampler.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  sampler.maxLod = VK_LOD_CLAMP_NONE;
  sampler.magFilter = sampler.minFilter = VK_FILTER_LINEAR;
  sampler.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  check(vkCreateSampler(device_, &sampler, nullptr, &linearSampler_), "vkCreateSampler");
  sampler.magFilter = sampler.minFilter = VK_FILTER_NEAREST;
  sampler.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  check(vkCreateSampler(device_, &sampler, nullptr, &nearestSampler_), "vkCreateSampler");
  // Texel coordinates (unnormalised): the same position filters the same
  // whatever the image's size (Vulkan's rules: one level, lod 0, no mips).
  sampler.magFilter = sampler.minFilter = VK_FILTER_LINEAR;
  sampler.unnormalizedCoordinates = VK_TRUE;
  sampler.maxLod = 0.0f;
  check(vkCreateSampler(device_, &sampler, nullptr, &texelLinearSampler_), "vkCreateSampler");
}

Context::~Context() { release(); }

void Context::release() {
  if (device_) {
    // Another's device may be busy with its own work; its owner waits for
    // what concerns this context before destroying it (docs/integration.md).
    if (ownsDevice_) vkDeviceWaitIdle(device_);
    if (linearSampler_) vkDestroySampler(device_, linearSampler_, nullptr);
    if (nearestSampler_) vkDestroySampler(device_, nearestSampler_, nullptr);
    if (texelLinearSampler_) vkDestroySampler(device_, texelLinearSampler_, nullptr);
    if (setupPool_) vkDestroyCommandPool(device_, setupPool_, nullptr);
    if (ownsDevice_) vkDestroyDevice(device_, nullptr);
    device_ = VK_NULL_HANDLE;
  }
  if (!ownsDevice_) {
    instance_ = VK_NULL_HANDLE;
    return;
  }
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance_, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance_) {
    vkDestroyInstance(instance_, nullptr);
    instance_ = VK_NULL_HANDLE;
  }
}

VkBool32 Context::onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
                                 const VkDebugUtilsMessengerCallbackDataEXT* data, void* self) {
  auto* context = static_cast<Context*>(self);
  // General messages at warning level come from the loader about drivers it
  // skipped, not from Bounce's use of Vulkan; only its errors count.
  if (types == VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT && severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)
    return VK_FALSE;
  std::string text = std::string(severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning") +
                     " [" + (data->pMessageIdName ? data->pMessageIdName : "") + "] " +
                     (data->pMessage ? data->pMessage : "");
  if (context->printMessages_) std::fprintf(stderr, "vulkan validation %s\n", text.c_str());
  std::lock_guard lock(context->messagesMutex_);
  context->messages_.push_back(std::move(text));
  return VK_FALSE;
}

std::vector<std::string> Context::validationMessages() const {
  std::lock_guard lock(messagesMutex_);
  return messages_;
}

void Context::clearValidationMessages() {
  std::lock_guard lock(messagesMutex_);
  messages_.clear();
}

std::uint32_t Context::findMemoryType(std::uint32_t typeBits, VkMemoryPropertyFlags required,
                                      VkMemoryPropertyFlags preferred) const {
  std::optional<std::uint32_t> fallback;
  for (std::uint32_t i = 0; i < memoryProperties_.memoryTypeCount; ++i) {
    if (!(typeBits & (1u << i))) continue;
    VkMemoryPropertyFlags flags = memoryProperties_.memoryTypes[i].propertyFlags;
    if ((flags & required) != required) continue;
    if ((flags & preferred) == preferred) return i;
    if (!fallback) fallback = i;
  }
  if (!fallback) throw GpuError("no Vulkan memory type with the needed properties");
  return *fallback;
}

VkDeviceSize Context::largestDeviceLocalHeap() const {
  VkDeviceSize largest = 0;
  for (std::uint32_t i = 0; i < memoryProperties_.memoryHeapCount; ++i)
    if (memoryProperties_.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      largest = std::max(largest, memoryProperties_.memoryHeaps[i].size);
  return largest;
}

void Context::requireDeviceMemory(std::uint64_t bytes, const std::string& what) const {
  const VkDeviceSize heap = largestDeviceLocalHeap();
  if (heap == 0 || bytes <= heap) return;
  constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
  char numbers[160];
  std::snprintf(numbers, sizeof numbers, " needs at least %.1f GiB of device memory for its images; %s has %.1f GiB",
                double(bytes) / kGiB, deviceInfo().name.c_str(), double(heap) / kGiB);
  throw GpuError(what + numbers + ": render smaller (--width, --height) or choose another --device");
}

void Context::trackAllocation(std::uint32_t memoryType, std::int64_t bytes) {
  const std::uint32_t heap = memoryProperties_.memoryTypes[memoryType].heapIndex;
  if (memoryProperties_.memoryHeaps[heap].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
    deviceLocalBytes_ += VkDeviceSize(bytes);  // unsigned wrap-around makes a negative delta subtract
}

void Context::submitAndWait(const std::function<void(Recorder&)>& record) {
  if (!setupPool_) throw GpuError("submitAndWait needs a queue, and this context was given none");
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = setupPool_;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  check(vkAllocateCommandBuffers(device_, &alloc, &cmd), "vkAllocateCommandBuffers");
  VkFence fence = VK_NULL_HANDLE;
  std::vector<Recorder::CompletionHandler> handlers;
  std::vector<CapturedStage>* captures = nullptr;
  try {
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
    Recorder recorder(*this, cmd);
    record(recorder);
    handlers = recorder.takeCompletionHandlers();
    captures = recorder.captureSink();
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    check(vkCreateFence(device_, &fenceInfo, nullptr, &fence), "vkCreateFence");
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    check(vkQueueSubmit(queue_, 1, &submit, fence), "vkQueueSubmit");
    check(vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  } catch (...) {
    if (fence) vkDestroyFence(device_, fence, nullptr);
    vkFreeCommandBuffers(device_, setupPool_, 1, &cmd);
    throw;
  }
  vkDestroyFence(device_, fence, nullptr);
  vkFreeCommandBuffers(device_, setupPool_, 1, &cmd);
  for (Recorder::CompletionHandler& handler : handlers) handler(nullptr, captures);
}

void Context::nameObject(VkObjectType type, std::uint64_t handle, const std::string& name) const {
  if (!setObjectName || !device_) return;
  VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name.c_str();
  setObjectName(device_, &info);
}

}  // namespace bounce::gpu
