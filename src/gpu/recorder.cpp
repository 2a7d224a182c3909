#include "gpu/recorder.h"

#include <algorithm>
#include <string>

#include "gpu/context.h"
#include "gpu/error.h"
#include "gpu/format.h"

namespace bounce::gpu {
namespace {

constexpr VkPipelineStageFlags2 kCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkPipelineStageFlags2 kTransfer = VK_PIPELINE_STAGE_2_TRANSFER_BIT;

std::string declaredNames(const PassDesc& desc) {
  std::string list;
  for (const ResourceDecl& r : desc.resources) list += (list.empty() ? "" : ", ") + r.name;
  return list;
}

// A copy between `image` and `buffer` of `region` (its mip level's whole
// extent where width or height is 0), checked to lie inside the image and,
// from region.bufferOffset, inside the buffer; `fail` makes the error.
template <class Fail>
VkBufferImageCopy checkedCopy(const Image& image, const Buffer& buffer, const ImageRegion& region, const Fail& fail) {
  if (region.mipLevel >= image.desc().mipLevels || region.layer >= image.desc().layers)
    throw fail("mip level or layer out of range");
  const std::uint32_t levelWidth = image.mipWidth(region.mipLevel);
  const std::uint32_t levelHeight = image.mipHeight(region.mipLevel);
  const std::uint32_t width = region.width ? region.width : levelWidth;
  const std::uint32_t height = region.height ? region.height : levelHeight;
  if (region.x + width > levelWidth || region.y + height > levelHeight) throw fail("region outside the image");
  const VkDeviceSize bytes = VkDeviceSize(width) * height * formatInfo(image.format()).bytesPerPixel;
  if (region.bufferOffset + bytes > buffer.size()) throw fail("buffer is too small");
  VkBufferImageCopy copy{};
  copy.bufferOffset = region.bufferOffset;
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, region.mipLevel, region.layer, 1};
  copy.imageOffset = {std::int32_t(region.x), std::int32_t(region.y), 0};
  copy.imageExtent = {width, height, 1};
  return copy;
}

}  // namespace

Recorder::Recorder(Context& context, VkCommandBuffer commandBuffer, TimestampSink* timestamps)
    : context_(context), cmd_(commandBuffer), timestamps_(timestamps) {}

void Recorder::require(SyncState& state, VkImage image, std::uint32_t mipLevels, VkImageLayout layout,
                       VkPipelineStageFlags2 stage, VkAccessFlags2 access, bool writes) {
  // The same image bound twice to one dispatch (e.g. reading mip k - 1 while
  // writing mip k): barriers within one batch are unordered, so the first
  // one (often a layout transition) must be recorded before the second.
  if (image != VK_NULL_HANDLE &&
      std::any_of(imageBarriers_.begin(), imageBarriers_.end(),
                  [&](const VkImageMemoryBarrier2& pending) { return pending.image == image; }))
    flushBarriers();
  // A layout transition reads and writes the whole image, so it orders
  // against every earlier access, like a write.
  const bool transition = image != VK_NULL_HANDLE && state.layout != layout;
  VkPipelineStageFlags2 srcStage = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 srcAccess = VK_ACCESS_2_NONE;
  bool hazard = false;
  if (writes || transition) {
    // Write after read: wait for the reads. Write after write: wait for the
    // write and make it available, so the two do not race.
    srcStage = state.readStages | state.writeStage;
    srcAccess = state.writeAccess;
    hazard = srcStage != VK_PIPELINE_STAGE_2_NONE;
  } else if (state.writeStage != VK_PIPELINE_STAGE_2_NONE && (state.visibleTo & access) != access) {
    // Read after write, not yet made visible to this kind of read.
    srcStage = state.writeStage;
    srcAccess = state.writeAccess;
    hazard = true;
  }
  if (!autoBarriers_) {
    srcStage = VK_PIPELINE_STAGE_2_NONE;
    srcAccess = VK_ACCESS_2_NONE;
    hazard = false;
  }

  if (image != VK_NULL_HANDLE && (hazard || transition)) {
    VkImageMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    barrier.srcStageMask = srcStage;
    barrier.srcAccessMask = srcAccess;
    barrier.dstStageMask = stage;
    barrier.dstAccessMask = access;
    barrier.oldLayout = state.layout;
    barrier.newLayout = layout;
    barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = image;
    barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, mipLevels, 0, VK_REMAINING_ARRAY_LAYERS};
    imageBarriers_.push_back(barrier);
  } else if (hazard) {
    memoryBarrier_.srcStageMask |= srcStage;
    memoryBarrier_.srcAccessMask |= srcAccess;
    memoryBarrier_.dstStageMask |= stage;
    memoryBarrier_.dstAccessMask |= access;
    memoryBarrierPending_ = true;
  }

  if (image != VK_NULL_HANDLE) state.layout = layout;
  if (writes || transition) {
    // After a transition the image is as if just written at `stage`: later
    // accesses order against it, and it is visible to this access.
    state.writeStage = stage;
    state.writeAccess = access & (VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT);
    state.readStages = writes ? VK_PIPELINE_STAGE_2_NONE : stage;
    // What this command writes is visible to no later access yet (a
    // read-write access reads before it writes); a transition's barrier
    // made it visible to this access.
    state.visibleTo = writes ? VK_ACCESS_2_NONE : access;
  } else {
    state.readStages |= stage;
    if (hazard || state.writeStage == VK_PIPELINE_STAGE_2_NONE) state.visibleTo |= access;
  }
}

