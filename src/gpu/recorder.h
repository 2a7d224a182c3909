// Records GPU work into a command buffer and places every barrier itself.
//
// Each Image and Buffer remembers what the GPU last did to it (SyncState).
// When a pass is dispatched, the Recorder compares each bound resource's
// declared access (from the pass declaration) with that state and inserts the
// pipeline barrier the hazard needs: read-after-write, write-after-read,
// write-after-write, and layout transitions (GENERAL for compute,
// TRANSFER_SRC/DST_OPTIMAL for copies). Passes never write a
// barrier by hand, so none can be forgotten. Because resources carry their
// state across command buffers, this stays right across frames as long as
// command buffers are submitted in the order they were recorded (which the
// FrameLoop guarantees).
#pragma once

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/pass.h"
#include "gpu/resources.h"
#include "gpu/timing.h"  // TimingStats, PassTraffic

namespace bounce::gpu {

class Context;

// One resource bound to a pass, by the name the pass declares.
// One mip level of an image, for Bind.
struct MipLevel {
  std::uint32_t level = 0;
};

struct Bind {
  static constexpr std::uint32_t kAllMips = ~0u;
  Bind(std::string_view name, Image& image, VkSampler sampler = VK_NULL_HANDLE)
      : name(name), image(&image), sampler(sampler) {}
  // A single mip level (storage images otherwise see level 0; sampled images all levels).
  Bind(std::string_view name, Image& image, MipLevel mip, VkSampler sampler = VK_NULL_HANDLE)
      : name(name), image(&image), sampler(sampler), mipLevel(mip.level) {}
  Bind(std::string_view name, Buffer& buffer) : name(name), buffer(&buffer) {}
  // Captured (--dump-stages) under `label` in place of the binding's name:
  // a per-signal slot named after the signal it holds this time.
  static Bind labelled(std::string_view name, Image& image, std::string_view label) {
    Bind bind(name, image);
    bind.captureLabel = label;
    return bind;
  }
  // Fills a slot the pass leaves untouched (a stage's slot that no signal
  // of the dispatch takes): bound as declared, never captured.
  static Bind filler(std::string_view name, Image& image) {
    Bind bind(name, image);
    bind.fillsUnusedSlot = true;
    return bind;
  }
  std::string_view name;
  Image* image = nullptr;
  Buffer* buffer = nullptr;
  VkSampler sampler = VK_NULL_HANDLE;  // sampled images: VK_NULL_HANDLE = the context's linear sampler
  std::uint32_t mipLevel = kAllMips;
  std::string_view captureLabel;  // empty: captured under `name`
  bool fillsUnusedSlot = false;
};

// The binds of `binds` whose names `pass` declares (for shared lists, see
// declareUsed in gpu/pass.h).
std::vector<Bind> bindsDeclaredBy(const ComputePass& pass, std::span<const Bind> binds);

// Where texels of one upload land: a rectangle of one mip level of one layer.
struct ImageRegion {
  std::uint32_t mipLevel = 0;
  std::uint32_t layer = 0;
  std::uint32_t x = 0, y = 0;
  std::uint32_t width = 0, height = 0;  // 0 = the whole mip level
  VkDeviceSize bufferOffset = 0;        // tightly packed texels start here
};

// A copy of one image a pass wrote, taken right after that pass ran (so
// later passes that reuse the image do not hide it): the level the pass
// wrote, over the grid it dispatched (a pass that covers a render size
// smaller than its images is captured at that size).
struct CapturedStage {
  std::uint64_t frame = 0;
  std::string pass;
  std::string binding;
  ImageDesc image;                   // width, height: the captured region; mipLevels 1
  std::vector<std::uint8_t> texels;  // tightly packed rows, once completeCapture() ran
  std::shared_ptr<Buffer> pending;   // the GPU's copy, until then
};

// Moves a capture's texels from its host-visible buffer into `texels` and
// frees the buffer; only once the command buffer that took it has completed.
void completeCapture(CapturedStage& capture);

// Where a Recorder writes its GPU timestamps (owned by the FrameLoop).

struct TimestampSink {
  VkQueryPool pool = VK_NULL_HANDLE;
  std::uint32_t capacity = 0;        // queries in the pool (two per pass)
  std::vector<std::string> passes;   // pass names in recorded order
  std::vector<PassTraffic> traffic;  // each pass's binds, alike
};

class Recorder {
 public:
  Recorder(Context& context, VkCommandBuffer commandBuffer, TimestampSink* timestamps = nullptr);

