#include "gi/pass_log.h"

#include <algorithm>

#include "gi/world_ray_count.glsl"
#include "gpu/error.h"

namespace bounce::gi {
namespace {

// Two queries a pass, and room for the debug views and deep pyramids.
constexpr std::uint32_t kMaxPassesPerRecording = 64;

}  // namespace

Visualization visualization(gpu::Visualize view) {
  switch (view) {
    case gpu::Visualize::Radiance:
      return Visualization::Radiance;
    case gpu::Visualize::Color:
      return Visualization::Color;
    case gpu::Visualize::Signed:
      return Visualization::Signed;
    case gpu::Visualize::Range:
      return Visualization::Range;
    case gpu::Visualize::Raw:
      return Visualization::Raw;
    case gpu::Visualize::Motion:
      return Visualization::Motion;
    case gpu::Visualize::Ids:
      return Visualization::Ids;
    case gpu::Visualize::Heat:
      return Visualization::Heat;
  }
  return Visualization::Raw;
}

PassLog::PassLog(gpu::Context& context, bool timestamps, bool countRays)
    : context_(context), timestamps_(timestamps && context.hasTimestamps()) {
  if (countRays) {
    const VkDeviceSize bytes = shared::kWorldRayCounterWords * sizeof(std::uint32_t);
    rayCounters_ = std::make_unique<gpu::Buffer>(context, "gi.world_ray_counts", bytes, gpu::BufferUsage::DeviceLocal);
    rayReadback_ =
        std::make_unique<gpu::Buffer>(context, "gi.world_ray_counts.readback", bytes, gpu::BufferUsage::Readback);
  }
  if (!timestamps_) return;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2 * kMaxPassesPerRecording;
  gpu::check(vkCreateQueryPool(context_.device(), &info, nullptr, &sink_.pool), "vkCreateQueryPool");
  sink_.capacity = info.queryCount;
}

PassLog::~PassLog() {
  if (sink_.pool) vkDestroyQueryPool(context_.device(), sink_.pool, nullptr);
}

void PassLog::begin(VkCommandBuffer commandBuffer, gpu::Recorder& recorder, std::uint64_t frameIndex,
                    bool captureStages) {
  captures_.clear();
  sink_.passes.clear();
  sink_.traffic.clear();
  frameIndex_ = frameIndex;
  if (timestamps_) vkCmdResetQueryPool(commandBuffer, sink_.pool, 0, sink_.capacity);
  if (captureStages) recorder.captureStages(&captures_, frameIndex);
  rayCountsRecorded_ = false;
  if (rayCounters_) recorder.fillBuffer(*rayCounters_, 0u);
}

void PassLog::end(gpu::Recorder& recorder) {
  if (!rayCounters_) return;
  recorder.copyBuffer(*rayCounters_, *rayReadback_, rayCounters_->size());
  recorder.makeHostReadable(*rayReadback_);
  rayCountsRecorded_ = true;
}

void PassLog::collectInto(FrameResults& results, const std::string& caller) {
  if (!frameIndex_) return;
  const std::uint64_t frameIndex = *frameIndex_;
  const auto queries = std::uint32_t(sink_.passes.size() * 2);
  if (timestamps_ && queries > 0) {
    std::vector<std::uint64_t> ticks(queries);
    const VkResult result =
        vkGetQueryPoolResults(context_.device(), sink_.pool, 0, queries, queries * sizeof(std::uint64_t),
                              ticks.data(), sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT);
    if (result == VK_NOT_READY)
      throw Error(caller + ": frame " + std::to_string(frameIndex) +
                  " has not completed on the GPU; wait for its command buffer first");
    gpu::check(result, "reading the GI library's timestamps");
    const double msPerTick = context_.timestampPeriodNs() * 1e-6;
    const std::size_t first = results.timings.size();
    for (std::size_t i = 0; i < sink_.passes.size(); ++i) {
      const double ms = double(ticks[2 * i + 1] - ticks[2 * i]) * msPerTick;
      const std::string& pass = sink_.passes[i];
      const auto same = std::find_if(results.timings.begin() + std::ptrdiff_t(first), results.timings.end(),
                                     [&](const PassTiming& t) { return t.pass == pass; });
      const gpu::PassTraffic& traffic = sink_.traffic[i];
      if (same == results.timings.end()) {
        results.timings.push_back({frameIndex, pass, ms, traffic.imageBytes, traffic.bufferBytes});
      } else {
        same->milliseconds += ms;
        same->imageBytes += traffic.imageBytes;
        same->bufferBytes += traffic.bufferBytes;
      }
    }
  }
  if (rayCountsRecorded_) {
    WorldRayCount count{.frameIndex = frameIndex};
    const auto* words = static_cast<const std::uint32_t*>(rayReadback_->mapped());
    for (std::uint32_t pass = 0; pass < shared::kWorldRayPasses; ++pass)
      for (std::uint32_t purpose = 0; purpose < shared::kWorldRayPurposes; ++purpose)
        for (std::uint32_t copy = 0; copy < shared::kWorldRayCounterCopies; ++copy) {
          const std::uint32_t rays =
              words[(pass * shared::kWorldRayPurposes + purpose) * shared::kWorldRayCounterCopies + copy];
          count.rays[purpose] += rays;
          count.passRays[pass] += rays;
        }
    for (std::uint32_t pass = 0; pass < shared::kWorldRayPasses; ++pass)
      count.passQueued[pass] = words[shared::kWorldRayQueuedCounters + pass];
    results.worldRays.push_back(count);
  }
  for (gpu::CapturedStage& capture : captures_) {
    gpu::completeCapture(capture);
    results.stages.push_back({.frameIndex = capture.frame,
                              .pass = capture.pass,
                              .binding = capture.binding,
                              .width = capture.image.width,
                              .height = capture.image.height,
                              .format = capture.image.format,
                              .visualization = visualization(capture.image.visualize),
                              .texels = std::move(capture.texels)});
  }
  captures_.clear();
  sink_.passes.clear();
  sink_.traffic.clear();
  frameIndex_.reset();
  rayCountsRecorded_ = false;
}

}  // namespace bounce::gi
