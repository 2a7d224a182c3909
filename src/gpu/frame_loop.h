// Frames in flight: a ring of command buffers, fences and timestamp pools, so
// the CPU records frame N+1 while the GPU runs frame N. Command buffers and
// query pools are created once and reused; a frame allocates nothing on the
// GPU (except the copies --dump-stages asks for).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/recorder.h"
#include "gpu/timing.h"

namespace bounce::gpu {

class Context;

class FrameLoop {
 public:
  explicit FrameLoop(Context& context, std::uint32_t framesInFlight = 2, std::uint32_t maxPassesPerFrame = 64);
  ~FrameLoop();
  FrameLoop(const FrameLoop&) = delete;
  FrameLoop& operator=(const FrameLoop&) = delete;

  // Waits until the oldest frame slot is free (collecting its timings and
  // captures), then starts recording into it. `capture` copies every pass
  // output of this frame (see Recorder::captureStages).
  Recorder& beginFrame(bool capture = false);
  // Ends recording and submits; returns at once.
  void endFrame();
  // Waits for every submitted frame and collects its results.
  void finish();

  std::uint64_t frameIndex() const { return frameIndex_; }  // of the frame being (or last) recorded
  std::uint32_t framesInFlight() const { return std::uint32_t(slots_.size()); }
  const TimingStats& timings() const { return timings_; }
  // Work recorded with its own queries (a library's) adds its times here
  // through Recorder::onCompleted.
  TimingStats& timings() { return timings_; }
  // Stage copies of completed frames (texels on the host), oldest first; the caller takes them.
  std::vector<CapturedStage> takeCaptures();

 private:
  struct Slot {
    std::uint64_t frameIndex = 0;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    TimestampSink timestamps;
    std::vector<CapturedStage> captures;
    std::unique_ptr<Recorder> recorder;  // one per slot, so its scratch memory is reused
    std::vector<Recorder::CompletionHandler> completionHandlers;  // of the frame in flight
    bool pending = false;
  };
  void collect(Slot& slot);

  Context& context_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  std::vector<Slot> slots_;
  std::uint64_t frameIndex_ = 0;
  std::uint64_t submitted_ = 0;
  bool recording_ = false;
  TimingStats timings_;
  std::vector<CapturedStage> completedCaptures_;
  std::vector<std::uint64_t> queryResults_;
};

}  // namespace bounce::gpu
