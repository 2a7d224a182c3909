#include "viewer/window.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include "gpu/error.h"
#include "gpu/recorder.h"
#include "io/image_io.h"

namespace bounce::viewer {
namespace {

// Command buffers of the present (blit + UI) in flight at once.
constexpr std::uint32_t kPresentSlots = 2;

// GLFW reports failures through a callback; the last one explains a
// failed call.
std::string lastGlfwError;
void onGlfwError(int, const char* description) { lastGlfwError = description ? description : "unknown error"; }

void check(VkResult result, const char* call) {
  if (result != VK_SUCCESS) throw gpu::GpuError(std::string(call) + " failed: " + std::to_string(int(result)));
}

void checkImGui(VkResult result) { check(result, "Dear ImGui's Vulkan backend"); }

}  // namespace

void handOverToWindow(gpu::Recorder& recorder, gpu::Image& image) {
  recorder.handOver(image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_READ_BIT);
  recorder.flush();
}

Window::Window(const WindowOptions& options) {
  try {
    if (options.headless) {
      context_ = std::make_unique<gpu::Context>(
          gpu::ContextOptions{.validation = options.validation, .deviceIndex = options.deviceIndex});
      extent_ = {options.width, options.height};
    } else {
      openWindow(options);
    }
    createCommandSlots();
    if (window_)
      createSwapchain();
    else
      createOffscreenTarget();
    initialiseImGui();
  } catch (...) {
    release();
    throw;
  }
}

// The GLFW window, a context that can present to it, and its surface.
void Window::openWindow(const WindowOptions& options) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit()) {
    const char* display = std::getenv("DISPLAY");
    throw std::runtime_error(
        "cannot open a window (" + lastGlfwError + ")" +
        (display && *display ? std::string(" on DISPLAY=") + display : std::string(": DISPLAY is not set")) +
        "; without a screen, run under xvfb-run (apt-get install xvfb)");
  }
  glfwReady_ = true;
  if (!glfwVulkanSupported())
    throw std::runtime_error("GLFW finds no Vulkan loader that can present to a window (" + lastGlfwError + ")");
  std::uint32_t count = 0;
  const char** required = glfwGetRequiredInstanceExtensions(&count);
  if (!required) throw std::runtime_error("the window system offers no Vulkan surface (" + lastGlfwError + ")");

  gpu::ContextOptions contextOptions;
  contextOptions.validation = options.validation;
  contextOptions.deviceIndex = options.deviceIndex;
  contextOptions.instanceExtensions.assign(required, required + count);
  contextOptions.deviceExtensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
  contextOptions.queueFamilyUsable = [](VkInstance instance, VkPhysicalDevice device, std::uint32_t family) {
    return glfwGetPhysicalDevicePresentationSupport(instance, device, family) == GLFW_TRUE;
  };
  context_ = std::make_unique<gpu::Context>(contextOptions);

  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  window_ = glfwCreateWindow(int(options.width), int(options.height), options.title.c_str(), nullptr, nullptr);
  if (!window_) throw std::runtime_error("cannot create a window: " + lastGlfwError);
  check(glfwCreateWindowSurface(context_->instance(), window_, nullptr, &surface_), "glfwCreateWindowSurface");
  VkBool32 supported = VK_FALSE;
  check(vkGetPhysicalDeviceSurfaceSupportKHR(context_->physicalDevice(), context_->queueFamily(), surface_, &supported),
        "vkGetPhysicalDeviceSurfaceSupportKHR");
  if (!supported) throw gpu::GpuError("the device's queue cannot present to this window");
}

Window::~Window() { release(); }

