#include "gi/image_table.h"

#include <algorithm>
#include <stdexcept>

#include "bounce/gi.h"
#include "gpu/format.h"

namespace bounce::gi {

const char* resolutionName(Resolution resolution) {
  switch (resolution) {
    case Resolution::Full:
      return "full";
    case Resolution::Half:
      return "half";
    case Resolution::Pyramid:
      return "pyramid";
    case Resolution::Tile:
      return "tile";
    case Resolution::Single:
      return "single";
  }
  return "?";
}

Extent extentOf(Resolution resolution, Extent renderSize, std::uint32_t level) {
  const auto divide = [](std::uint32_t size, std::uint32_t shift) {
    return std::uint32_t((std::uint64_t(size) + (std::uint64_t(1) << shift) - 1) >> shift);
  };
  switch (resolution) {
    case Resolution::Full:
      return renderSize;
    case Resolution::Half:
      return {divide(renderSize.width, 1), divide(renderSize.height, 1)};
    case Resolution::Pyramid:
      return {divide(renderSize.width, level), divide(renderSize.height, level)};
    case Resolution::Tile:
      return {divide(renderSize.width, 4), divide(renderSize.height, 4)};
    case Resolution::Single:
      return {1, 1};
  }
  return renderSize;
}

void ImageTableBuilder::add(std::string name, ImageSpec spec, std::string purpose) {
  spec.name = text_.emplace_back(std::move(name));
  if (!purpose.empty()) spec.purpose = text_.emplace_back(std::move(purpose));
  specs_.push_back(spec);
}

namespace {

std::uint64_t tableBytes(std::span<const ImageSpec> table, Extent maxSize, std::uint32_t pyramidLevels,
                         std::span<const std::size_t> unused, bool transient) {
  const auto bytes = [](const ImageSpec& spec, Extent size) {
    return std::uint64_t(size.width) * size.height * gpu::formatInfo(spec.format).bytesPerPixel;
  };
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < table.size(); ++i) {
    const ImageSpec& spec = table[i];
    if (spec.debug || spec.transient != transient || std::find(unused.begin(), unused.end(), i) != unused.end())
      continue;
    if (spec.resolution == Resolution::Pyramid)
      for (std::uint32_t level = 1; level <= pyramidLevels; ++level)
        total += bytes(spec, extentOf(spec.resolution, maxSize, level));
    else
      total += bytes(spec, extentOf(spec.resolution, maxSize)) * (spec.history ? 2 : 1);
  }
  return total;
}

}  // namespace

std::uint64_t imageSetBytes(std::span<const ImageSpec> table, Extent maxSize, std::uint32_t pyramidLevels,
                            std::span<const std::size_t> unused) {
  return tableBytes(table, maxSize, pyramidLevels, unused, false);
}

std::uint64_t transientImageBytes(std::span<const ImageSpec> table, Extent maxSize, std::uint32_t pyramidLevels,
                                  std::span<const std::size_t> unused) {
  return tableBytes(table, maxSize, pyramidLevels, unused, true);
}

struct ImageSet::Entry {
  std::unique_ptr<gpu::HistoryImage> history;
  std::vector<std::unique_ptr<gpu::Image>> images;  // one, or a pyramid's levels
};

ImageSet::ImageSet(gpu::Context& context, gpu::MemoryArena& arena, std::span<const ImageSpec> table, Extent maxSize,
                   std::uint32_t pyramidLevels, std::span<const std::size_t> unused, gpu::MemoryArena* transientPool)
    : context_(context),
      arena_(arena),
      table_(table),
      maxSize_(maxSize),
      pyramidLevels_(pyramidLevels),
      unused_(table.size(), false),
      transientPool_(transientPool) {
  for (const std::size_t index : unused) unused_.at(index) = true;
  entries_.resize(table.size());
  for (std::size_t i = 0; i < table.size(); ++i)
    if (!table[i].debug && !unused_[i]) make(i);
}

ImageSet::~ImageSet() = default;

