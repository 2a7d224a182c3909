// The diffuse branch (the Jitter gi pass's diffuse ReSTIR): screen-space ReSTIR GI at half resolution,
// resolved at full resolution with screen-space visibility, then a
// temporal filter. Its passes, in order:
//   gi.diffuse.bright_pixels(_reduce)  the last frame's brightest pixels, 2x2 -> 1 per level
//   gi.diffuse.gather                  half res: candidates into one reservoir per pixel
//   gi.diffuse.temporal_reuse          half res: merge with last frame's reservoir
//   gi.diffuse.spatial_reuse           half res: merge with neighbours, twice; each time
//     gi.diffuse.neighbour_visibility  (a bridge that traces) the neighbours' visibility tests it queued
//     gi.diffuse.spatial_normalize     and their verdicts counted in
//   gi.diffuse.sample_visibility       half res (hybrid, a bridge that traces): hidden samples dropped
//   gi.diffuse.resolve                 full res: indirect diffuse
//   gi.diffuse.temporal_filter         full res: reprojected history, clamped to the fast history
// docs/gi.md explains the algorithm; docs/passes.md each pass and image.
#pragma once

#include <memory>
#include <span>

#include "bounce/gi_settings.h"
#include "gi/scene_bridge.h"
#include "gi/unit.h"

namespace bounce::gi {

// The branch's images, in the order of diffuseImageTable().
enum DiffuseImage : std::size_t {
  kGathered0,
  kGathered1,
  kTransient0,
  kTransient1,
  kReservoirs0,
  kReservoirs1,
  kResolved,
  kFiltered,
  kMoments,
  kBrightLevels,
  kReservoirEstimate,
  kReservoirM,
  kReservoirW,
  kTestSummary,
  kDiffuseImageCount
};
std::span<const ImageSpec> diffuseImageTable();

// Levels of the bright-pixel pyramid for a render size: halving until about
// `brightPixels` entries remain (at least one level).
std::uint32_t brightPyramidLevels(Extent renderSize, std::uint32_t brightPixels);

struct UnitRegistration;
struct UnitSetup;
// The branch as a unit (gi/units.h). Products: "diffuse.noisy" (the
// resolved signal) and, with its own filter, "diffuse" (the filtered one);
// it takes the frame's surfaces, last frame's composite, the light change,
// the cache and (screen-only mode) the screen tiles.
UnitRegistration diffuseUnit();

// What the branch receives of the settings: its own section, the switch of
// reuse (gi.restir) and its share of the ray budget (planWorldRays).
struct DiffuseBranchSettings {
  DiffuseSettings diffuse;
  bool restir = true;
  WorldRayPlan rays;
};

class DiffuseBranch final : public BranchUnit {
 public:
  static constexpr std::string_view kSignal = "diffuse";
  // `scene`: the bridge the gather, reuse and resolve trace through (it
  // outlives the branch). `ownFilter`: the branch runs its own temporal
  // filter on some frames (no later unit makes its signal from the resolved
  // one, or it is disabled and its result is the cleared filter image);
  // without, the filter's images are not made (unusedImages).
  // `transientPool`: where its transient images live (the context's; null: `arena`).
  DiffuseBranch(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize, const DiffuseBranchSettings& settings,
                const SceneBridgeBinding& scene, bool ownFilter, gpu::MemoryArena* transientPool = nullptr);
  ~DiffuseBranch() override;
  static DiffuseBranchSettings settingsOf(const Settings& settings);
  static bool ownFilter(const UnitSetup& setup);

  void record(const FrameState& frame) override;
  std::vector<ImageSet*> imageSets() override { return {&images_}; }
  std::vector<gpu::Buffer*> transientBuffers() override {
    if (!pendingRays_) return {};
    return {pendingRays_.get(), worldQueue_.get(), neighbourTests_.get(), testQueue_.get()};
  }
  // Every pass the unit may record, debug views included (gi/unit_catalog.h).
  static std::vector<gpu::PassDesc> passes();

  // Device memory of the branch's buffers, all in the transient pool
  // (counted in its transientBytes): with a bridge that traces, the rays
  // waiting for gi.diffuse.world_candidates and their queue, and spatial
  // reuse's visibility tests and theirs.
  static std::uint64_t transientBufferBytes(Extent maxSize, const DiffuseBranchSettings& settings, bool bridgeTraces);
  // The entries of diffuseImageTable() a branch without its own filter does not make.
  static std::span<const std::size_t> unusedImages(bool ownFilter);

 private:
  struct Passes;
  std::vector<std::string> takes() const override;
  void recordReuse(const FrameState& frame, gpu::Image*& final0, gpu::Image*& final1);
  void viewReservoirs(const FrameState& frame, std::size_t after, gpu::Image& first, gpu::Image& second);

  gpu::Context& context_;
  const SceneBridgeBinding& scene_;
  DiffuseBranchSettings settings_;
  WorldRayPlan plan_;  // how the ray budget is spent (settings_.rays)
  bool ownFilter_;
  ImageSet images_;
  std::unique_ptr<gpu::Buffer> constants_;
  // With a bridge that traces: per reservoir and ray candidate, the
  // direction of a ray the gather left to the world trace; and the queue of
  // their pixels (a count, then x | y << 16).
  std::unique_ptr<gpu::Buffer> pendingRays_, worldQueue_;
  // With a bridge that traces: spatial reuse's visibility tests (per pixel
  // testSlots_ of them) and their queue (gi/diffuse/neighbour_tests.glsl).
  std::uint32_t testSlots_ = 0;
  std::unique_ptr<gpu::Buffer> neighbourTests_, testQueue_;
  std::unique_ptr<Passes> passes_;
};

}  // namespace bounce::gi