void Window::createCommandSlots() {
  const VkDevice device = context_->device();
  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  poolInfo.queueFamilyIndex = context_->queueFamily();
  check(vkCreateCommandPool(device, &poolInfo, nullptr, &commandPool_), "vkCreateCommandPool");
  if (context_->hasTimestamps()) {
    VkQueryPoolCreateInfo queries{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    queries.queryType = VK_QUERY_TYPE_TIMESTAMP;
    queries.queryCount = 2 * kPresentSlots;
    check(vkCreateQueryPool(device, &queries, nullptr, &timestamps_), "vkCreateQueryPool");
  }
  slots_.resize(kPresentSlots);
  for (Slot& slot : slots_) {
    VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    allocate.commandPool = commandPool_;
    allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocate.commandBufferCount = 1;
    check(vkAllocateCommandBuffers(device, &allocate, &slot.cmd), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    check(vkCreateFence(device, &fence, nullptr, &slot.fence), "vkCreateFence");
    VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    check(vkCreateSemaphore(device, &semaphore, nullptr, &slot.acquired), "vkCreateSemaphore");
  }
}

void Window::createOffscreenTarget() {
  const VkDevice device = context_->device();
  format_ = VK_FORMAT_R8G8B8A8_UNORM;
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format_;
  info.extent = {extent_.width, extent_.height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  check(vkCreateImage(device, &info, nullptr, &offscreen_), "vkCreateImage");
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(device, offscreen_, &requirements);
  VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  allocate.allocationSize = requirements.size;
  allocate.memoryTypeIndex = context_->findMemoryType(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  check(vkAllocateMemory(device, &allocate, nullptr, &offscreenMemory_), "vkAllocateMemory");
  check(vkBindImageMemory(device, offscreen_, offscreenMemory_, 0), "vkBindImageMemory");
  images_ = {offscreen_};
  canCapture_ = true;
  createRenderPassAndFramebuffers();
}

VkImageLayout Window::targetLayout() const {
  return window_ ? VK_IMAGE_LAYOUT_PRESENT_SRC_KHR : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
}

void Window::beginUiFrame() {
  if (window_) {
    glfwPollEvents();
    ImGui_ImplGlfw_NewFrame();
  } else {
    // No window, no input: the panels are laid out for the image's size.
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(float(extent_.width), float(extent_.height));
    io.DeltaTime = 1.0f / 60.0f;
  }
  ImGui_ImplVulkan_NewFrame();
  ImGui::NewFrame();
}

void Window::release() {
  if (context_) {
    vkDeviceWaitIdle(context_->device());
    if (imguiReady_) {
      ImGui_ImplVulkan_Shutdown();
      if (window_) ImGui_ImplGlfw_Shutdown();
      ImGui::DestroyContext();
      imguiReady_ = false;
    }
    const VkDevice device = context_->device();
    destroySwapchain();
    if (offscreen_) vkDestroyImage(device, offscreen_, nullptr);
    if (offscreenMemory_) vkFreeMemory(device, offscreenMemory_, nullptr);
    offscreen_ = VK_NULL_HANDLE;
    offscreenMemory_ = VK_NULL_HANDLE;
    if (timestamps_) vkDestroyQueryPool(device, timestamps_, nullptr);
    timestamps_ = VK_NULL_HANDLE;
    if (renderPass_) vkDestroyRenderPass(device, renderPass_, nullptr);
    if (imguiPool_) vkDestroyDescriptorPool(device, imguiPool_, nullptr);
    for (Slot& slot : slots_) {
      if (slot.fence) vkDestroyFence(device, slot.fence, nullptr);
      if (slot.acquired) vkDestroySemaphore(device, slot.acquired, nullptr);
    }
    slots_.clear();
    if (commandPool_) vkDestroyCommandPool(device, commandPool_, nullptr);
    if (surface_) vkDestroySurfaceKHR(context_->instance(), surface_, nullptr);
    renderPass_ = VK_NULL_HANDLE;
    imguiPool_ = VK_NULL_HANDLE;
    commandPool_ = VK_NULL_HANDLE;
    surface_ = VK_NULL_HANDLE;
    context_.reset();
  }
  if (window_) glfwDestroyWindow(window_);
  window_ = nullptr;
  if (glfwReady_) glfwTerminate();
  glfwReady_ = false;
}

bool Window::closeRequested() const { return window_ && glfwWindowShouldClose(window_) == GLFW_TRUE; }

void Window::setTitle(const std::string& title) {
  if (window_) glfwSetWindowTitle(window_, title.c_str());
}

void Window::createSwapchain() {
  const VkPhysicalDevice physical = context_->physicalDevice();
  VkSurfaceCapabilitiesKHR capabilities;
  check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(physical, surface_, &capabilities),
        "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
  std::uint32_t formatCount = 0;
  vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface_, &formatCount, nullptr);
  std::vector<VkSurfaceFormatKHR> formats(formatCount);
  vkGetPhysicalDeviceSurfaceFormatsKHR(physical, surface_, &formatCount, formats.data());
  // The display image is sRGB-encoded already: a UNORM swapchain shows
  // its bytes as they are (an _SRGB one would encode them twice).
  auto chosen = std::find_if(formats.begin(), formats.end(), [](const VkSurfaceFormatKHR& f) {
    return (f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) &&
           f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
  });
  if (chosen == formats.end()) throw gpu::GpuError("the window offers no 8-bit UNORM swapchain format");
  format_ = chosen->format;

  int width = 0, height = 0;
  glfwGetFramebufferSize(window_, &width, &height);
  extent_ = capabilities.currentExtent.width != ~0u
                ? capabilities.currentExtent
                : VkExtent2D{std::clamp(std::uint32_t(width), capabilities.minImageExtent.width,
                                        capabilities.maxImageExtent.width),
                             std::clamp(std::uint32_t(height), capabilities.minImageExtent.height,
                                        capabilities.maxImageExtent.height)};
  if (extent_.width == 0 || extent_.height == 0) return;  // minimised: nothing to present to
  std::uint32_t imageCount = capabilities.minImageCount + 1;
  if (capabilities.maxImageCount > 0) imageCount = std::min(imageCount, capabilities.maxImageCount);

  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface_;
  info.minImageCount = imageCount;
  info.imageFormat = format_;
  info.imageColorSpace = chosen->colorSpace;
  info.imageExtent = extent_;
  info.imageArrayLayers = 1;
  // Copied from for window screenshots, where the surface allows it.
  canCapture_ = (capabilities.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0;
  info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                    (canCapture_ ? VK_IMAGE_USAGE_TRANSFER_SRC_BIT : 0);
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = capabilities.currentTransform;
  info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  info.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always offered; no tearing
  info.clipped = VK_TRUE;
  const VkDevice device = context_->device();
  check(vkCreateSwapchainKHR(device, &info, nullptr, &swapchain_), "vkCreateSwapchainKHR");
  std::uint32_t count = 0;
  vkGetSwapchainImagesKHR(device, swapchain_, &count, nullptr);
  images_.resize(count);
  vkGetSwapchainImagesKHR(device, swapchain_, &count, images_.data());

  createRenderPassAndFramebuffers();
}

void Window::createRenderPassAndFramebuffers() {
  const VkDevice device = context_->device();
  if (!renderPass_) {
    // The UI is drawn over the blitted frame: loaded, not cleared.
    VkAttachmentDescription attachment{};
    attachment.format = format_;
    attachment.samples = VK_SAMPLE_COUNT_1_BIT;
    attachment.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    attachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    attachment.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    attachment.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachment.initialLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    attachment.finalLayout = targetLayout();
    VkAttachmentReference colour{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &colour;
    // The blit's write comes before the UI's blending reads it.
    VkSubpassDependency dependency{};
    dependency.srcSubpass = VK_SUBPASS_EXTERNAL;
    dependency.dstSubpass = 0;
    dependency.srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    dependency.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    dependency.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dependency.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    VkRenderPassCreateInfo passInfo{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    passInfo.attachmentCount = 1;
    passInfo.pAttachments = &attachment;
    passInfo.subpassCount = 1;
    passInfo.pSubpasses = &subpass;
    // And the UI's writes (with the final layout transition) before a
    // window screenshot's copy; a present waits on its semaphore instead.
    VkSubpassDependency toCopy{};
    toCopy.srcSubpass = 0;
    toCopy.dstSubpass = VK_SUBPASS_EXTERNAL;
    toCopy.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    toCopy.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    toCopy.dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
    toCopy.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    const VkSubpassDependency dependencies[] = {dependency, toCopy};
    passInfo.dependencyCount = 2;
    passInfo.pDependencies = dependencies;
    check(vkCreateRenderPass(device, &passInfo, nullptr, &renderPass_), "vkCreateRenderPass");
  }
  for (VkImage image : images_) {
    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = image;
    viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
    viewInfo.format = format_;
    viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageView view = VK_NULL_HANDLE;
    check(vkCreateImageView(device, &viewInfo, nullptr, &view), "vkCreateImageView");
    views_.push_back(view);
    VkFramebufferCreateInfo framebufferInfo{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    framebufferInfo.renderPass = renderPass_;
    framebufferInfo.attachmentCount = 1;
    framebufferInfo.pAttachments = &view;
    framebufferInfo.width = extent_.width;
    framebufferInfo.height = extent_.height;
    framebufferInfo.layers = 1;
    VkFramebuffer framebuffer = VK_NULL_HANDLE;
    check(vkCreateFramebuffer(device, &framebufferInfo, nullptr, &framebuffer), "vkCreateFramebuffer");
    framebuffers_.push_back(framebuffer);
    VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VkSemaphore finished = VK_NULL_HANDLE;
    check(vkCreateSemaphore(device, &semaphore, nullptr, &finished), "vkCreateSemaphore");
    renderFinished_.push_back(finished);
  }
}

void Window::destroySwapchain() {
  const VkDevice device = context_->device();
  for (VkFramebuffer framebuffer : framebuffers_) vkDestroyFramebuffer(device, framebuffer, nullptr);
  for (VkImageView view : views_) vkDestroyImageView(device, view, nullptr);
  for (VkSemaphore semaphore : renderFinished_) vkDestroySemaphore(device, semaphore, nullptr);
  framebuffers_.clear();
  views_.clear();
  renderFinished_.clear();
  images_.clear();
  if (swapchain_) vkDestroySwapchainKHR(device, swapchain_, nullptr);
  swapchain_ = VK_NULL_HANDLE;
}

void Window::initialiseImGui() {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // the layout is the program's, not a file left in the working folder
  ImGui::StyleColorsDark();
  imguiReady_ = true;
  if (window_) ImGui_ImplGlfw_InitForVulkan(window_, true);

  const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16}};
  VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  poolInfo.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  poolInfo.maxSets = 16;
  poolInfo.poolSizeCount = 1;
  poolInfo.pPoolSizes = sizes;
  check(vkCreateDescriptorPool(context_->device(), &poolInfo, nullptr, &imguiPool_), "vkCreateDescriptorPool");

  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = context_->instance();
  info.PhysicalDevice = context_->physicalDevice();
  info.Device = context_->device();
  info.QueueFamily = context_->queueFamily();
  info.Queue = context_->queue();
  info.DescriptorPool = imguiPool_;
  info.MinImageCount = 2;
  info.ImageCount = std::max<std::uint32_t>(2, std::uint32_t(images_.size()));
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  info.CheckVkResultFn = checkImGui;
  if (!ImGui_ImplVulkan_Init(&info, renderPass_)) throw gpu::GpuError("Dear ImGui's Vulkan backend did not start");
  context_->submitAndWait(
      [](gpu::Recorder& recorder) { ImGui_ImplVulkan_CreateFontsTexture(recorder.commandBuffer()); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
}

void Window::present(gpu::Image& frame, ImDrawData* ui, std::span<const Overlay> overlays) {
  const VkDevice device = context_->device();
  if (window_ && !swapchain_) {
    // Minimised (or lost): try again at this size; nothing to show on.
    vkDeviceWaitIdle(device);
    destroySwapchain();
    createSwapchain();
    if (!swapchain_) return;
  }
  const std::size_t slotIndex = presented_ % slots_.size();
  Slot& slot = slots_[slotIndex];
  check(vkWaitForFences(device, 1, &slot.fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  if (slot.timed) {
    std::uint64_t ticks[2] = {0, 0};
    if (vkGetQueryPoolResults(device, timestamps_, std::uint32_t(2 * slotIndex), 2, sizeof ticks, ticks,
                              sizeof ticks[0], VK_QUERY_RESULT_64_BIT) == VK_SUCCESS)
      lastPresentGpuMs_ = double(ticks[1] - ticks[0]) * context_->timestampPeriodNs() * 1.0e-6;
    slot.timed = false;
  }
  std::uint32_t imageIndex = 0;
  if (window_) {
    VkResult acquired =
        vkAcquireNextImageKHR(device, swapchain_, UINT64_MAX, slot.acquired, VK_NULL_HANDLE, &imageIndex);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
      vkDeviceWaitIdle(device);
      destroySwapchain();
      createSwapchain();
      return;  // this frame is skipped; the next one gets the new swapchain
    }
    if (acquired != VK_SUBOPTIMAL_KHR) check(acquired, "vkAcquireNextImageKHR");
  }
  check(vkResetFences(device, 1, &slot.fence), "vkResetFences");

  check(vkResetCommandBuffer(slot.cmd, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(slot.cmd, &begin), "vkBeginCommandBuffer");
  if (timestamps_) {
    vkCmdResetQueryPool(slot.cmd, timestamps_, std::uint32_t(2 * slotIndex), 2);
    vkCmdWriteTimestamp(slot.cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, timestamps_, std::uint32_t(2 * slotIndex));
  }
  VkImageMemoryBarrier toTransfer{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  toTransfer.srcAccessMask = 0;
  toTransfer.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  toTransfer.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  toTransfer.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  toTransfer.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  toTransfer.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  toTransfer.image = images_[imageIndex];
  toTransfer.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  // Chained to the acquire semaphore, whose wait is at the transfer stage.
  vkCmdPipelineBarrier(slot.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                       nullptr, 1, &toTransfer);
  VkImageBlit blit{};
  blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.srcOffsets[1] = {std::int32_t(frame.width()), std::int32_t(frame.height()), 1};
  blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.dstOffsets[1] = {std::int32_t(extent_.width), std::int32_t(extent_.height), 1};
  vkCmdBlitImage(slot.cmd, frame.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, images_[imageIndex],
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_LINEAR);
  VkRenderPassBeginInfo pass{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  pass.renderPass = renderPass_;
  pass.framebuffer = framebuffers_[imageIndex];
  pass.renderArea = {{0, 0}, extent_};
  vkCmdBeginRenderPass(slot.cmd, &pass, VK_SUBPASS_CONTENTS_INLINE);
  if (ui) ImGui_ImplVulkan_RenderDrawData(ui, slot.cmd);
  vkCmdEndRenderPass(slot.cmd);
  if (!overlays.empty()) {
    // Images beside the panels (Dear ImGui 1.86's Vulkan backend draws no
    // images of ours): blitted over the UI, into the rectangles it kept.
    VkImageMemoryBarrier toBlit{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    toBlit.srcAccessMask = 0;  // the render pass's dependency to EXTERNAL made its writes available
    toBlit.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    toBlit.oldLayout = targetLayout();
    toBlit.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    toBlit.srcQueueFamilyIndex = toBlit.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    toBlit.image = images_[imageIndex];
    toBlit.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(slot.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                         nullptr, 1, &toBlit);
    for (const Overlay& overlay : overlays) {
      // Clipped to the window: a panel dragged half out of it keeps its image's visible part.
      const std::int32_t x0 = std::max(overlay.x, 0), y0 = std::max(overlay.y, 0);
      const std::int32_t x1 = std::min(overlay.x + std::int32_t(overlay.image->width()), std::int32_t(extent_.width));
      const std::int32_t y1 = std::min(overlay.y + std::int32_t(overlay.image->height()), std::int32_t(extent_.height));
      if (x1 <= x0 || y1 <= y0) continue;
      VkImageBlit region{};
      region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      region.srcOffsets[0] = {x0 - overlay.x, y0 - overlay.y, 0};
      region.srcOffsets[1] = {x1 - overlay.x, y1 - overlay.y, 1};
      region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      region.dstOffsets[0] = {x0, y0, 0};
      region.dstOffsets[1] = {x1, y1, 1};
      vkCmdBlitImage(slot.cmd, overlay.image->handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, images_[imageIndex],
                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region, VK_FILTER_NEAREST);
    }
    VkImageMemoryBarrier back = toBlit;
    back.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    back.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    back.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    back.newLayout = targetLayout();
    vkCmdPipelineBarrier(slot.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, nullptr, 0,
                         nullptr, 1, &back);
  }
  std::unique_ptr<gpu::Buffer> capture;
  if (!capturePath_.empty()) {
    capture =
        std::make_unique<gpu::Buffer>(*context_, "viewer.window_capture",
                                      VkDeviceSize(extent_.width) * extent_.height * 4, gpu::BufferUsage::Readback);
    VkImageMemoryBarrier toCopy{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    toCopy.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    toCopy.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    toCopy.oldLayout = targetLayout();
    toCopy.newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    toCopy.srcQueueFamilyIndex = toCopy.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    toCopy.image = images_[imageIndex];
    toCopy.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(slot.cmd, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0, nullptr, 1, &toCopy);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {extent_.width, extent_.height, 1};
    vkCmdCopyImageToBuffer(slot.cmd, images_[imageIndex], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, capture->handle(), 1,
                           &region);
    VkImageMemoryBarrier back = toCopy;
    back.srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    back.dstAccessMask = 0;
    back.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    back.newLayout = targetLayout();
    VkBufferMemoryBarrier toHost{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
    toHost.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    toHost.srcQueueFamilyIndex = toHost.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    toHost.buffer = capture->handle();
    toHost.size = VK_WHOLE_SIZE;
    vkCmdPipelineBarrier(slot.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT | VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1, &toHost,
                         1, &back);
  }
  if (timestamps_) {
    vkCmdWriteTimestamp(slot.cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps_, std::uint32_t(2 * slotIndex + 1));
    slot.timed = true;
  }
  check(vkEndCommandBuffer(slot.cmd), "vkEndCommandBuffer");

  const VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_TRANSFER_BIT;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  if (window_) {
    submit.waitSemaphoreCount = 1;
    submit.pWaitSemaphores = &slot.acquired;
    submit.pWaitDstStageMask = &waitStage;
    submit.signalSemaphoreCount = 1;
    submit.pSignalSemaphores = &renderFinished_[imageIndex];
  }
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &slot.cmd;
  check(vkQueueSubmit(context_->queue(), 1, &submit, slot.fence), "vkQueueSubmit");
  ++presented_;
  if (capture) {
    check(vkWaitForFences(device, 1, &slot.fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    io::ImageF shot(int(extent_.width), int(extent_.height), {"R", "G", "B"});
    const auto* bytes = static_cast<const std::uint8_t*>(capture->mapped());
    const bool bgra = format_ == VK_FORMAT_B8G8R8A8_UNORM;
    for (std::size_t i = 0; i < std::size_t(extent_.width) * extent_.height; ++i)
      for (std::size_t c = 0; c < 3; ++c) shot.pixels[i * 3 + c] = float(bytes[i * 4 + (bgra ? 2 - c : c)]) / 255.0f;
    io::writePng(capturePath_, shot, io::PngEncoding::Linear);
    std::printf("wrote %s (the window, %ux%u)\n", capturePath_.c_str(), extent_.width, extent_.height);
    capturePath_.clear();
  }
  if (!window_) return;  // headless: nothing to present to

  VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  present.waitSemaphoreCount = 1;
  present.pWaitSemaphores = &renderFinished_[imageIndex];
  present.swapchainCount = 1;
  present.pSwapchains = &swapchain_;
  present.pImageIndices = &imageIndex;
  const VkResult presented = vkQueuePresentKHR(context_->queue(), &present);
  int width = 0, height = 0;
  glfwGetFramebufferSize(window_, &width, &height);
  const bool resized = std::uint32_t(width) != extent_.width || std::uint32_t(height) != extent_.height;
  if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR || resized) {
    vkDeviceWaitIdle(device);
    destroySwapchain();
    createSwapchain();
  } else {
    check(presented, "vkQueuePresentKHR");
  }
}

void Window::waitIdle() { vkDeviceWaitIdle(context_->device()); }

void Window::captureNextPresent(const std::filesystem::path& png) {
  if (!canCapture_) throw gpu::GpuError("this window's swapchain cannot be copied from: no window screenshot");
  capturePath_ = png;
}

}  // namespace bounce::viewer
