#include "gpu/resources.h"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <string>
#include <utility>

#include "gpu/context.h"
#include "gpu/error.h"
#include "gpu/format.h"

namespace bounce::gpu {
namespace {

// Binds memory to an image; a device that runs out (some drivers commit
// memory only here) is told in the terms a user can act on.
void bindImageMemory(Context& context, VkImage image, VkDeviceMemory memory, VkDeviceSize offset,
                     const std::string& name) {
  const VkResult result = vkBindImageMemory(context.device(), image, memory, offset);
  if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY) {
    constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;
    char message[256];
    std::snprintf(message, sizeof message,
                  "image '%s': out of memory binding it: %.1f GiB of device memory are held already, the largest "
                  "heap of %s has %.1f GiB",
                  name.c_str(), double(context.deviceLocalBytesInUse()) / kGiB, context.deviceInfo().name.c_str(),
                  double(context.largestDeviceLocalHeap()) / kGiB);
    throw GpuError(message);
  }
  check(result, ("vkBindImageMemory '" + name + "'").c_str());
}

}  // namespace

MemoryArena::MemoryArena(Context& context, VkDeviceSize maxBlock, VkDeviceSize expected)
    : context_(context), maxBlock_(maxBlock), expected_(expected) {}

MemoryArena::~MemoryArena() {
  for (const Block& block : blocks_) {
    vkFreeMemory(context_.device(), block.memory, nullptr);
    context_.trackAllocation(block.type, -std::int64_t(block.size));
  }
}

MemoryArena::Allocation MemoryArena::allocate(const VkMemoryRequirements& requirements, VkMemoryPropertyFlags required,
                                              const char* kind, const std::string& name) {
  const std::uint32_t type = context_.findMemoryType(requirements.memoryTypeBits, required);
  // Images and buffers may share a block: keeping every start at a multiple
  // of bufferImageGranularity keeps linear and optimal data off one page.
  const VkDeviceSize alignment =
      std::max(requirements.alignment, context_.properties().limits.bufferImageGranularity);
  const auto alignUp = [alignment](VkDeviceSize value) { return (value + alignment - 1) / alignment * alignment; };
  const auto handedOut = [&](Allocation allocation) {
    requested_ += requirements.size;
    allocations_.emplace_back(name, requirements.size);
    return allocation;
  };
  for (Block& block : blocks_) {
    if (block.type != type) continue;
    const VkDeviceSize offset = alignUp(block.used);
    if (offset + requirements.size > block.size) continue;
    block.used = offset + requirements.size;
    return handedOut({block.memory, offset});
  }
  Block block;
  block.type = type;
  constexpr VkDeviceSize kFirstBlock = VkDeviceSize(4) << 20;
  // Without an expected total, blocks grow with what is held (few
  // allocations for an unknown need).
  VkDeviceSize size = std::clamp(bytes(), kFirstBlock, std::max(kFirstBlock, maxBlock_));
  if (requested_ < expected_) {
    // What is left of the expected, and room for alignment: 1/32 of it and 1 MiB.
    const VkDeviceSize left = expected_ - requested_;
    size = std::min(std::max(kFirstBlock, context_.maxAllocationBytes()), left + left / 32 + (VkDeviceSize(1) << 20));
  } else if (expected_ > 0) {
    // Past the expected (a driver that pads images beyond their texels,
    // images made later such as debug views): each large allocation gets a
    // block of its own size and small ones share one of kFirstBlock, so no
    // block's unused tail exceeds kFirstBlock (a block grown with what is
    // held left 103 MiB unused at 1080p on an H100).
    size = kFirstBlock;
  }
  block.size = std::max(requirements.size, size);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = block.size;
  alloc.memoryTypeIndex = type;
  check(
      vkAllocateMemory(context_.device(), &alloc, nullptr, &block.memory),
      ("allocating " + std::to_string(block.size) + " bytes of device memory for " + kind + " '" + name + "'").c_str());
  context_.trackAllocation(type, std::int64_t(block.size));
  block.used = requirements.size;
  blocks_.push_back(block);
  return handedOut({block.memory, 0});
}

void MemoryArena::rewind() {
  peak_ = std::max(peak_, requested_);
  requested_ = 0;
  for (Block& block : blocks_) block.used = 0;
}

VkDeviceSize MemoryArena::bytes() const {
  VkDeviceSize total = 0;
  for (const Block& block : blocks_) total += block.size;
  return total;
}

