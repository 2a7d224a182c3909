#include "gi/cache/radiance_cache.h"

#include <array>

#include "gi/frame_passes.h"
#include "gi/units.h"

#include <bit>
#include <cmath>

#include <glm/glm.hpp>

#include "gi/cache/cache_types.glsl"
#include "gi/frame_constants.h"
#include "gi/gi_shaders.h"
#include "gi/light_change.h"
#include "gpu/constants_layout.h"
#include "gpu/format.h"
#include "gpu/recorder.h"

namespace bounce::gi {
namespace {

using gpu::Access;
using gpu::ResourceDecl;
using gpu::ResourceKind;
using namespace gpu::formats;

enum CacheImage : std::size_t { kCacheRadianceView, kCacheCellsView, kCacheImageCount };

constexpr ImageSpec kImages[] = {
    {"gi.cache.radiance", Resolution::Full, kRgba16f, false, gpu::Visualize::Radiance,
     "each pixel's radiance-cache cell value: what a world ray hitting there is lit with (captured frames only)",
     true},
    {"gi.cache.cells", Resolution::Full, kRgba8, false, gpu::Visualize::Color,
     "each cache cell in a colour of its own; the top bar: share of the slots in use (captured frames only)", true},
};
static_assert(std::size(kImages) == kCacheImageCount, "one table entry per CacheImage");

ResourceDecl buffer(const char* name, Access access, const char* purpose) {
  return {name, access, VK_FORMAT_UNDEFINED, purpose, ResourceKind::StorageBuffer};
}

// A cache pass: the frame constants (binding 0), its own resources, and the
// cache (from binding 4) as far as the shader uses it (declareUsed; the update
// pass's through the bridge's adapt()).
gpu::PassDesc cachePass(const char* name, const char* shader, GroupPart group, std::vector<ResourceDecl> own,
                        bool declareCache = true) {
  std::vector<ResourceDecl> resources = frameGroupDecls(group);
  resources.insert(resources.end(), own.begin(), own.end());
  gpu::PassDesc desc{.name = name,
                     .shader = shader,
                     .shaders = shaders(),
                     .resources = std::move(resources),
                     .constants = {frameConstantsLayout(), cacheConstantsLayout()}};
  if (declareCache) gpu::declareUsed(desc, cacheResources(), false);
  return desc;
}

gpu::PassDesc injectPass() {
  return cachePass(
      "gi.cache.inject", "gi/cache/inject", GroupPart::Constants,
      {{"gPrev_Surface", Access::Read, kRg32ui, "last frame's viewZ and octahedral normal"},
       {"gPrev_Diffuse", Access::Read, VK_FORMAT_UNDEFINED,
        "last frame's filtered indirect diffuse (sampled: any float format)", gpu::ResourceKind::SampledImage},
       lightChangeDecl()});
}

gpu::PassDesc updatePass(bool declareCache = true) {
  return cachePass("gi.cache.update", "gi/cache/update", GroupPart::Surfaces,
                   {{"gIn_Environment", Access::Read, VK_FORMAT_UNDEFINED, "what update rays that miss see",
                     ResourceKind::SampledImage},
                    lightChangeDecl()},
                   declareCache);
}

gpu::PassDesc resolvePass() {
  gpu::PassDesc desc{.name = "gi.cache.resolve",
                     .shader = "gi/cache/resolve",
                     .shaders = shaders(),
                     .resources = {lightChangeDecl()},
                     .constants = {cacheConstantsLayout()}};
  gpu::declareUsed(desc, cacheResources(), false);
  return desc;
}

gpu::PassDesc viewPass() {
  return cachePass("gi.cache.view", "gi/cache/view", GroupPart::Surfaces,
                   {{"gOut_CacheRadiance", Access::Write, kRgba16f, "each pixel's cell value"},
                    {"gOut_CacheCells", Access::Write, kRgba8, "each cell a colour; occupancy bar on top"}});
}

}  // namespace

std::uint32_t cacheCapacity(std::uint32_t memoryMib) {
  const std::uint64_t cells = (std::uint64_t(memoryMib) << 20) / kCacheBytesPerCell;
  return std::uint32_t(std::bit_floor(std::max<std::uint64_t>(cells, 1)));
}

std::uint32_t cacheCellsHeld(const CacheSettings& settings, bool bridgeTraces) {
  return settings.enabled && bridgeTraces ? cacheCapacity(settings.memoryMib) : 1u;
}

std::uint32_t cacheUpdateStride(Extent renderSize, const CacheSettings& settings) {
  const std::uint64_t paths = std::max<std::uint64_t>(settings.updateRays / std::max(settings.updateBounces, 1u), 1);
  const double pixelsPerPath = double(renderSize.width) * double(renderSize.height) / double(paths);
  return std::max(1u, std::uint32_t(std::ceil(std::sqrt(pixelsPerPath))));
}

std::vector<gpu::ResourceDecl> cacheResources() {
  return {
      {"gIn_CacheConstants", Access::Read, VK_FORMAT_UNDEFINED, "the radiance cache's settings this frame",
       ResourceKind::UniformBuffer},
      buffer("gCache_Keys", Access::ReadWrite, "radiance cache: each slot's key checksum (0: empty)"),
      buffer("gCache_Accumulators", Access::ReadWrite,
             "radiance cache: this frame's samples per cell, then its direct light's"),
      buffer("gCache_Radiance", Access::ReadWrite, "radiance cache: each cell's value, then each cell's direct light"),
      buffer("gCache_Touched", Access::ReadWrite, "radiance cache: the last frame each cell was used"),
      buffer("gCache_Counts", Access::ReadWrite,
             "radiance cache: live cells; while the light changes, the direct light its paths find and held before")};
}

gpu::ConstantsDecl cacheConstantsLayout() {
  return BOUNCE_CONSTANTS_LAYOUT("gIn_CacheConstants", shared::CacheConstants, cameraPosition, capacity, enabled, frame,
                                 updateStride, updateBounces, cellSize, historyFrames, maxAge, injectStride,
                                 environmentMip, directLight);
}

struct RadianceCache::Passes {
  gpu::ComputePass inject, resolve;
  std::unique_ptr<gpu::ComputePass> update;  // with a bridge that traces only
  std::unique_ptr<gpu::ComputePass> view;    // made on the first captured frame
  Passes(gpu::Context& context, const SceneBridgeBinding& scene)
      : inject(context, injectPass()), resolve(context, resolvePass()) {
    if (scene.traces())
      update = std::make_unique<gpu::ComputePass>(context, scene.adapt(updatePass(false), cacheResources()));
  }
};

RadianceCache::RadianceCache(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize,
                             const CacheSettings& settings, float environmentMip, const SceneBridgeBinding& scene)
    : context_(context),
      scene_(scene),
      settings_(settings),
      environmentMip_(environmentMip),
      capacity_(cacheCellsHeld(settings, scene.traces())),
      images_(context, arena, kImages, maxSize) {
  const auto make = [&](const char* name, std::uint64_t bytes) {
    return std::make_unique<gpu::Buffer>(context, name, bytes, gpu::BufferUsage::DeviceLocal, &arena);
  };
  constants_ = make("gi.cache.constants", sizeof(shared::CacheConstants));
  keys_ = make("gi.cache.keys", std::uint64_t(capacity_) * 4);
  accumulators_ = make("gi.cache.accumulators", std::uint64_t(capacity_) * 32);  // indirect, then direct light
  radiance_ = make("gi.cache.radiance", std::uint64_t(capacity_) * 32);          // indirect, then direct light
  touched_ = make("gi.cache.touched", std::uint64_t(capacity_) * 4);
  counts_ = make("gi.cache.counts", kCountsBytes);
  passes_ = std::make_unique<Passes>(context, scene);
}

RadianceCache::~RadianceCache() = default;

std::uint64_t RadianceCache::memoryBytes(Extent maxSize, const CacheSettings& settings, bool bridgeTraces) {
  // keys, accumulators, radiance, touched (as the constructor makes them) and the counts.
  return imageSetBytes(kImages, maxSize) + std::uint64_t(cacheCellsHeld(settings, bridgeTraces)) * kCacheBytesPerCell +
         kCountsBytes + sizeof(shared::CacheConstants);
}

std::vector<gpu::Bind> RadianceCache::binds() const {
  return {{"gIn_CacheConstants", *constants_}, {"gCache_Keys", *keys_},       {"gCache_Accumulators", *accumulators_},
          {"gCache_Radiance", *radiance_},     {"gCache_Touched", *touched_}, {"gCache_Counts", *counts_}};
}

std::span<const ImageSpec> cacheImageTable() { return kImages; }

std::vector<gpu::PassDesc> RadianceCache::passes() { return {injectPass(), updatePass(), resolvePass(), viewPass()}; }

Unit::Plan RadianceCache::plan(const FramePlan& frame) const {
  return {.records = frame.wanted.contains(product::kCache),
          .takes = {std::string(product::kPreviousSurface), std::string(product::kLightChange),
                    std::string(product::kEnvironment)}};
}

void RadianceCache::record(const FrameState& frame) {
  gpu::Recorder& recorder = frame.recorder;
  const std::array<float, 3>& cameraPosition = frame.cameraPosition;
  if (frame_ == 0)
    for (gpu::Buffer* b : {keys_.get(), accumulators_.get(), radiance_.get(), touched_.get()})
      recorder.fillBuffer(*b, 0u);
  ++frame_;
  shared::CacheConstants c{};
  c.cameraPosition = glm::vec4(cameraPosition[0], cameraPosition[1], cameraPosition[2], 1.0f);
  c.capacity = capacity_;
  c.enabled = settings_.enabled && scene_.traces() ? 1u : 0u;
  c.frame = frame_;
  c.updateStride = cacheUpdateStride(frame.renderSize, settings_);
  c.updateBounces = settings_.updateBounces;
  c.cellSize = settings_.cellSize;
  c.historyFrames = float(settings_.historySamples);
  c.maxAge = settings_.maxAge;
  c.injectStride = settings_.injectStride;
  c.environmentMip = environmentMip_;
  c.directLight = settings_.directLight ? 1u : 0u;
  recorder.updateBuffer(*constants_, &c, sizeof c);
  frame.products.put(product::kCache, binds());
  // The cells are filled from last frame's indirect diffuse as the
  // composite read it (the denoiser's, or the branch's own filter's).
  gpu::Image* previousDiffuse = frame.previous.find(kLibrarySignals[kDiffuseSignal].name);
  if (!c.enabled || !frame.usableHistory || !previousDiffuse) return;
  const std::uint32_t stride = settings_.injectStride;
  std::vector<gpu::Bind> binds = this->binds();
  binds.insert(binds.end(), {{"gPrev_Surface", frame.products.image(product::kPreviousSurface)},
                             {"gPrev_Diffuse", *previousDiffuse, frame.nearestSampler},
                             {"gIn_LightChange", frame.products.image(product::kLightChange)}});
  recorder.dispatch(passes_->inject, (frame.renderSize.width + stride - 1) / stride,
                    (frame.renderSize.height + stride - 1) / stride, frame.group.binds(GroupPart::Constants),
                    std::span<const gpu::Bind>(gpu::bindsDeclaredBy(passes_->inject, binds)));
}

void RadianceCache::recordAfterConsumers(const FrameState& frame) {
  if (!settings_.enabled || !scene_.traces()) return;
  gpu::Recorder& recorder = frame.recorder;
  gpu::Image& lightChange = frame.products.image(product::kLightChange);
  // gi.cache.update sums the change of light into them, gi.cache.resolve counts the live cells anew.
  recorder.fillBuffer(*counts_, 0u);
  if (settings_.updateRays > 0) {
    std::vector<gpu::Bind> binds = this->binds();
    binds.push_back({"gIn_Environment", frame.engine[Input::Environment], frame.environmentSampler});
    binds.push_back({"gIn_LightChange", lightChange});
    const std::vector<gpu::Bind> bridged = scene_.binds(*passes_->update, {});
    binds.insert(binds.end(), bridged.begin(), bridged.end());
    const std::uint32_t stride = cacheUpdateStride(frame.renderSize, settings_);
    recorder.dispatch(*passes_->update, (frame.renderSize.width + stride - 1) / stride,
                      (frame.renderSize.height + stride - 1) / stride, frame.group.binds(),
                      std::span<const gpu::Bind>(gpu::bindsDeclaredBy(*passes_->update, binds)));
  }
  std::vector<gpu::Bind> resolveBinds = this->binds();
  resolveBinds.push_back({"gIn_LightChange", lightChange});
  recorder.dispatch(passes_->resolve, capacity_, 1,
                    std::span<const gpu::Bind>(gpu::bindsDeclaredBy(passes_->resolve, resolveBinds)));
  if (frame.capturing) {
    if (!passes_->view) {
      passes_->view = std::make_unique<gpu::ComputePass>(context_, viewPass());
      images_.makeDebugImages();
    }
    std::vector<gpu::Bind> viewBinds = this->binds();
    viewBinds.insert(viewBinds.end(), {{"gOut_CacheRadiance", images_.current(kCacheRadianceView, frame.frameIndex)},
                                       {"gOut_CacheCells", images_.current(kCacheCellsView, frame.frameIndex)}});
    recorder.dispatch(*passes_->view, frame.renderSize.width, frame.renderSize.height, frame.group.binds(),
                      std::span<const gpu::Bind>(gpu::bindsDeclaredBy(*passes_->view, viewBinds)));
  }
}

UnitRegistration cacheUnit() {
  return {.name = "cache",
          .produces = [](const UnitSetup&) { return std::vector<std::string>{std::string(product::kCache)}; },
          .make = [](const UnitSetup& setup, const UnitResources& resources) -> std::unique_ptr<Unit> {
            // Its update rays that miss read the environment at the level the diffuse branch's rays read.
            return std::make_unique<RadianceCache>(resources.context, resources.arena, setup.maxSize,
                                                   setup.settings.cache, setup.settings.diffuse.environmentMip,
                                                   resources.scene);
          },
          .memoryBytes =
              [](const UnitSetup& setup) {
                return RadianceCache::memoryBytes(setup.maxSize, setup.settings.cache, setup.bridgeTraces);
              }};
}

}  // namespace bounce::gi
