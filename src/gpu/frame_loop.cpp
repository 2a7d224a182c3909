#include "gpu/frame_loop.h"

#include <algorithm>
#include <utility>

#include "gpu/context.h"
#include "gpu/error.h"

namespace bounce::gpu {

FrameLoop::FrameLoop(Context& context, std::uint32_t framesInFlight, std::uint32_t maxPassesPerFrame)
    : context_(context), slots_(framesInFlight) {
  if (framesInFlight == 0) throw GpuError("FrameLoop needs at least one frame in flight");
  VkDevice device = context.device();
  VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  poolInfo.queueFamilyIndex = context.queueFamily();
  check(vkCreateCommandPool(device, &poolInfo, nullptr, &pool_), "vkCreateCommandPool");
  for (Slot& slot : slots_) {
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool_;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    check(vkAllocateCommandBuffers(device, &alloc, &slot.cmd), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    check(vkCreateFence(device, &fenceInfo, nullptr, &slot.fence), "vkCreateFence");
    VkQueryPoolCreateInfo queryInfo{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    queryInfo.queryType = VK_QUERY_TYPE_TIMESTAMP;
    queryInfo.queryCount = maxPassesPerFrame * 2;
    check(vkCreateQueryPool(device, &queryInfo, nullptr, &slot.timestamps.pool), "vkCreateQueryPool");
    slot.timestamps.capacity = queryInfo.queryCount;
    slot.timestamps.passes.reserve(maxPassesPerFrame);
    slot.recorder = std::make_unique<Recorder>(context, slot.cmd, &slot.timestamps);
  }
  queryResults_.resize(std::size_t(maxPassesPerFrame) * 2);
}

FrameLoop::~FrameLoop() {
  VkDevice device = context_.device();
  vkDeviceWaitIdle(device);
  for (Slot& slot : slots_) {
    vkDestroyQueryPool(device, slot.timestamps.pool, nullptr);
    vkDestroyFence(device, slot.fence, nullptr);
  }
  vkDestroyCommandPool(device, pool_, nullptr);
}

void FrameLoop::collect(Slot& slot) {
  if (!slot.pending) return;
  check(vkWaitForFences(context_.device(), 1, &slot.fence, VK_TRUE, UINT64_MAX), "waiting for a frame");
  slot.pending = false;
  const auto queries = std::uint32_t(slot.timestamps.passes.size() * 2);
  if (queries) {
    check(vkGetQueryPoolResults(context_.device(), slot.timestamps.pool, 0, queries, queries * sizeof(std::uint64_t),
                                queryResults_.data(), sizeof(std::uint64_t),
                                VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "reading GPU timestamps");
    // A pass dispatched several times in a frame (one mip level or pyramid
    // step each) is one row: its dispatches' times add up.
    const double msPerTick = context_.timestampPeriodNs() * 1e-6;
    struct Total {
      const std::string* pass;
      double ms;
      PassTraffic traffic;
    };
    std::vector<Total> frameTotals;
    for (std::size_t i = 0; i < slot.timestamps.passes.size(); ++i) {
      const double ms = double(queryResults_[2 * i + 1] - queryResults_[2 * i]) * msPerTick;
      const std::string& pass = slot.timestamps.passes[i];
      const auto same =
          std::find_if(frameTotals.begin(), frameTotals.end(), [&](const Total& t) { return *t.pass == pass; });
      if (same == frameTotals.end()) {
        frameTotals.push_back({&pass, ms, slot.timestamps.traffic[i]});
      } else {
        same->ms += ms;
        same->traffic += slot.timestamps.traffic[i];
      }
    }
    for (const Total& t : frameTotals) timings_.add(*t.pass, t.ms, t.traffic);
  }
  slot.timestamps.passes.clear();
  slot.timestamps.traffic.clear();
  for (CapturedStage& c : slot.captures) {
    completeCapture(c);
    completedCaptures_.push_back(std::move(c));
  }
  slot.captures.clear();
  for (Recorder::CompletionHandler& handler : slot.completionHandlers) handler(&timings_, &completedCaptures_);
  slot.completionHandlers.clear();
}

Recorder& FrameLoop::beginFrame(bool capture) {
  if (recording_) throw GpuError("beginFrame called twice without endFrame");
  frameIndex_ = submitted_;
  Slot& slot = slots_[submitted_ % slots_.size()];
  collect(slot);
  slot.frameIndex = frameIndex_;
  check(vkResetFences(context_.device(), 1, &slot.fence), "vkResetFences");
  check(vkResetCommandBuffer(slot.cmd, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(slot.cmd, &begin), "vkBeginCommandBuffer");
  vkCmdResetQueryPool(slot.cmd, slot.timestamps.pool, 0, slot.timestamps.capacity);
  slot.recorder->captureStages(capture ? &slot.captures : nullptr, frameIndex_);
  recording_ = true;
  return *slot.recorder;
}

void FrameLoop::endFrame() {
  if (!recording_) throw GpuError("endFrame called without beginFrame");
  Slot& slot = slots_[submitted_ % slots_.size()];
  check(vkEndCommandBuffer(slot.cmd), "vkEndCommandBuffer");
  slot.completionHandlers = slot.recorder->takeCompletionHandlers();
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &slot.cmd;
  check(vkQueueSubmit(context_.queue(), 1, &submit, slot.fence), "vkQueueSubmit");
  slot.pending = true;
  recording_ = false;
  ++submitted_;
}

void FrameLoop::finish() {
  // Oldest first, so timings and captures stay in frame order.
  for (std::size_t i = 0; i < slots_.size(); ++i) collect(slots_[(submitted_ + i) % slots_.size()]);
}

std::vector<CapturedStage> FrameLoop::takeCaptures() { return std::exchange(completedCaptures_, {}); }

}  // namespace bounce::gpu
