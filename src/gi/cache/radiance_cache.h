// The world-space radiance cache (shaders/gi/cache/radiance_cache.glsl;
// docs/gi.md, "The radiance cache"): a hash grid in device buffers, shared
// by the branches whose world rays it lights. Its passes, in frame order:
//   gi.cache.inject    the last frame's filtered indirect diffuse into the cells of its surfaces
//   (the branches query it: gi.diffuse.gather's world hits)
//   gi.cache.update    paths of several bounces from pixels of the frame, adding to every cell they pass
//   gi.cache.resolve   samples into values, eviction of cells unused for max_age frames
//   gi.cache.view      captured frames: each pixel's cell value and cell layout, occupancy
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "bounce/gi_settings.h"
#include "gi/image_table.h"
#include "gi/scene_bridge.h"
#include "gi/unit.h"
#include "gpu/pass.h"
#include "gpu/resources.h"

namespace bounce::gi {

// Bytes a cell takes in the cache's buffers (key, indirect and direct accumulators and values, last use).
constexpr std::uint64_t kCacheBytesPerCell = 4 + 32 + 32 + 4;
// The counts buffer: live cells, and while the light changes the direct light found and held before.
constexpr std::uint64_t kCountsBytes = 12;
// Cells the cache holds within `memoryMib`: the largest power of two that fits.
std::uint32_t cacheCapacity(std::uint32_t memoryMib);
// The cells a cache holds: cacheCapacity(memory_mib) where it can be
// filled (enabled, with a bridge that traces); else one, which keeps every
// binding whole without the 72 MiB of cells nothing would write or read.
std::uint32_t cacheCellsHeld(const CacheSettings& settings, bool bridgeTraces);
// gi.cache.update starts a path at one pixel of every stride x stride block
// of the frame: the smallest stride whose paths' rays (update_bounces each)
// stay within update_rays.
std::uint32_t cacheUpdateStride(Extent renderSize, const CacheSettings& settings);

// The declarations a pass that queries the cache adds (it includes
// gi/cache/radiance_cache.glsl), and the layout of gIn_CacheConstants.
std::vector<gpu::ResourceDecl> cacheResources();
gpu::ConstantsDecl cacheConstantsLayout();

// The cache's debug views (captured frames only).
std::span<const ImageSpec> cacheImageTable();

struct UnitRegistration;
// The cache as a unit (gi/units.h): product "cache" (its buffers, for the
// passes that query it), recorded on the frames a later unit takes it.
UnitRegistration cacheUnit();

class RadianceCache final : public Unit {
 public:
  // `environmentMip`: the level of the environment update rays that miss
  // read (the diffuse branch's rays' level).
  RadianceCache(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize, const CacheSettings& settings,
                float environmentMip, const SceneBridgeBinding& scene);
  ~RadianceCache() override;
  // The bytes of device memory one made for `maxSize`, `settings` and a
  // bridge that traces or not holds.
  static std::uint64_t memoryBytes(Extent maxSize, const CacheSettings& settings, bool bridgeTraces);

  std::uint32_t capacity() const { return capacity_; }

  std::string_view name() const override { return "cache"; }
  Plan plan(const FramePlan& frame) const override;
  // Before the units that query it: clears the cache on the first frame,
  // sets this frame's constants, fills cells from last frame's indirect
  // diffuse (the product "diffuse" of last frame).
  void record(const FrameState& frame) override;
  // After their queries: update rays, resolve, and the view on captured frames.
  void recordAfterConsumers(const FrameState& frame) override;
  std::vector<ImageSet*> imageSets() override { return {&images_}; }
  // The binds of cacheResources() for a pass that queries the cache.
  std::vector<gpu::Bind> binds() const;
  // Every pass the unit may record, debug views included (gi/unit_catalog.h).
  static std::vector<gpu::PassDesc> passes();

 private:
  struct Passes;
  gpu::Context& context_;
  const SceneBridgeBinding& scene_;
  CacheSettings settings_;
  float environmentMip_;  // what update rays that miss read: the level the diffuse branch's rays read
  std::uint32_t capacity_;
  ImageSet images_;
  std::unique_ptr<gpu::Buffer> constants_, keys_, accumulators_, radiance_, touched_, counts_;
  std::unique_ptr<Passes> passes_;
  std::uint32_t frame_ = 0;  // frames since the cache was cleared
};

}  // namespace bounce::gi