void Recorder::flushBarriers() {
  if (imageBarriers_.empty() && !memoryBarrierPending_) return;
  VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dependency.memoryBarrierCount = memoryBarrierPending_ ? 1 : 0;
  dependency.pMemoryBarriers = &memoryBarrier_;
  dependency.imageMemoryBarrierCount = std::uint32_t(imageBarriers_.size());
  dependency.pImageMemoryBarriers = imageBarriers_.data();
  vkCmdPipelineBarrier2(cmd_, &dependency);
  imageBarriers_.clear();
  memoryBarrier_ = {VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  memoryBarrierPending_ = false;
}

void Recorder::writeTimestamp(bool begin, const std::string& passName, const PassTraffic& traffic) {
  if (!timestamps_) return;
  auto index = std::uint32_t(timestamps_->passes.size() * 2 + (begin ? 0 : 1));
  if (index >= timestamps_->capacity)
    throw GpuError("more passes in one frame than the timestamp pool holds (" +
                   std::to_string(timestamps_->capacity / 2) + ")");
  // ALL_COMMANDS on both ends: each pass is timed from the moment all earlier
  // work finished to its own end, so waiting on earlier passes is not
  // charged to it.
  vkCmdWriteTimestamp2(cmd_, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, timestamps_->pool, index);
  if (!begin) {
    timestamps_->passes.push_back(passName);
    timestamps_->traffic.push_back(traffic);
  }
}

std::vector<Bind> bindsDeclaredBy(const ComputePass& pass, std::span<const Bind> binds) {
  std::vector<Bind> declared;
  for (const Bind& bind : binds)
    if (std::any_of(pass.desc().resources.begin(), pass.desc().resources.end(),
                    [&](const ResourceDecl& d) { return d.name == bind.name; }))
      declared.push_back(bind);
  return declared;
}

void Recorder::dispatch(const ComputePass& pass, std::uint32_t width, std::uint32_t height, std::span<const Bind> binds,
                        const void* pushConstants, std::size_t pushConstantBytes) {
  dispatch(pass, width, height, std::span<const Bind>(), binds, pushConstants, pushConstantBytes);
}

void Recorder::dispatch(const ComputePass& pass, std::uint32_t width, std::uint32_t height,
                        std::span<const Bind> group, std::span<const Bind> binds, const void* pushConstants,
                        std::size_t pushConstantBytes) {
  const PassDesc& desc = pass.desc();
  auto fail = [&](const std::string& why) { return GpuError("pass '" + desc.name + "': " + why); };
  if (width == 0 || height == 0) throw fail("dispatch over an empty grid");
  if (pushConstantBytes != desc.pushConstantSize())
    throw fail("push constants of " + std::to_string(pushConstantBytes) + " bytes given, " +
               std::to_string(desc.pushConstantSize()) + " declared");

  // Put the binds into declaration order, checking names as we go.
  ordered_.assign(desc.resources.size(), nullptr);
  for (std::size_t b = 0; b < group.size() + binds.size(); ++b) {
    const Bind& bind = b < group.size() ? group[b] : binds[b - group.size()];
    auto it = std::find_if(desc.resources.begin(), desc.resources.end(),
                           [&](const ResourceDecl& r) { return r.name == bind.name; });
    if (it == desc.resources.end())
      throw fail("no resource named '" + std::string(bind.name) + "' is declared (declared: " + declaredNames(desc) +
                 ")");
    std::size_t index = std::size_t(it - desc.resources.begin());
    if (ordered_[index]) throw fail("'" + it->name + "' is bound twice");
    ordered_[index] = &bind;
  }

  PassTraffic traffic;
  countedLevels_.clear();
  writes_.clear();
  imageInfos_.clear();
  bufferInfos_.clear();
  accesses_.clear();
  // One access per image or buffer, however many bindings it has: a write
  // of one binding followed by a read of another would otherwise count as
  // already made visible to reads (the barrier recorded for the read comes
  // before this dispatch), and the next pass's read would get none.
  const auto addAccess = [&](SyncState& state, VkImage image, std::uint32_t mipLevels, VkImageLayout layout,
                          VkAccessFlags2 flags, bool writes) {
    for (DispatchAccess& earlier : accesses_)
      if (earlier.state == &state) {
        earlier.access |= flags;
        earlier.writes = earlier.writes || writes;
        if (layout == VK_IMAGE_LAYOUT_GENERAL) earlier.layout = layout;
        return;
      }
    accesses_.push_back({&state, image, mipLevels, layout, flags, writes});
  };
  // An image bound for storage anywhere in the dispatch is in GENERAL for all its bindings.
  const auto boundForStorage = [&](const Image& image) {
    for (std::size_t j = 0; j < desc.resources.size(); ++j)
      if (pass.binding(j).kind == ResourceKind::StorageImage && ordered_[j] && ordered_[j]->image == &image)
        return true;
    return false;
  };
  imageInfos_.reserve(desc.resources.size());
  bufferInfos_.reserve(desc.resources.size());
  for (std::size_t i = 0; i < desc.resources.size(); ++i) {
    const ResourceDecl& decl = desc.resources[i];
    // What the pipeline binds there: a declared uniform buffer is a storage
    // buffer in the shader variant for CPU drivers (gpu/constant_block.glsl).
    const ResourceKind kind = pass.binding(i).kind;
    const Bind* bind = ordered_[i];
    if (!bind) throw fail("resource '" + decl.name + "' is not bound");
    const bool isImage = kind == ResourceKind::StorageImage || kind == ResourceKind::SampledImage;
    if (isImage != (bind->image != nullptr))
      throw fail("'" + decl.name + "' needs " + (isImage ? "an image" : "a buffer"));
    const bool writes = decl.access != Access::Read;
    VkAccessFlags2 access = VK_ACCESS_2_NONE;
    switch (kind) {
      case ResourceKind::StorageImage:
      case ResourceKind::StorageBuffer:
        if (decl.access != Access::Write) access |= VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
        if (writes) access |= VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
        break;
      case ResourceKind::SampledImage:
        access = VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;
        break;
      case ResourceKind::UniformBuffer:
        access = VK_ACCESS_2_UNIFORM_READ_BIT;
        break;
    }

    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstBinding = pass.binding(i).binding;
    write.descriptorCount = 1;
    if (isImage) {
      Image& image = *bind->image;
      if (kind == ResourceKind::StorageImage && image.format() != decl.format)
        throw fail("'" + decl.name + "' is declared " + formatName(decl.format) + " (" + formatInfo(decl.format).name +
                   " in GLSL) but image '" + image.name() + "' is " + formatName(image.format()));
      // Storage access needs GENERAL; a sampled read takes the image in the
      // layout it is sampled in (another's image stays in its read-only layout).
      const VkImageLayout layout = kind == ResourceKind::SampledImage && !writes && !boundForStorage(image)
                                       ? image.sampledLayout()
                                       : VK_IMAGE_LAYOUT_GENERAL;
      addAccess(image.sync(), image.handle(), image.desc().mipLevels, layout, access, writes);
      VkDescriptorImageInfo info{};
      // Storage images take one level: the one asked for, else level 0.
      if (bind->mipLevel != Bind::kAllMips)
        info.imageView = image.mipView(bind->mipLevel);
      else
        info.imageView = kind == ResourceKind::StorageImage ? image.mipView(0) : image.view();
      info.imageLayout = layout;
      if (kind == ResourceKind::SampledImage) info.sampler = bind->sampler ? bind->sampler : context_.linearSampler();
      imageInfos_.push_back(info);
      // The levels the view shows: one bound level, a storage image's
      // level 0, or every level of a sampled image; an image bound in two
      // slots (one filling a slot the pass leaves unread) counts once.
      const bool allLevels = bind->mipLevel == Bind::kAllMips && kind == ResourceKind::SampledImage;
      const std::uint32_t first = bind->mipLevel == Bind::kAllMips ? 0 : bind->mipLevel;
      const std::uint32_t end = allLevels ? image.desc().mipLevels : first + 1;
      for (std::uint32_t level = first; level < end; ++level) {
        const std::pair<VkImage, std::uint32_t> key(image.handle(), level);
        if (std::find(countedLevels_.begin(), countedLevels_.end(), key) != countedLevels_.end()) continue;
        countedLevels_.push_back(key);
        traffic.imageBytes +=
            std::uint64_t(image.mipWidth(level)) * image.mipHeight(level) * formatInfo(image.format()).bytesPerPixel;
      }
      write.descriptorType = kind == ResourceKind::SampledImage ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER
                                                                : VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
      write.pImageInfo = &imageInfos_.back();
    } else {
      Buffer& buffer = *bind->buffer;
      // A larger buffer would be bound anyway and read out of range on some
      // devices (VUID-VkWriteDescriptorSet-descriptorType-00333/00332).
      const bool uniform = kind == ResourceKind::UniformBuffer;
      const VkDeviceSize maxRange = uniform ? context_.properties().limits.maxUniformBufferRange
                                            : context_.properties().limits.maxStorageBufferRange;
      if (buffer.size() > maxRange)
        throw fail("buffer '" + buffer.name() + "' (" + std::to_string(buffer.size()) + " bytes) for '" + decl.name +
                   "' is larger than this device binds (" + std::to_string(maxRange) + " bytes)");
      addAccess(buffer.sync(), VK_NULL_HANDLE, 0, VK_IMAGE_LAYOUT_UNDEFINED, access, writes);
      bufferInfos_.push_back({buffer.handle(), 0, VK_WHOLE_SIZE});
      if (!uniform) traffic.bufferBytes += buffer.size();
      write.descriptorType =
          kind == ResourceKind::UniformBuffer ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      write.pBufferInfo = &bufferInfos_.back();
    }
    writes_.push_back(write);
  }
  for (const DispatchAccess& a : accesses_)
    require(*a.state, a.image, a.mipLevels, a.layout, kCompute, a.access, a.writes);
  flushBarriers();

  VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
  label.pLabelName = desc.name.c_str();
  if (context_.cmdBeginDebugLabel) context_.cmdBeginDebugLabel(cmd_, &label);
  writeTimestamp(true, desc.name);
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pass.pipeline());
  context_.cmdPushDescriptorSet(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pass.layout(), 0, std::uint32_t(writes_.size()),
                                writes_.data());
  if (pushConstantBytes)
    vkCmdPushConstants(cmd_, pass.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, std::uint32_t(pushConstantBytes),
                       pushConstants);
  const std::uint32_t* local = pass.localSize();
  vkCmdDispatch(cmd_, (width + local[0] - 1) / local[0], (height + local[1] - 1) / local[1], 1);
  writeTimestamp(false, desc.name, traffic);
  if (context_.cmdEndDebugLabel) context_.cmdEndDebugLabel(cmd_);

  if (captures_) {
    for (std::size_t i = 0; i < desc.resources.size(); ++i) {
      const ResourceDecl& decl = desc.resources[i];
      if (decl.access == Access::Read || !ordered_[i]->image || ordered_[i]->fillsUnusedSlot) continue;
      Image& image = *ordered_[i]->image;
      const std::uint32_t level = ordered_[i]->mipLevel == Bind::kAllMips ? 0 : ordered_[i]->mipLevel;
      const ImageRegion region{.mipLevel = level,
                               .width = std::min(width, image.mipWidth(level)),
                               .height = std::min(height, image.mipHeight(level))};
      const std::string_view label = ordered_[i]->captureLabel;
      CapturedStage capture{.frame = captureFrame_,
                            .pass = desc.name,
                            .binding = label.empty() ? decl.name : std::string(label),
                            .image = image.desc()};
      capture.image.width = region.width;
      capture.image.height = region.height;
      capture.image.mipLevels = 1;
      capture.pending = std::make_shared<Buffer>(context_, "capture." + desc.name + "." + decl.name,
                                                 VkDeviceSize(region.width) * region.height *
                                                     formatInfo(image.format()).bytesPerPixel,
                                                 BufferUsage::Readback);
      copyImageToBuffer(image, *capture.pending, region);
      makeHostReadable(*capture.pending);
      captures_->push_back(std::move(capture));
    }
  }
}