  VkCommandBuffer commandBuffer() const { return cmd_; }
  Context& context() const { return context_; }

  // Runs `pass` over a width x height grid of threads (one per pixel): the
  // workgroup count comes from the shader's local size. Every declared
  // resource must be bound exactly once; push constants must be exactly the
  // declared size.
  void dispatch(const ComputePass& pass, std::uint32_t width, std::uint32_t height, std::span<const Bind> binds,
                const void* pushConstants = nullptr, std::size_t pushConstantBytes = 0);
  void dispatch(const ComputePass& pass, std::uint32_t width, std::uint32_t height, std::initializer_list<Bind> binds,
                const void* pushConstants = nullptr, std::size_t pushConstantBytes = 0) {
    dispatch(pass, width, height, std::span<const Bind>(binds.begin(), binds.size()), pushConstants, pushConstantBytes);
  }
  template <class Params>
  void dispatch(const ComputePass& pass, std::uint32_t width, std::uint32_t height, std::initializer_list<Bind> binds,
                const Params& params) {
    dispatch(pass, width, height, binds, &params, sizeof(Params));
  }
  // A group of binds many passes share (a library's frame inputs) and the
  // pass's own, together: every declared resource bound exactly once.
  void dispatch(const ComputePass& pass, std::uint32_t width, std::uint32_t height, std::span<const Bind> group,
                std::span<const Bind> binds, const void* pushConstants = nullptr, std::size_t pushConstantBytes = 0);
  void dispatch(const ComputePass& pass, std::uint32_t width, std::uint32_t height, std::span<const Bind> group,
                std::initializer_list<Bind> binds, const void* pushConstants = nullptr,
                std::size_t pushConstantBytes = 0) {
    dispatch(pass, width, height, group, std::span<const Bind>(binds.begin(), binds.size()), pushConstants,
             pushConstantBytes);
  }
  template <class Params>
  void dispatch(const ComputePass& pass, std::uint32_t width, std::uint32_t height, std::span<const Bind> group,
                std::initializer_list<Bind> binds, const Params& params) {
    dispatch(pass, width, height, group, std::span<const Bind>(binds.begin(), binds.size()), &params,
             sizeof(Params));
  }
  // Bind lists put together at run time, e.g. a pass's own binds plus GpuBvh::appendBinds.
  template <class Params>
  void dispatch(const ComputePass& pass, std::uint32_t width, std::uint32_t height, std::span<const Bind> binds,
                const Params& params) {
    dispatch(pass, width, height, binds, &params, sizeof(Params));
  }

  // Transfers, with the same automatic barriers.
  void copyBufferToImage(Buffer& source, Image& destination);  // tightly packed mip 0
  void copyBufferToImage(Buffer& source, Image& destination, const ImageRegion& region);
  void copyImageToBuffer(Image& source, Buffer& destination);  // mip 0, tightly packed
  void copyImageToBuffer(Image& source, Buffer& destination, const ImageRegion& region);
  void copyBuffer(Buffer& source, Buffer& destination, VkDeviceSize bytes);
  // Writes `bytes` (a multiple of 4, at most 65536) into the start of a
  // buffer from the command buffer itself (vkCmdUpdateBuffer), so per-frame
  // constants need no host-visible buffer per frame in flight.
  void updateBuffer(Buffer& destination, const void* data, std::size_t bytes);
  void clearImage(Image& image, const VkClearColorValue& value);
  void fillBuffer(Buffer& buffer, std::uint32_t word);
  // Makes GPU writes to a host-visible buffer visible to the CPU after the
  // submission's fence is waited on.
  void makeHostReadable(Buffer& buffer);
  // Hands an image over to work recorded outside this recorder's tracking
  // (an engine's next use, or another library's): a barrier from everything
  // recorded here to `stage`/`access`, moving it to `layout`. Afterwards the
  // image counts as last used there.
  void handOver(Image& image, VkImageLayout layout, VkPipelineStageFlags2 stage, VkAccessFlags2 access);
  // Records the barriers asked for so far (handOver batches them).
  void flush() { flushBarriers(); }

