#include "gi/specular/specular_branch.h"

#include <cmath>

#include <glm/glm.hpp>

#include "gi/cache/radiance_cache.h"
#include "gi/specular/specular_common.glsl"
#include "gi/specular/specular_passes.h"
#include "gi/units.h"
#include "gi/world_queue.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

using namespace gpu::formats;
using gpu::Visualize;

constexpr ImageSpec kImages[] = {
    {"gi.specular.traced0", Resolution::Half, kRgba32ui, false, Visualize::Raw,
     "the trace's fresh reservoirs (hit position, normal) until temporal reuse has read them; then spatial "
     "reuse's: what the resolve evaluates",
     false, true},
    {"gi.specular.traced1", Resolution::Half, kRgba32ui, false, Visualize::Raw,
     "the trace's fresh reservoirs (radiance, M, W, flags); then spatial reuse's", false, true},
    {"gi.specular.pending_rays", Resolution::Half, kRgba32f, false, Visualize::Signed,
     "rays screen space could not finish, left to the world trace: direction (xyz) and its pdf (w; 0: none)", false,
     true},
    {"gi.specular.reservoirs0", Resolution::Half, kRgba32ui, true, Visualize::Raw,
     "temporal reuse's reservoirs: the next frame's history (the Jitter gi pass's feedback point, before spatial "
     "reuse)"},
    {"gi.specular.reservoirs1", Resolution::Half, kRgba32ui, true, Visualize::Raw, "(second half of the pair)"},
    {"gi.specular.resolved", Resolution::Full, kRgba16f, false, Visualize::Radiance,
     "indirect specular, demodulated, before the temporal filter; alpha: hit distance"},
    {"gi.specular.filtered", Resolution::Full, kRgba32f, true, Visualize::Radiance,
     "indirect specular, filtered (the branch's result), demodulated; alpha: history length"},
    {"gi.specular.moments", Resolution::Full, kRgba32f, true, Visualize::Raw,
     "luminance moments: mean and deviation over the history, mean of the fast history"},
    {"gi.specular.reprojection", Resolution::Full, kRgba16f, false, Visualize::Color,
     "which history the filter used: red surface motion, green virtual (reflection) motion, blue history length"},
    {"gi.specular.reservoir_M", Resolution::Half, kR32f, false, Visualize::Heat,
     "the final reservoirs' confidence M (captured frames only)", true},
    {"gi.specular.hit_distance", Resolution::Half, kR32f, false, Visualize::Heat,
     "the final reservoirs' hit distance, world units (captured frames only)", true},
};
static_assert(std::size(kImages) == kSpecularImageCount, "one table entry per SpecularImage");

}  // namespace

std::span<const ImageSpec> specularImageTable() { return kImages; }

struct SpecularBranch::Passes {
  gpu::ComputePass trace, temporalReuse, spatialReuse, resolve, temporalFilter;
  std::unique_ptr<gpu::ComputePass> worldTrace;  // with a bridge that traces only
  std::unique_ptr<gpu::ComputePass> validation;  // made on the first captured frame
  Passes(gpu::Context& context, const SceneBridgeBinding& scene)
      : trace(context, scene.adapt(specularTracePass(), specularTraceRayResources())),
        temporalReuse(context, specularTemporalReusePass()),
        spatialReuse(context, specularSpatialReusePass()),
        resolve(context, specularResolvePass()),
        temporalFilter(context, specularTemporalFilterPass()) {
    if (scene.traces())
      worldTrace = std::make_unique<gpu::ComputePass>(context, scene.adapt(specularWorldTracePass(), cacheResources()));
  }
};

std::uint64_t SpecularBranch::transientBufferBytes(Extent maxSize, bool bridgeTraces) {
  return bridgeTraces ? worldQueueBytes(maxSize) : 0;
}

std::span<const std::size_t> SpecularBranch::unusedImages(bool ownFilter) {
  static constexpr std::size_t kFilterImages[] = {kSpecularFiltered, kSpecularMoments, kSpecularReprojection};
  return ownFilter ? std::span<const std::size_t>() : std::span<const std::size_t>(kFilterImages);
}

SpecularBranch::SpecularBranch(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize,
                               const SpecularBranchSettings& settings, const SceneBridgeBinding& scene, bool ownFilter,
                               gpu::MemoryArena* transientPool)
    : BranchUnit(kSignal, settings.specular.enabled),
      context_(context),
      scene_(scene),
      settings_(settings),
      ownFilter_(ownFilter),
      images_(context, arena, kImages, maxSize, 0, unusedImages(ownFilter), transientPool),
      constants_(std::make_unique<gpu::Buffer>(context, "gi.specular.constants", sizeof(shared::SpecularConstants),
                                               gpu::BufferUsage::DeviceLocal, &arena)),
      passes_(std::make_unique<Passes>(context, scene)) {
  // Written and read only while the branch records: in the transient pool.
  if (scene.traces())
    worldQueue_ = makeWorldQueue(context, transientPool ? *transientPool : arena, maxSize, "gi.specular.world_queue");
}

