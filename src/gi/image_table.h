// The declarative table of a GI unit's images (the frame's common images,
// each branch's): name, resolution, format, whether it keeps history, how
// to look at it, what it holds. From one table come the allocation (an
// ImageSet, in the context's memory arena), GiContext::images(), the stage
// dumps' visualisation, and the image tables of docs/passes.md (a test
// compares them). A unit indexes its table with its own enum, so a name
// cannot be misspelled at a use.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/recorder.h"
#include "gpu/resources.h"

namespace bounce::gi {

// How large an image is for a render size (the context's largest when allocating).
enum class Resolution {
  Full,     // the render size
  Half,     // ceil(size / 2): one reservoir per 2x2 pixels
  Pyramid,  // levels 1..n of a 2x2 -> 1 reduction: level k is ceil(size / 2^k)
  Tile,     // ceil(size / 16): one texel per 16x16 tile (the denoiser's classification)
  Single,   // one texel, whatever the size (a whole-screen reduction)
};
const char* resolutionName(Resolution resolution);  // "full", "half", "pyramid", "tile", "single"

struct ImageSpec {
  std::string_view name;  // "gi.diffuse.gathered0"; a pyramid's levels append 1..n
  Resolution resolution;
  VkFormat format;
  bool history;  // two images, this frame's and the last one's, swapping by frame index
  gpu::Visualize view;
  std::string_view purpose;
  bool debug = false;  // made on the first frame whose stages are captured, and only shown then
  // Lives only while its unit records a frame: written and read by the
  // unit's own passes, never by another unit nor a later frame. Its memory
  // is the context's transient pool, which every unit's transient images
  // share (the units record one after another), so its contents are gone
  // once its unit's record ends: not listed by GiContext::images(), seen
  // through the stages --dump-stages captures right after each pass.
  bool transient = false;
};

// A table made at run time, for a unit whose images follow what the engine
// declares (the denoiser's: a set per signal, named after it). It owns the
// names and purposes its specs point to.
class ImageTableBuilder {
 public:
  ImageTableBuilder() = default;
  ImageTableBuilder(const ImageTableBuilder&) = delete;
  ImageTableBuilder& operator=(const ImageTableBuilder&) = delete;
  // Appends `spec` under `name` (and `purpose`, when given).
  void add(std::string name, ImageSpec spec, std::string purpose = {});
  std::span<const ImageSpec> specs() const { return specs_; }

 private:
  std::deque<std::string> text_;  // a deque: growing it moves no string the specs point into
  std::vector<ImageSpec> specs_;
};

struct Extent {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
};
// The size of an image of `resolution` for a render size (a pyramid's `level`).
Extent extentOf(Resolution resolution, Extent renderSize, std::uint32_t level = 1);

// The texel bytes an ImageSet of `table` holds at `maxSize` in its unit's
// own memory: every image made up front (not the debug ones, nor the
// `unused` entries, nor the transient ones), both halves of a history,
// every level of a pyramid. Alignment the driver adds is not counted.
std::uint64_t imageSetBytes(std::span<const ImageSpec> table, Extent maxSize, std::uint32_t pyramidLevels = 0,
                            std::span<const std::size_t> unused = {});
// The same for its transient images alone (what it takes of the transient pool).
std::uint64_t transientImageBytes(std::span<const ImageSpec> table, Extent maxSize, std::uint32_t pyramidLevels = 0,
                                  std::span<const std::size_t> unused = {});

// The images of one table, made for the largest render size.
// A unit's transient buffer (made in the transient pool, as the images of
// ImageSpec::transient): before the unit's first pass of a frame, as
// ImageSet::takeTransients does for images, its first use waits for every
// command recorded before it (other units' images and buffers in the same
// memory).
void takeTransient(gpu::Buffer& buffer);

class ImageSet {
 public:
  // `pyramidLevels`: levels of each Pyramid entry (at least 1 if the table
  // has one). `unused`: entries the unit's settings never use (e.g. a
  // branch's own temporal filter while the denoiser takes its signal),
  // never made nor listed; asking for one is a logic error.
  // `transientPool`: where the transient entries' memory comes from (the
  // context's pool, which other units' transients share); null: `arena`.
  ImageSet(gpu::Context& context, gpu::MemoryArena& arena, std::span<const ImageSpec> table, Extent maxSize,
           std::uint32_t pyramidLevels = 0, std::span<const std::size_t> unused = {},
           gpu::MemoryArena* transientPool = nullptr);
  ~ImageSet();
  ImageSet(const ImageSet&) = delete;
  ImageSet& operator=(const ImageSet&) = delete;

  // Entry `index`: the image (history: this frame's), the last frame's
  // (history only), and a pyramid's level 1..levels.
  gpu::Image& current(std::size_t index, std::uint64_t frameIndex);
  gpu::Image& previous(std::size_t index, std::uint64_t frameIndex);
  gpu::Image& level(std::size_t index, std::uint32_t level);
  std::uint32_t pyramidLevels() const { return pyramidLevels_; }

  // Clears every image of these (non-pyramid) entries, both of a history
  // pair, to zero and leaves them in the layout every library image is in
  // between passes (GENERAL): for entries no pass will write that readers
  // (stage dumps, scans) still list.
  void clearToZero(gpu::Recorder& recorder, std::span<const std::size_t> entries, std::uint64_t frameIndex);
  void clearToZero(gpu::Recorder& recorder, std::initializer_list<std::size_t> entries, std::uint64_t frameIndex) {
    clearToZero(recorder, std::span<const std::size_t>(entries.begin(), entries.size()), frameIndex);
  }

  // Before the unit's first pass of a frame: its transient images' memory
  // held other units' images since it last recorded, so each one's first
  // use waits for every command recorded before it and drops what the
  // memory held (from an undefined layout). Does nothing for a set
  // without transient images made in a pool.
  void takeTransients();

  // Makes the debug entries (those with ImageSpec::debug); later calls do nothing.
  void makeDebugImages();

  struct Listed {
    std::string name;
    gpu::Image* image;
    const ImageSpec* spec;
  };
  // Every image made but the transient ones, this frame's for history
  // entries, pyramids level by level.
  std::vector<Listed> list(std::uint64_t frameIndex);
  std::span<const ImageSpec> table() const { return table_; }

 private:
  struct Entry;
  void make(std::size_t index);
  Entry& entry(std::size_t index);  // throws for an entry not made
  gpu::Context& context_;
  gpu::MemoryArena& arena_;
  std::span<const ImageSpec> table_;
  Extent maxSize_;
  std::uint32_t pyramidLevels_;
  std::vector<std::unique_ptr<Entry>> entries_;
  std::vector<bool> unused_;
  gpu::MemoryArena* transientPool_;
};

}  // namespace bounce::gi