void completeCapture(CapturedStage& capture) {
  if (!capture.pending) return;
  const auto* bytes = static_cast<const std::uint8_t*>(capture.pending->mapped());
  capture.texels.assign(bytes, bytes + capture.pending->size());
  capture.pending.reset();
}

void Recorder::copyBufferToImage(Buffer& source, Image& destination) {
  copyBufferToImage(source, destination, ImageRegion{});
}

void Recorder::copyBufferToImage(Buffer& source, Image& destination, const ImageRegion& region) {
  const VkBufferImageCopy copy = checkedCopy(destination, source, region, [&](const std::string& why) {
    return GpuError("upload to '" + destination.name() + "' from '" + source.name() + "': " + why);
  });
  require(source.sync(), VK_NULL_HANDLE, 0, VK_IMAGE_LAYOUT_UNDEFINED, kTransfer, VK_ACCESS_2_TRANSFER_READ_BIT, false);
  require(destination.sync(), destination.handle(), destination.desc().mipLevels, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
          kTransfer, VK_ACCESS_2_TRANSFER_WRITE_BIT, true);
  flushBarriers();
  vkCmdCopyBufferToImage(cmd_, source.handle(), destination.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
}

void Recorder::copyImageToBuffer(Image& source, Buffer& destination) {
  copyImageToBuffer(source, destination, ImageRegion{});
}

void Recorder::copyImageToBuffer(Image& source, Buffer& destination, const ImageRegion& region) {
  const VkBufferImageCopy copy = checkedCopy(source, destination, region, [&](const std::string& why) {
    return GpuError("readback of '" + source.name() + "' into '" + destination.name() + "': " + why);
  });
  require(source.sync(), source.handle(), source.desc().mipLevels, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, kTransfer,
          VK_ACCESS_2_TRANSFER_READ_BIT, false);
  require(destination.sync(), VK_NULL_HANDLE, 0, VK_IMAGE_LAYOUT_UNDEFINED, kTransfer, VK_ACCESS_2_TRANSFER_WRITE_BIT,
          true);
  flushBarriers();
  vkCmdCopyImageToBuffer(cmd_, source.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, destination.handle(), 1, &copy);
}

void Recorder::copyBuffer(Buffer& source, Buffer& destination, VkDeviceSize bytes) {
  if (bytes > source.size() || bytes > destination.size())
    throw GpuError("copy of " + std::to_string(bytes) + " bytes from '" + source.name() + "' to '" +
                   destination.name() + "' overruns a buffer");
  require(source.sync(), VK_NULL_HANDLE, 0, VK_IMAGE_LAYOUT_UNDEFINED, kTransfer, VK_ACCESS_2_TRANSFER_READ_BIT, false);
  require(destination.sync(), VK_NULL_HANDLE, 0, VK_IMAGE_LAYOUT_UNDEFINED, kTransfer, VK_ACCESS_2_TRANSFER_WRITE_BIT,
          true);
  flushBarriers();
  VkBufferCopy region{0, 0, bytes};
  vkCmdCopyBuffer(cmd_, source.handle(), destination.handle(), 1, &region);
}

void Recorder::updateBuffer(Buffer& destination, const void* data, std::size_t bytes) {
  if (bytes == 0 || bytes % 4 != 0 || bytes > 65536 || bytes > destination.size())
    throw GpuError("update of " + std::to_string(bytes) + " bytes of '" + destination.name() +
                   "': must be a multiple of 4, at most 65536 and fit the buffer");
  require(destination.sync(), VK_NULL_HANDLE, 0, VK_IMAGE_LAYOUT_UNDEFINED, kTransfer, VK_ACCESS_2_TRANSFER_WRITE_BIT,
          true);
  flushBarriers();
  vkCmdUpdateBuffer(cmd_, destination.handle(), 0, bytes, data);
}

void Recorder::clearImage(Image& image, const VkClearColorValue& value) {
  require(image.sync(), image.handle(), image.desc().mipLevels, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, kTransfer,
          VK_ACCESS_2_TRANSFER_WRITE_BIT, true);
  flushBarriers();
  VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, image.desc().mipLevels, 0, image.desc().layers};
  vkCmdClearColorImage(cmd_, image.handle(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &value, 1, &range);
}

void Recorder::fillBuffer(Buffer& buffer, std::uint32_t word) {
  require(buffer.sync(), VK_NULL_HANDLE, 0, VK_IMAGE_LAYOUT_UNDEFINED, kTransfer, VK_ACCESS_2_TRANSFER_WRITE_BIT, true);
  flushBarriers();
  vkCmdFillBuffer(cmd_, buffer.handle(), 0, VK_WHOLE_SIZE, word);
}

void Recorder::handOver(Image& image, VkImageLayout layout, VkPipelineStageFlags2 stage, VkAccessFlags2 access) {
  require(image.sync(), image.handle(), image.desc().mipLevels, layout, stage, access, true);
}

void Recorder::makeHostReadable(Buffer& buffer) {
  require(buffer.sync(), VK_NULL_HANDLE, 0, VK_IMAGE_LAYOUT_UNDEFINED, VK_PIPELINE_STAGE_2_HOST_BIT,
          VK_ACCESS_2_HOST_READ_BIT, false);
  flushBarriers();
}

}  // namespace bounce::gpu