  // Copies every image each later pass writes into `sink` (see CapturedStage).
  void captureStages(std::vector<CapturedStage>* sink, std::uint64_t frame) {
    captures_ = sink;
    captureFrame_ = frame;
  }
  // Whether this frame's pass outputs are being captured (passes that exist
  // only to be looked at run then, and only then).
  bool capturing() const { return captures_ != nullptr; }

  // Work a library recorded into this command buffer with its own queries
  // and copies reports through `handler` once the command buffer has
  // completed: FrameLoop calls it with its timings table and captures list
  // (in frame order), Context::submitAndWait with no timings and this
  // recorder's capture list (null when not capturing).
  using CompletionHandler = std::function<void(TimingStats* timings, std::vector<CapturedStage>* captures)>;
  void onCompleted(CompletionHandler handler) { completionHandlers_.push_back(std::move(handler)); }
  std::vector<CompletionHandler> takeCompletionHandlers() { return std::exchange(completionHandlers_, {}); }
  std::vector<CapturedStage>* captureSink() const { return captures_; }
  std::uint64_t captureFrame() const { return captureFrame_; }

  // For tests that prove synchronization validation works: with false, only
  // layout transitions are recorded, no hazard barriers.
  void setAutoBarriers(bool enabled) { autoBarriers_ = enabled; }

 private:
  // Records the barrier (and layout transition) that an access to a resource
  // needs after what its SyncState says happened before, and updates the state.
  void require(SyncState& state, VkImage image, std::uint32_t mipLevels, VkImageLayout layout,
               VkPipelineStageFlags2 stage, VkAccessFlags2 access, bool writes);
  void flushBarriers();
  void writeTimestamp(bool begin, const std::string& passName, const PassTraffic& traffic = {});

  Context& context_;
  VkCommandBuffer cmd_;
  TimestampSink* timestamps_;
  bool autoBarriers_ = true;
  std::vector<CapturedStage>* captures_ = nullptr;
  std::vector<CompletionHandler> completionHandlers_;
  std::uint64_t captureFrame_ = 0;
  // Scratch storage reused by every dispatch, so recording a frame does not
  // allocate once their capacity has grown.
  std::vector<VkImageMemoryBarrier2> imageBarriers_;
  VkMemoryBarrier2 memoryBarrier_{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  bool memoryBarrierPending_ = false;
  std::vector<VkWriteDescriptorSet> writes_;
  std::vector<std::pair<VkImage, std::uint32_t>> countedLevels_;  // image levels in this dispatch's traffic
  std::vector<VkDescriptorImageInfo> imageInfos_;
  std::vector<VkDescriptorBufferInfo> bufferInfos_;
  std::vector<const Bind*> ordered_;
  // What one dispatch does to each image and buffer it binds, its bindings
  // merged: an image bound twice (a slot filler, mip k - 1 read while mip
  // k is written) is one access that reads and writes, whatever order its
  // bindings come in.
  struct DispatchAccess {
    SyncState* state;
    VkImage image;
    std::uint32_t mipLevels;
    VkImageLayout layout;
    VkAccessFlags2 access;
    bool writes;
  };
  std::vector<DispatchAccess> accesses_;
};

}  // namespace bounce::gpu