void ImageSet::make(std::size_t index) {
  const ImageSpec& spec = table_[index];
  if (spec.transient && spec.history) throw std::logic_error("gi: a transient image cannot keep history");
  gpu::MemoryArena* memory = spec.transient && transientPool_ ? transientPool_ : &arena_;
  auto entry = std::make_unique<Entry>();
  const auto desc = [&](std::string name, Extent size) {
    return gpu::ImageDesc{
        .name = std::move(name), .width = size.width, .height = size.height, .format = spec.format, .visualize = spec.view};
  };
  if (spec.resolution == Resolution::Pyramid) {
    if (spec.history) throw std::logic_error("gi: a pyramid image cannot keep history");
    for (std::uint32_t level = 1; level <= pyramidLevels_; ++level)
      entry->images.push_back(std::make_unique<gpu::Image>(
          context_, desc(std::string(spec.name) + std::to_string(level), extentOf(spec.resolution, maxSize_, level)),
          memory));
  } else if (spec.history) {
    entry->history = std::make_unique<gpu::HistoryImage>(
        context_, desc(std::string(spec.name), extentOf(spec.resolution, maxSize_)), &arena_);
  } else {
    entry->images.push_back(
        std::make_unique<gpu::Image>(context_, desc(std::string(spec.name), extentOf(spec.resolution, maxSize_)), memory));
  }
  entries_[index] = std::move(entry);
}

namespace {

// As if every command before had written the memory: the first use's
// barrier waits for all of them (other units' images and buffers in this
// memory included); an image moves from an undefined layout, dropping what
// the memory held.
gpu::SyncState discardedState() {
  gpu::SyncState discarded;
  discarded.writeStage = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  discarded.writeAccess = VK_ACCESS_2_MEMORY_WRITE_BIT;
  discarded.readStages = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  discarded.layout = VK_IMAGE_LAYOUT_UNDEFINED;
  return discarded;
}

}  // namespace

void takeTransient(gpu::Buffer& buffer) { buffer.sync() = discardedState(); }

void ImageSet::takeTransients() {
  if (!transientPool_) return;
  const gpu::SyncState discarded = discardedState();
  for (std::size_t i = 0; i < table_.size(); ++i)
    if (entries_[i] && table_[i].transient)
      for (const std::unique_ptr<gpu::Image>& image : entries_[i]->images) image->sync() = discarded;
}

void ImageSet::makeDebugImages() {
  for (std::size_t i = 0; i < table_.size(); ++i)
    if (!entries_[i] && !unused_[i]) make(i);
}

ImageSet::Entry& ImageSet::entry(std::size_t index) {
  if (!entries_.at(index))
    throw std::logic_error("gi: image '" + std::string(table_[index].name) + "' is " +
                           (unused_[index] ? "not used with these settings" : "a debug image not made yet"));
  return *entries_[index];
}

gpu::Image& ImageSet::current(std::size_t index, std::uint64_t frameIndex) {
  Entry& entry = this->entry(index);
  return entry.history ? entry.history->current(frameIndex) : *entry.images.at(0);
}

gpu::Image& ImageSet::previous(std::size_t index, std::uint64_t frameIndex) {
  Entry& entry = this->entry(index);
  if (!entry.history) throw std::logic_error("gi: image '" + std::string(table_[index].name) + "' keeps no history");
  return entry.history->previous(frameIndex);
}

void ImageSet::clearToZero(gpu::Recorder& recorder, std::span<const std::size_t> entries, std::uint64_t frameIndex) {
  const auto clear = [&](gpu::Image& image) {
    recorder.clearImage(image, {});
    recorder.handOver(image, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, kLibraryImageAccess);
  };
  for (const std::size_t index : entries) {
    clear(current(index, frameIndex));
    if (table_[index].history) clear(previous(index, frameIndex));
  }
}

gpu::Image& ImageSet::level(std::size_t index, std::uint32_t level) {
  Entry& entry = this->entry(index);
  if (level == 0 || level > entry.images.size())
    throw std::logic_error("gi: image '" + std::string(table_[index].name) + "' has no level " +
                           std::to_string(level));
  return *entry.images[level - 1];
}

std::vector<ImageSet::Listed> ImageSet::list(std::uint64_t frameIndex) {
  std::vector<Listed> listed;
  for (std::size_t i = 0; i < table_.size(); ++i) {
    if (!entries_[i] || table_[i].transient) continue;
    const ImageSpec& spec = table_[i];
    if (spec.resolution == Resolution::Pyramid) {
      for (std::uint32_t level = 1; level <= entries_[i]->images.size(); ++level)
        listed.push_back({std::string(spec.name) + std::to_string(level), &this->level(i, level), &spec});
    } else {
      listed.push_back({std::string(spec.name), &current(i, frameIndex), &spec});
    }
  }
  return listed;
}

}  // namespace bounce::gi