Buffer::Buffer(Context& context, std::string name, VkDeviceSize size, BufferUsage usage, MemoryArena* arena)
    : context_(context), name_(std::move(name)), size_(size) {
  if (size == 0) throw GpuError("buffer '" + name_ + "': size is zero");
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
               VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkDevice device = context.device();
  check(vkCreateBuffer(device, &info, nullptr, &buffer_), ("vkCreateBuffer '" + name_ + "'").c_str());

  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(device, buffer_, &requirements);
  VkMemoryPropertyFlags required = 0;
  VkMemoryPropertyFlags preferred = 0;
  switch (usage) {
    case BufferUsage::DeviceLocal:
      required = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
      break;
    case BufferUsage::Upload:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      break;
    case BufferUsage::Readback:
      required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
      break;
  }
  if (arena && usage == BufferUsage::DeviceLocal) {
    MemoryArena::Allocation allocation;
    try {
      allocation = arena->allocate(requirements, required, "buffer", name_);
    } catch (...) {
      vkDestroyBuffer(device, buffer_, nullptr);
      throw;
    }
    check(vkBindBufferMemory(device, buffer_, allocation.memory, allocation.offset), "vkBindBufferMemory");
    context.nameObject(VK_OBJECT_TYPE_BUFFER, std::uint64_t(buffer_), name_);
    return;
  }
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = requirements.size;
  alloc.memoryTypeIndex = context.findMemoryType(requirements.memoryTypeBits, required, preferred);
  VkResult result = vkAllocateMemory(device, &alloc, nullptr, &memory_);
  if (result != VK_SUCCESS) {
    vkDestroyBuffer(device, buffer_, nullptr);
    check(result, ("allocating " + std::to_string(size) + " bytes for buffer '" + name_ + "'").c_str());
  }
  allocated_ = alloc.allocationSize;
  memoryType_ = alloc.memoryTypeIndex;
  context.trackAllocation(memoryType_, std::int64_t(allocated_));
  check(vkBindBufferMemory(device, buffer_, memory_, 0), "vkBindBufferMemory");
  if (usage != BufferUsage::DeviceLocal)
    check(vkMapMemory(device, memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
  context.nameObject(VK_OBJECT_TYPE_BUFFER, std::uint64_t(buffer_), name_);
}

Buffer::Buffer(Context& context, const ExternalBuffer& external)
    : context_(context), name_(external.name), size_(external.size), buffer_(external.buffer), sync_(external.state),
      owned_(false) {
  if (!buffer_ || size_ == 0) throw GpuError("buffer '" + name_ + "': no buffer handle or size given");
}

Buffer::~Buffer() {
  if (!owned_) return;
  VkDevice device = context_.device();
  vkDestroyBuffer(device, buffer_, nullptr);
  if (memory_) {
    vkFreeMemory(device, memory_, nullptr);
    context_.trackAllocation(memoryType_, -std::int64_t(allocated_));
  }
}

Image::Image(Context& context, const ExternalImage& external)
    : context_(context), desc_(external.desc), image_(external.image), owned_(false), view_(external.view),
      sync_(external.state) {
  if (!image_ || !view_) throw GpuError("image '" + desc_.name + "': no image or view handle given");
}

Image::Image(Context& context, const ImageDesc& desc, MemoryArena* arena) : context_(context), desc_(desc) {
  const std::uint32_t maxSide = context.properties().limits.maxImageDimension2D;
  if (desc.width == 0 || desc.height == 0 || desc.width > maxSide || desc.height > maxSide)
    throw GpuError("image '" + desc.name + "': size " + std::to_string(desc.width) + "x" + std::to_string(desc.height) +
                   " is outside 1.." + std::to_string(maxSide));
  if (desc.layers == 0 || desc.layers > 2048)
    throw GpuError("image '" + desc.name + "': " + std::to_string(desc.layers) + " layers is outside 1..2048");
  const std::uint32_t fullChain = std::uint32_t(std::bit_width(std::max(desc.width, desc.height)));
  if (desc.mipLevels == 0 || desc.mipLevels > fullChain)
    throw GpuError("image '" + desc.name + "': " + std::to_string(desc.mipLevels) + " mip levels is outside 1.." +
                   std::to_string(fullChain));
  const FormatInfo& format = formatInfo(desc.format);
  VkFormatProperties props;
  vkGetPhysicalDeviceFormatProperties(context.physicalDevice(), desc.format, &props);
  if (desc.storage && !(props.optimalTilingFeatures & VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT))
    throw GpuError("image '" + desc.name + "': this device cannot use " + format.name + " as a storage image");
  if (!(props.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
    throw GpuError("image '" + desc.name + "': this device cannot sample " + format.name);

  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = desc.format;
  info.extent = {desc.width, desc.height, 1};
  info.mipLevels = desc.mipLevels;
  info.arrayLayers = desc.layers;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = (desc.storage ? VK_IMAGE_USAGE_STORAGE_BIT : 0) | VK_IMAGE_USAGE_SAMPLED_BIT |
               VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkDevice device = context.device();
  check(vkCreateImage(device, &info, nullptr, &image_), ("vkCreateImage '" + desc.name + "'").c_str());

  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(device, image_, &requirements);
  if (arena) {
    MemoryArena::Allocation allocation;
    try {
      allocation = arena->allocate(requirements, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, "image", desc.name);
    } catch (...) {
      vkDestroyImage(device, image_, nullptr);
      throw;
    }
    bindImageMemory(context, image_, allocation.memory, allocation.offset, desc.name);
  } else {
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = requirements.size;
    alloc.memoryTypeIndex = context.findMemoryType(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    VkResult result = vkAllocateMemory(device, &alloc, nullptr, &memory_);
    if (result != VK_SUCCESS) {
      vkDestroyImage(device, image_, nullptr);
      check(result, ("allocating memory for image '" + desc.name + "'").c_str());
    }
    allocated_ = alloc.allocationSize;
    memoryType_ = alloc.memoryTypeIndex;
    context.trackAllocation(memoryType_, std::int64_t(allocated_));
    bindImageMemory(context, image_, memory_, 0, desc.name);
  }

  VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  viewInfo.image = image_;
  viewInfo.viewType = desc.layers > 1 || desc.arrayed ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
  viewInfo.format = desc.format;
  viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, desc.mipLevels, 0, desc.layers};
  check(vkCreateImageView(device, &viewInfo, nullptr, &view_), "vkCreateImageView");
  if (desc.mipLevels > 1) {
    for (std::uint32_t level = 0; level < desc.mipLevels; ++level) {
      viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, level, 1, 0, desc.layers};
      VkImageView view = VK_NULL_HANDLE;
      check(vkCreateImageView(device, &viewInfo, nullptr, &view), "vkCreateImageView (mip level)");
      mipViews_.push_back(view);
    }
  }
  context.nameObject(VK_OBJECT_TYPE_IMAGE, std::uint64_t(image_), desc.name);
}

Image::~Image() {
  VkDevice device = context_.device();
  if (!owned_) {
    for (VkImageView view : mipViews_) vkDestroyImageView(device, view, nullptr);
    return;
  }
  for (VkImageView view : mipViews_) vkDestroyImageView(device, view, nullptr);
  vkDestroyImageView(device, view_, nullptr);
  vkDestroyImage(device, image_, nullptr);
  if (memory_) {
    vkFreeMemory(device, memory_, nullptr);
    context_.trackAllocation(memoryType_, -std::int64_t(allocated_));
  }
}

VkImageView Image::mipView(std::uint32_t level) const {
  if (level >= desc_.mipLevels)
    throw GpuError("image '" + desc_.name + "': mip level " + std::to_string(level) + " of " +
                   std::to_string(desc_.mipLevels));
  if (!owned_ && desc_.mipLevels > 1 && mipViews_.empty()) {
    // Another's image comes with one view of all its mips; views of single
    // levels are made the first time one is asked for, and are this wrapper's.
    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = image_;
    viewInfo.viewType = desc_.layers > 1 || desc_.arrayed ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
    viewInfo.format = desc_.format;
    for (std::uint32_t mip = 0; mip < desc_.mipLevels; ++mip) {
      viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, mip, 1, 0, desc_.layers};
      VkImageView view = VK_NULL_HANDLE;
      check(vkCreateImageView(context_.device(), &viewInfo, nullptr, &view), "vkCreateImageView (mip level)");
      mipViews_.push_back(view);
    }
  }
  return mipViews_.empty() ? view_ : mipViews_[level];
}

VkDeviceSize Image::byteSize() const {
  return VkDeviceSize(desc_.width) * desc_.height * formatInfo(desc_.format).bytesPerPixel;
}

HistoryImage::HistoryImage(Context& context, const ImageDesc& desc, MemoryArena* arena) {
  for (std::size_t i = 0; i < images_.size(); ++i) {
    ImageDesc half = desc;
    half.name = desc.name + (i == 0 ? ".ping" : ".pong");
    images_[i] = std::make_unique<Image>(context, half, arena);
  }
}

}  // namespace bounce::gpu