SpecularBranch::~SpecularBranch() = default;

std::vector<gpu::PassDesc> SpecularBranch::passes() {
  return {specularTracePass(),   specularWorldTracePass(),     specularTemporalReusePass(), specularSpatialReusePass(),
          specularResolvePass(), specularTemporalFilterPass(), specularValidationPass()};
}

std::vector<std::string> SpecularBranch::takes() const {
  std::vector<std::string> takes = {std::string(product::kPreviousSurface), std::string(product::kPreviousComposite),
                                    std::string(product::kLightChange), std::string(product::kCache),
                                    std::string(product::kEnvironment)};
  // The trace marches the pyramid unless its march is off (trace_steps 0).
  if (settings_.specular.traceSteps > 0) takes.emplace_back(product::kDepthPyramid);
  // Without a bridge that traces, the screen-only policy answers the rays screen space cannot decide.
  if (!scene_.traces()) takes.emplace_back(product::kScreenTiles);
  // Rough pixels take the diffuse branch's samples where it offers them (record() falls back to a ray where not).
  if (settings_.specular.diffuseSampleRoughness <= 1.0f) takes.emplace_back(product::kDiffuseReservoirs);
  return takes;
}

void SpecularBranch::record(const FrameState& frame) {
  gpu::Recorder& recorder = frame.recorder;
  const std::uint64_t f = frame.frameIndex;
  const SpecularSettings& s = settings_.specular;
  if (!s.enabled) {
    recorder.clearImage(images_.current(kSpecularFiltered, f), {});  // no indirect specular
    frame.products.put(kSignal, images_.current(kSpecularFiltered, f));
    return;
  }
  const Products& products = frame.products;
  const Extent full = frame.renderSize;
  const Extent half = extentOf(Resolution::Half, full);

  shared::SpecularConstants c{};
  c.sampling = std::uint32_t(s.sampling);
  c.lobeFraction = s.lobeFraction;
  // Without reuse (gi.restir off) every surface keeps its own ray, as a mirror does.
  c.reuseMinRoughness = settings_.restir ? s.reuseMinRoughness : 2.0f;
  c.traceSteps = s.traceSteps;
  c.traceThickness = s.traceThickness;
  c.temporalMaxM = float(s.temporalMaxM);
  c.temporalDepthTolerance = s.temporalDepthTolerance;
  c.temporalCosNormalTolerance = std::cos(glm::radians(s.temporalNormalToleranceDegrees));
  c.spatialSamples = s.spatialSamples;
  c.spatialMaxRadius = s.spatialMaxRadius;
  c.spatialCosNormalTolerance = std::cos(glm::radians(s.spatialNormalToleranceDegrees));
  c.spatialPlaneTolerance = s.spatialPlaneTolerance;
  c.jacobian = s.jacobian ? 1u : 0u;
  c.resolveMaxSamples = s.resolveMaxSamples;
  c.resolveFullRoughness = s.resolveFullRoughness;
  c.resolveMaxRadius = s.resolveMaxRadius;
  c.reprojection = std::uint32_t(s.reprojection);
  c.varianceClippingGamma = s.varianceClippingGamma;
  c.temporalFilterFrames = float(s.temporalFilterFrames);
  c.environmentLevels = float(frame.engine[Input::Environment].desc().mipLevels);
  c.hasPreviousFrame = frame.hasHistory ? 1u : 0u;
  // Without the diffuse branch's tested samples (it is off, the engine
  // gives its own diffuse, or its visibility is not hybrid) every pixel traces.
  const std::span<const gpu::Bind> diffuseSamples = products.binds(product::kDiffuseReservoirs);
  c.diffuseSampleRoughness = diffuseSamples.empty() ? 2.0f : s.diffuseSampleRoughness;
  c.cachedDirectRoughness = s.cachedDirectRoughness;
  recorder.updateBuffer(*constants_, &c, sizeof c);
  const gpu::Bind constants("gIn_SpecularConstants", *constants_);
  const gpu::Bind material("gIn_BaseColorMetallic", frame.engine[Input::BaseColorMetallic], frame.nearestSampler);

  gpu::Image& traced0 = images_.current(kSpecularTraced0, f);
  gpu::Image& traced1 = images_.current(kSpecularTraced1, f);
  gpu::Image& pending = images_.current(kSpecularPendingRays, f);
  const gpu::Bind previousComposite("gPrev_Composite", products.image(product::kPreviousComposite));
  const gpu::Bind previousSurface("gPrev_Surface", products.image(product::kPreviousSurface));
  const gpu::Bind environment("gIn_Environment", frame.engine[Input::Environment], frame.environmentSampler);
  // What --dump-stages shows: only this frame's queued rays (and, without a
  // bridge that traces, an image no pass writes still has a defined layout).
  images_.clearToZero(recorder, {kSpecularPendingRays}, f);
  if (worldQueue_) recorder.fillBuffer(*worldQueue_, 0u);
  std::vector<gpu::Bind> traceBinds = scene_.binds(passes_->trace, {constants,
                                                                    material,
                                                                    previousComposite,
                                                                    previousSurface,
                                                                    environment,
                                                                    {"gOut_Reservoir0", traced0},
                                                                    {"gOut_Reservoir1", traced1},
                                                                    {"gOut_PendingRay", pending}});
  if (worldQueue_) traceBinds.emplace_back("gOut_WorldQueue", *worldQueue_);
  if (diffuseSamples.empty()) {
    // Never read (diffuseSampleRoughness 2): last frame's reservoirs keep the bindings whole.
    traceBinds.emplace_back("gIn_Diffuse_Reservoir0", images_.previous(kSpecularReservoirs0, f));
    traceBinds.emplace_back("gIn_Diffuse_Reservoir1", images_.previous(kSpecularReservoirs1, f));
  } else {
    traceBinds.insert(traceBinds.end(), diffuseSamples.begin(), diffuseSamples.end());
  }
  for (const std::string_view name : {product::kDepthPyramid, product::kScreenTiles}) {
    const std::span<const gpu::Bind> binds = products.binds(name);
    traceBinds.insert(traceBinds.end(), binds.begin(), binds.end());
  }
  const std::span<const gpu::Bind> cache = products.binds(product::kCache);
  traceBinds.insert(traceBinds.end(), cache.begin(), cache.end());
  recorder.dispatch(passes_->trace, half.width, half.height, frame.group.binds(),
                    std::span<const gpu::Bind>(gpu::bindsDeclaredBy(passes_->trace, traceBinds)));
  // The rays screen space left, traced together: one thread each, so a
  // warp's threads all trace instead of waiting on the few that do
  // (docs/benchmarks.md, "World rays").
  if (passes_->worldTrace) {
    std::vector<gpu::Bind> worldBinds = scene_.binds(*passes_->worldTrace, {constants,
                                                                            material,
                                                                            previousComposite,
                                                                            previousSurface,
                                                                            environment,
                                                                            {"gIn_PendingRay", pending},
                                                                            {"gIn_WorldQueue", *worldQueue_},
                                                                            {"gOut_Reservoir0", traced0},
                                                                            {"gOut_Reservoir1", traced1}});
    worldBinds.insert(worldBinds.end(), cache.begin(), cache.end());
    recorder.dispatch(*passes_->worldTrace, half.width, half.height, frame.group.binds(),
                      std::span<const gpu::Bind>(gpu::bindsDeclaredBy(*passes_->worldTrace, worldBinds)));
  }

  // Without reuse (gi.restir off) the resolve reads the trace's reservoirs.
  gpu::Image* final0 = &traced0;
  gpu::Image* final1 = &traced1;
  if (settings_.restir) recordReuse(frame, traced0, traced1, final0, final1);
  if (frame.capturing) {
    if (!passes_->validation) {
      passes_->validation = std::make_unique<gpu::ComputePass>(context_, specularValidationPass());
      images_.makeDebugImages();
    }
    recorder.dispatch(*passes_->validation, half.width, half.height, frame.group.binds(),
                      {{"gIn_Reservoir0", *final0},
                       {"gIn_Reservoir1", *final1},
                       {"gOut_M", images_.current(kSpecularReservoirM, f)},
                       {"gOut_HitDistance", images_.current(kSpecularHitDistance, f)}});
  }

  gpu::Image& resolved = images_.current(kSpecularResolved, f);
  recorder.dispatch(passes_->resolve, full.width, full.height, frame.group.binds(),
                    {constants,
                     material,
                     {"gIn_Reservoir0", *final0},
                     {"gIn_Reservoir1", *final1},
                     {"gOut_Specular", resolved}});
  frame.products.put(product::noisy(kSignal), resolved);
  // A later unit (the denoiser) makes the signal from the resolved one: the filter's images were not made.
  if (!ownFilter_) return;
  recorder.dispatch(passes_->temporalFilter, full.width, full.height, frame.group.binds(),
                    {constants,
                     {"gIn_Motion", frame.engine[Input::Motion], frame.nearestSampler},
                     {"gIn_Specular", resolved},
                     previousSurface,
                     {"gPrev_Filtered", images_.previous(kSpecularFiltered, f)},
                     {"gPrev_Moments", images_.previous(kSpecularMoments, f)},
                     {"gOut_Filtered", images_.current(kSpecularFiltered, f)},
                     {"gOut_Moments", images_.current(kSpecularMoments, f)},
                     {"gOut_Reprojection", images_.current(kSpecularReprojection, f)},
                     {"gIn_LightChange", products.image(product::kLightChange)}});
  frame.products.put(kSignal, images_.current(kSpecularFiltered, f));
}

