// GPU memory objects: buffers, 2D images, and ping-pong history images.
// Each carries its own synchronization state, which the Recorder reads and
// updates to place barriers automatically (see recorder.h).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

namespace bounce::gpu {

class Context;

// Every access flag that writes: what of another's last use (an engine's
// stage and access) a first barrier must wait for and make visible.
inline constexpr VkAccessFlags2 kWriteAccessFlags =
    VK_ACCESS_2_SHADER_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT |
    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_HOST_WRITE_BIT |
    VK_ACCESS_2_MEMORY_WRITE_BIT;

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

// Device memory for many images and buffers in a few vkAllocateMemory calls:
// blocks handed out front to back and freed only with the arena (which must
// outlive what it holds). Drivers limit the number of allocations (4096 is
// common) and each one costs. Blocks grow with what the arena holds: the
// first is 4 MiB, each next one as large as all before it, up to maxBlock,
// so a small context needs few blocks. An owner that knows what it is about
// to allocate says so (`expected`): then the next block is as large as what
// is left of that, plus a little for alignment, in one allocation up to the
// device's largest (Context::maxAllocationBytes), so no block before the last
// is left with an unused tail (at 1080p on an H100, 128 MiB blocks left 59
// MiB of tails where a padded image did not fit the end of one). Past the
// expected (a driver that pads images beyond their texels, which the
// estimate counts), each allocation of 4 MiB or more takes a block of its own
// size and smaller ones share 4 MiB blocks: at most 4 MiB of a block is left
// unused.
class MemoryArena {
 public:
  // maxBlock: the largest block while the arena grows without an expected total.
  explicit MemoryArena(Context& context, VkDeviceSize maxBlock = VkDeviceSize(128) << 20, VkDeviceSize expected = 0);
  ~MemoryArena();
  MemoryArena(const MemoryArena&) = delete;
  MemoryArena& operator=(const MemoryArena&) = delete;

  struct Allocation {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize offset = 0;
  };
  // `kind` ("buffer", "image") and `name` say what it is for, in errors and in bytesByName().
  Allocation allocate(const VkMemoryRequirements& requirements, VkMemoryPropertyFlags required, const char* kind,
                      const std::string& name);

  // Hands out from the front of its blocks again: what it hands out next
  // shares memory with what it handed out before. For owners whose
  // resources never live at once, which make each one's first use wait for
  // everything before it and drop its contents (gi's transient pool: each
  // unit's frame-local images, gi::ImageSet::takeTransients).
  void rewind();
  VkDeviceSize bytes() const;                                // device memory held
  // The most its allocations asked for between two rewinds (all of them without one).
  VkDeviceSize peakRequested() const { return std::max(peak_, requested_); }
  // The bytes each allocation took, by its name, in the order made (the
  // blocks' unused tails, in bytes() but in none of these, not counted).
  const std::vector<std::pair<std::string, VkDeviceSize>>& bytesByName() const { return allocations_; }
  std::size_t allocationCount() const { return blocks_.size(); }  // vkAllocateMemory calls

 private:
  struct Block {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    std::uint32_t type = 0;
    VkDeviceSize size = 0;
    VkDeviceSize used = 0;
  };
  Context& context_;
  VkDeviceSize maxBlock_;
  VkDeviceSize expected_;
  VkDeviceSize requested_ = 0;  // what allocations have asked for so far (since the last rewind)
  VkDeviceSize peak_ = 0;       // the most requested_ was before a rewind
  std::vector<Block> blocks_;
  std::vector<std::pair<std::string, VkDeviceSize>> allocations_;
};

enum class BufferUsage {
  DeviceLocal,  // storage buffer on the GPU
  Upload,       // host-visible, written by the CPU, read by the GPU
  Readback,     // host-visible and cached, written by the GPU, read by the CPU
};

// Another's buffer (an engine's), used without owning it: in the state
// `state` says, `size` bytes from its start.
struct ExternalBuffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  std::string name;
  SyncState state;
};

class Buffer {
 public:
  // Device-local buffers may come from an arena; host-visible ones get their own memory.
  Buffer(Context& context, std::string name, VkDeviceSize size, BufferUsage usage, MemoryArena* arena = nullptr);
  Buffer(Context& context, const ExternalBuffer& external);
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
  VkDeviceMemory memory_ = VK_NULL_HANDLE;  // null when the memory is an arena's
  VkDeviceSize allocated_ = 0;
  std::uint32_t memoryType_ = 0;
  void* mapped_ = nullptr;
  SyncState sync_;
  bool owned_ = true;  // false: another's buffer (ExternalBuffer)
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
  // false: sampled and copied only (formats without a storage qualifier,
  // such as sRGB; tests that stand in for an engine's images).
  bool storage = true;
};

// Someone else's image (an engine's), used but never destroyed: its handle,
// a view of all its mips, and what was last done to it, where the first
// barrier starts from.
struct ExternalImage {
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  ImageDesc desc;
  SyncState state;
};

// A 2D image usable as storage image, sampled image and transfer source and
// destination. Compute passes use it in VK_IMAGE_LAYOUT_GENERAL (storage
// and sampled alike, unless sampledLayout() says otherwise); copies move it
// to the transfer layouts and the next pass back.
class Image {
 public:
  Image(Context& context, const ImageDesc& desc, MemoryArena* arena = nullptr);
  // Wraps another's image: its view shows all mips; mipView() makes views
  // of single levels when first asked, and destroys only those.
  Image(Context& context, const ExternalImage& external);
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
  // The layout compute passes sample it in (storage access is always in
  // GENERAL): GENERAL for Bounce's own images; for another's image, the
  // read-only layout it came in, so reading it needs no transition.
  VkImageLayout sampledLayout() const { return sampledLayout_; }
  void setSampledLayout(VkImageLayout layout) { sampledLayout_ = layout; }

 private:
  Context& context_;
  ImageDesc desc_;
  VkImage image_ = VK_NULL_HANDLE;
  bool owned_ = true;  // false: another's image (ExternalImage)
  VkDeviceSize allocated_ = 0;
  std::uint32_t memoryType_ = 0;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;  // null when the memory is an arena's
  VkImageView view_ = VK_NULL_HANDLE;
  mutable std::vector<VkImageView> mipViews_;  // one per level when there are several (another's: made when asked)
  SyncState sync_;
  VkImageLayout sampledLayout_ = VK_IMAGE_LAYOUT_GENERAL;
};

// A temporal resource: two images that swap roles every frame. Which one is
// "current" is a pure function of the frame index, so nobody swaps by hand
// and a skipped swap cannot happen.
class HistoryImage {
 public:
  HistoryImage(Context& context, const ImageDesc& desc, MemoryArena* arena = nullptr);

  Image& current(std::uint64_t frameIndex) { return *images_[frameIndex & 1u]; }
  Image& previous(std::uint64_t frameIndex) { return *images_[(frameIndex + 1u) & 1u]; }
  const ImageDesc& desc() const { return images_[0]->desc(); }

 private:
  std::array<std::unique_ptr<Image>, 2> images_;
};

}  // namespace bounce::gpu
