// The specular branch (the Jitter gi pass's specular ReSTIR, with Zyanide's uniform-lobe reservoirs as options):
// screen-space ReSTIR for indirect specular at half resolution, resolved at full resolution, then a temporal filter
// with dual-source reprojection. Its passes, in order:
//   gi.specular.trace            half res: one lobe-sampled ray per pixel (depth-buffer march, then the bridge)
//   gi.specular.temporal_reuse   half res: merge with last frame's reservoir (M <= 4); next frame's history
//   gi.specular.spatial_reuse    half res: merge with neighbours in the lobe's footprint
//   gi.specular.resolve          full res: roughness-adaptive reservoirs per pixel, demodulated
//   gi.specular.temporal_filter  full res: surface and virtual-image history, blended
//   gi.specular.validation       captured frames only: reservoir M, hit distance
// docs/gi.md explains the algorithm; docs/passes.md each pass and image.
#pragma once

#include <memory>
#include <span>

#include "bounce/gi_settings.h"
#include "gi/scene_bridge.h"
#include "gi/unit.h"

namespace bounce::gi {

// The branch's images, in the order of specularImageTable().
enum SpecularImage : std::size_t {
  kSpecularTraced0,
  kSpecularTraced1,
  kSpecularPendingRays,
  kSpecularReservoirs0,
  kSpecularReservoirs1,
  kSpecularResolved,
  kSpecularFiltered,
  kSpecularMoments,
  kSpecularReprojection,
  kSpecularReservoirM,
  kSpecularHitDistance,
  kSpecularImageCount
};
std::span<const ImageSpec> specularImageTable();

struct UnitRegistration;
struct UnitSetup;
// The branch as a unit (gi/units.h). Products: "specular.noisy" (the
// resolved signal) and, with its own filter, "specular"; it takes the
// frame's surfaces, last frame's composite, the light change, the cache,
// the depth pyramid (its trace's march) and (screen-only mode) the tiles.
UnitRegistration specularUnit();

// What the branch receives of the settings: its own section and the switch of reuse (gi.restir).
struct SpecularBranchSettings {
  SpecularSettings specular;
  bool restir = true;
};

class SpecularBranch final : public BranchUnit {
 public:
  static constexpr std::string_view kSignal = "specular";
  // `scene`: the bridge rays continue through (it outlives the branch).
  // `ownFilter`, `transientPool`: as DiffuseBranch's.
  SpecularBranch(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize, const SpecularBranchSettings& settings,
                 const SceneBridgeBinding& scene, bool ownFilter, gpu::MemoryArena* transientPool = nullptr);
  ~SpecularBranch() override;
  static SpecularBranchSettings settingsOf(const Settings& settings);
  static bool ownFilter(const UnitSetup& setup);

  void record(const FrameState& frame) override;
  std::vector<ImageSet*> imageSets() override { return {&images_}; }
  std::vector<gpu::Buffer*> transientBuffers() override {
    if (!worldQueue_) return {};
    return {worldQueue_.get()};
  }
  // Every pass the unit may record, debug views included (gi/unit_catalog.h).
  static std::vector<gpu::PassDesc> passes();

  // Device memory of the branch's buffer in the transient pool (counted in
  // its transientBytes): the world-trace queue, with a bridge that traces.
  static std::uint64_t transientBufferBytes(Extent maxSize, bool bridgeTraces);
  // The entries of specularImageTable() a branch without its own filter does not make.
  static std::span<const std::size_t> unusedImages(bool ownFilter);

 private:
  struct Passes;
  std::vector<std::string> takes() const override;
  void recordReuse(const FrameState& frame, gpu::Image& traced0, gpu::Image& traced1, gpu::Image*& final0,
                   gpu::Image*& final1);
  gpu::Context& context_;
  const SceneBridgeBinding& scene_;
  SpecularBranchSettings settings_;
  bool ownFilter_;
  ImageSet images_;
  std::unique_ptr<gpu::Buffer> constants_;
  // The half-resolution pixels whose ray the trace left to the world trace:
  // a count, then the pixels (x | y << 16); with a bridge that traces.
  std::unique_ptr<gpu::Buffer> worldQueue_;
  std::unique_ptr<Passes> passes_;
};

}  // namespace bounce::gi
