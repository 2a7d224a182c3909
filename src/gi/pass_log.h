// What the library keeps of one recorded command buffer until the engine
// collects it: its passes' timestamp queries, the copies of their outputs
// (stage captures) and, where its passes trace, the world-ray counters. GiContext keeps one per frame in flight,
// EnvironmentPrefilter one for its single recording.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "bounce/gi.h"
#include "gpu/context.h"
#include "gpu/recorder.h"

namespace bounce::gi {

// The public name of a gpu::Visualize.
Visualization visualization(gpu::Visualize view);

class PassLog {
 public:
  // Timestamps only where asked and the queue family has them; world-ray
  // counters where asked (the passes logged bind rayCounters()).
  PassLog(gpu::Context& context, bool timestamps, bool countRays = false);
  ~PassLog();
  PassLog(const PassLog&) = delete;
  PassLog& operator=(const PassLog&) = delete;

  // Starts logging a recording of frame `frameIndex` into `commandBuffer`
  // (what an earlier one logged and nobody collected is dropped): resets the
  // queries there and sets `recorder` up to time its passes and, when
  // `captureStages`, to copy their outputs.
  void begin(VkCommandBuffer commandBuffer, gpu::Recorder& recorder, std::uint64_t frameIndex, bool captureStages);
  // The sink a Recorder for begin()'s command buffer must be made with (null: no timestamps).
  gpu::TimestampSink* sink() { return timestamps_ ? &sink_ : nullptr; }

  // The counters this recording's passes add their world rays to
  // (gi/world_ray_count.glsl; begin() clears them); only with countRays.
  gpu::Buffer& rayCounters() { return *rayCounters_; }
  // Records the copy of the counters the host reads at collectInto(); after
  // the recording's last pass.
  void end(gpu::Recorder& recorder);

  // The frame logged and not yet collected.
  const std::optional<std::uint64_t>& frameIndex() const { return frameIndex_; }

  // Appends the logged frame's pass times (a pass dispatched several times
  // in it is one entry, its times added), stage copies and world rays to `results`, and
  // forgets them. Throws Error, its message starting with `caller`, when the
  // command buffer has not completed.
  void collectInto(FrameResults& results, const std::string& caller);

 private:
  gpu::Context& context_;
  bool timestamps_ = false;
  gpu::TimestampSink sink_;
  std::vector<gpu::CapturedStage> captures_;
  std::optional<std::uint64_t> frameIndex_;
  std::unique_ptr<gpu::Buffer> rayCounters_, rayReadback_;
  bool rayCountsRecorded_ = false;
};

}  // namespace bounce::gi
