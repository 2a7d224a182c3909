// GPU memory objects: buffers, 2D images, and ping-pong history images.
// Each carries its own synchronization state, which the Recorder reads and
// updates to place barriers automatically (see recorder.h).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace bounce::gpu {

class Context;

// What the GPU last did to a resource, as far as recorded commands go.
struct SyncState {
  VkPipelineStageFlags2 writeStage = VK_PIPELINE_STAGE_2_NONE;  // last write not yet waited for by all
  VkAccessFlags2 writeAccess = VK_ACCESS_2_NONE;
  VkPipelineStageFlags2 readStages = VK_PIPELINE_STAGE_2_NONE;  // reads since the last write
  VkAccessFlags2 visibleTo = VK_ACCESS_2_NONE;                  // accesses the last write is visible to
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
};

// How a dumped image is turned into a PNG people can look at.
enum class Visualize {
  Radiance,  // linear HDR: exposure + tonemap + sRGB
  Color,     // linear [0,1] colour such as albedo: sRGB encode
  Signed,    // [-1,1] vectors such as normals: x*0.5+0.5
  Range,     // scalar data such as depth: min..max of the image to black..white
  Raw,       // stored as is, clamped to [0,1]
  Motion,    // 2D vectors: x in red, y in green, 0.5 = still, scaled by the largest
  Ids,       // integer labels: one hashed colour per value, all-ones (none) black
  Heat,      // positive scalars spanning decades (reservoir M and W, history lengths): log scale
             // from the 1st to the 99th percentile of the positive values, magma colours; 0 black
};

enum class BufferUsage {
  DeviceLocal,  // storage buffer on the GPU
  Upload,       // host-visible, written by the CPU, read by the GPU
  Readback,     // host-visible and cached, written by the GPU, read by the CPU
};

class Buffer {
 public:
  Buffer(Context& context, std::string name, VkDeviceSize size, BufferUsage usage);
  ~Buffer();
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  const std::string& name() const { return name_; }
  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  // Host pointer for Upload/Readback buffers (persistently mapped); null otherwise.
  void* mapped() const { return mapped_; }
  SyncState& sync() { return sync_; }

 private:
  Context& context_;
  std::string name_;
  VkDeviceSize size_ = 0;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize allocated_ = 0;
  std::uint32_t memoryType_ = 0;
  void* mapped_ = nullptr;
  SyncState sync_;
};

struct ImageDesc {
  std::string name;  // stable name; appears in validation messages and dumps
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  VkFormat format = VK_FORMAT_R16G16B16A16_SFLOAT;
  Visualize visualize = Visualize::Radiance;
  std::uint32_t mipLevels = 1;
  std::uint32_t layers = 1;  // > 1 makes an array image (image2DArray / sampler2DArray in shaders)
  bool arrayed = false;      // viewed as an array even with one layer (its shaders declare *2DArray)
};

// A 2D image usable as storage image, sampled image and transfer source and
// destination. Compute passes use it in VK_IMAGE_LAYOUT_GENERAL (storage
// and sampled alike); copies move it to the transfer layouts and back.
class Image {
 public:
  Image(Context& context, const ImageDesc& desc);
  ~Image();
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;

  const ImageDesc& desc() const { return desc_; }
  const std::string& name() const { return desc_.name; }
  std::uint32_t width() const { return desc_.width; }
  std::uint32_t height() const { return desc_.height; }
  VkFormat format() const { return desc_.format; }
  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }  // all mip levels
  // One mip level, for a pass that writes (or reads) that level alone, e.g.
  // building a mip chain level by level.
  VkImageView mipView(std::uint32_t level) const;
  std::uint32_t mipWidth(std::uint32_t level) const { return std::max(1u, desc_.width >> level); }
  std::uint32_t mipHeight(std::uint32_t level) const { return std::max(1u, desc_.height >> level); }
  VkDeviceSize byteSize() const;  // of mip level 0, layer 0
  SyncState& sync() { return sync_; }

 private:
  Context& context_;
  ImageDesc desc_;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceSize allocated_ = 0;
  std::uint32_t memoryType_ = 0;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  std::vector<VkImageView> mipViews_;  // one per level when there are several
  SyncState sync_;
};

// A temporal resource: two images that swap roles every frame. Which one is
// "current" is a pure function of the frame index, so nobody swaps by hand
// and a skipped swap cannot happen.
class HistoryImage {
 public:
  HistoryImage(Context& context, const ImageDesc& desc);

  Image& current(std::uint64_t frameIndex) { return *images_[frameIndex & 1u]; }
  Image& previous(std::uint64_t frameIndex) { return *images_[(frameIndex + 1u) & 1u]; }
  const ImageDesc& desc() const { return images_[0]->desc(); }

 private:
  std::array<std::unique_ptr<Image>, 2> images_;
};

}  // namespace bounce::gpu
