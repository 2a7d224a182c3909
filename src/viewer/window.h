// bounce view's window: a GLFW window, the Vulkan context made for it (the
// surface extensions, VK_KHR_swapchain, a queue family that presents to
// it), and what puts a frame on it: the swapchain, the blit of the
// rendered frame and Dear ImGui's draw lists on top. The GI library runs on
// this same device through its engine-device path (render::GiBridge).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/context.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"

struct GLFWwindow;
struct ImDrawData;

namespace bounce::viewer {

struct WindowOptions {
  std::uint32_t width = 960;  // the window's client area at start (it may be resized)
  std::uint32_t height = 540;
  std::string title = "bounce view";
  bool validation = false;
  std::optional<int> deviceIndex;
  // No window: the panels are drawn into an image of this size that is
  // never presented (a GPU machine without a display, to measure the
  // viewer's own cost). Input comes from a script only.
  bool headless = false;
};

// Leaves `image` as Window::present() takes its frame and overlays: in
// TRANSFER_SRC_OPTIMAL, after everything `recorder` recorded on it.
void handOverToWindow(gpu::Recorder& recorder, gpu::Image& image);

class Window {
 public:
  // Throws std::runtime_error when there is no display (DISPLAY unset, no
  // X server) or GLFW cannot make a Vulkan window, gpu::GpuError when no
  // device can present to it.
  explicit Window(const WindowOptions& options);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  gpu::Context& context() { return *context_; }
  GLFWwindow* handle() { return window_; }
  bool closeRequested() const;
  void setTitle(const std::string& title);
  bool headless() const { return !window_; }
  // Once a frame, before the panels are built: the window's events, and
  // Dear ImGui's new frame (size, time, input).
  void beginUiFrame();
  // The client area in pixels (the swapchain's size).
  VkExtent2D extent() const { return extent_; }

  // Puts `frame` (the display image: rgba8, handed over in
  // TRANSFER_SRC_OPTIMAL for the blit, Recorder::handOver) on the window,
  // scaled to fill it, with the UI's draw lists on top, and presents. The
  // frame's own command buffer must have been submitted before (the blit
  // follows it in queue order). Waits only when both of its own command
  // buffers are still in flight.
  // An image drawn over the panels at (x, y) of the window (rgba8, handed
  // over in TRANSFER_SRC_OPTIMAL as `frame` is): the material editor's plots.
  struct Overlay {
    gpu::Image* image;
    std::int32_t x, y;
  };
  void present(gpu::Image& frame, ImDrawData* ui, std::span<const Overlay> overlays = {});
  // Waits for every present submission.
  void waitIdle();
  // The next present() also writes what the window shows (the frame and
  // the UI over it) to `png`. Throws when the swapchain cannot be copied
  // from (VK_IMAGE_USAGE_TRANSFER_SRC_BIT not offered).
  void captureNextPresent(const std::filesystem::path& png);
  // GPU time (timestamps) of the latest completed present: the blit and
  // the panels' draw; 0 until one completed.
  double lastPresentGpuMs() const { return lastPresentGpuMs_; }

 private:
  void release();
  void openWindow(const WindowOptions& options);
  void createSwapchain();
  void createOffscreenTarget();
  void createRenderPassAndFramebuffers();
  void createCommandSlots();
  // The layout the render pass leaves the target in: PRESENT_SRC_KHR, or
  // TRANSFER_SRC_OPTIMAL when headless.
  VkImageLayout targetLayout() const;
  void destroySwapchain();
  void initialiseImGui();

  GLFWwindow* window_ = nullptr;
  std::unique_ptr<gpu::Context> context_;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkExtent2D extent_{};
  std::vector<VkImage> images_;
  std::vector<VkImageView> views_;
  std::vector<VkFramebuffer> framebuffers_;
  std::vector<VkSemaphore> renderFinished_;  // one per swapchain image
  VkRenderPass renderPass_ = VK_NULL_HANDLE;
  VkDescriptorPool imguiPool_ = VK_NULL_HANDLE;
  VkCommandPool commandPool_ = VK_NULL_HANDLE;
  // Headless: the image the panels are drawn into, in place of a swapchain's.
  VkImage offscreen_ = VK_NULL_HANDLE;
  VkDeviceMemory offscreenMemory_ = VK_NULL_HANDLE;
  VkQueryPool timestamps_ = VK_NULL_HANDLE;  // two per slot: the start and end of its present
  double lastPresentGpuMs_ = 0.0;
  struct Slot {
    bool timed = false;  // its queries hold a submitted present's times
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    VkSemaphore acquired = VK_NULL_HANDLE;
  };
  std::vector<Slot> slots_;
  std::uint64_t presented_ = 0;
  bool canCapture_ = false;            // the swapchain's images can be copied from
  std::filesystem::path capturePath_;  // non-empty: the next present writes it
  bool imguiReady_ = false;
  bool glfwReady_ = false;
};

}  // namespace bounce::viewer