// Temporal reuse (its output is the next frame's history), then spatial reuse.
void SpecularBranch::recordReuse(const FrameState& frame, gpu::Image& traced0, gpu::Image& traced1,
                                 gpu::Image*& final0, gpu::Image*& final1) {
  gpu::Recorder& recorder = frame.recorder;
  const std::uint64_t f = frame.frameIndex;
  const gpu::Bind constants("gIn_SpecularConstants", *constants_);
  const gpu::Bind material("gIn_BaseColorMetallic", frame.engine[Input::BaseColorMetallic], frame.nearestSampler);
  const Extent half = extentOf(Resolution::Half, frame.renderSize);
  gpu::Image& history0 = images_.current(kSpecularReservoirs0, f);
  gpu::Image& history1 = images_.current(kSpecularReservoirs1, f);
  recorder.dispatch(passes_->temporalReuse, half.width, half.height, frame.group.binds(),
                    {constants,
                     material,
                     {"gIn_Motion", frame.engine[Input::Motion], frame.nearestSampler},
                     {"gPrev_Surface", frame.products.image(product::kPreviousSurface)},
                     {"gIn_Reservoir0", traced0},
                     {"gIn_Reservoir1", traced1},
                     {"gPrev_Reservoir0", images_.previous(kSpecularReservoirs0, f)},
                     {"gPrev_Reservoir1", images_.previous(kSpecularReservoirs1, f)},
                     {"gOut_Reservoir0", history0},
                     {"gOut_Reservoir1", history1},
                     {"gPrev_Composite", frame.products.image(product::kPreviousComposite)},
                     {"gIn_LightChange", frame.products.image(product::kLightChange)}});
  // The traced reservoirs are read by temporal reuse alone: spatial reuse writes over them.
  gpu::Image& spatial0 = traced0;
  gpu::Image& spatial1 = traced1;
  recorder.dispatch(passes_->spatialReuse, half.width, half.height, frame.group.binds(),
                    {constants,
                     material,
                     {"gIn_Reservoir0", history0},
                     {"gIn_Reservoir1", history1},
                     {"gOut_Reservoir0", spatial0},
                     {"gOut_Reservoir1", spatial1}});
  final0 = &spatial0;
  final1 = &spatial1;
}

UnitRegistration specularUnit() {
  return {.name = std::string(SpecularBranch::kSignal),
          .produces =
              [](const UnitSetup&) {
                return std::vector<std::string>{std::string(SpecularBranch::kSignal),
                                                product::noisy(SpecularBranch::kSignal)};
              },
          .make = [](const UnitSetup& setup, const UnitResources& resources) -> std::unique_ptr<Unit> {
            return std::make_unique<SpecularBranch>(resources.context, resources.arena, setup.maxSize,
                                                    SpecularBranch::settingsOf(setup.settings), resources.scene,
                                                    SpecularBranch::ownFilter(setup), resources.transientPool);
          },
          .memoryBytes =
              [](const UnitSetup& setup) {
                return imageSetBytes(specularImageTable(), setup.maxSize, 0,
                                     SpecularBranch::unusedImages(SpecularBranch::ownFilter(setup)));
              },
          .transientBytes =
              [](const UnitSetup& setup) {
                return transientImageBytes(specularImageTable(), setup.maxSize, 0,
                                           SpecularBranch::unusedImages(SpecularBranch::ownFilter(setup))) +
                       SpecularBranch::transientBufferBytes(setup.maxSize, setup.bridgeTraces);
              }};
}

SpecularBranchSettings SpecularBranch::settingsOf(const Settings& settings) {
  return {settings.specular, settings.restir};
}

bool SpecularBranch::ownFilter(const UnitSetup& setup) {
  return branchKeepsOwnFilter(setup, kSignal, setup.settings.specular.enabled);
}

}  // namespace bounce::gi
