#include "gi/diffuse/diffuse_branch.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/glm.hpp>

#include "gi/cache/radiance_cache.h"
#include "gi/diffuse/diffuse_common.glsl"
#include "gi/diffuse/diffuse_passes.h"
#include "gi/units.h"
#include "gi/world_queue.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

using namespace gpu::formats;
using gpu::Visualize;

constexpr ImageSpec kImages[] = {
    {"gi.diffuse.gathered0", Resolution::Half, kRgba32ui, false, Visualize::Raw,
     "gather's fresh reservoirs (sample position, normal) until temporal reuse has read them; then the first "
     "spatial pass's output",
     false, true},
    {"gi.diffuse.gathered1", Resolution::Half, kRgba32ui, false, Visualize::Raw,
     "gather's fresh reservoirs (radiance, M, W, flags); then the first spatial pass's output", false, true},
    {"gi.diffuse.transient0", Resolution::Half, kRgba32ui, false, Visualize::Raw,
     "reservoirs of the reuse stage not kept for the next frame"},
    {"gi.diffuse.transient1", Resolution::Half, kRgba32ui, false, Visualize::Raw, "(second half of the pair)"},
    {"gi.diffuse.reservoirs0", Resolution::Half, kRgba32ui, true, Visualize::Raw,
     "the reservoirs the next frame's temporal reuse starts from"},
    {"gi.diffuse.reservoirs1", Resolution::Half, kRgba32ui, true, Visualize::Raw, "(second half of the pair)"},
    {"gi.diffuse.resolved", Resolution::Full, kRgba16f, false, Visualize::Radiance,
     "indirect diffuse, demodulated, before the temporal filter"},
    {"gi.diffuse.filtered", Resolution::Full, kRgba32f, true, Visualize::Radiance,
     "indirect diffuse, filtered (the branch's result); alpha: history length"},
    {"gi.diffuse.moments", Resolution::Full, kRgba32f, true, Visualize::Raw,
     "luminance moments: mean and deviation over the history, mean of the fast history"},
    {"gi.diffuse.bright_level", Resolution::Pyramid, kRgba32f, false, Visualize::Raw,
     "the last frame's brightest pixel per 2^k x 2^k tile: brightness, x, y, valid", false, true},
    {"gi.diffuse.reservoir_estimate", Resolution::Half, kRgba16f, false, Visualize::Radiance,
     "a reservoir's estimate at its own surface (captured frames only)", true},
    {"gi.diffuse.reservoir_M", Resolution::Half, kR32f, false, Visualize::Heat,
     "a reservoir's confidence M (captured frames only)", true},
    {"gi.diffuse.reservoir_W", Resolution::Half, kR32f, false, Visualize::Heat,
     "a reservoir's contribution weight W (captured frames only)", true},
    {"gi.diffuse.neighbour_tests", Resolution::Half, kRgba32f, false, Visualize::Raw,
     "the last spatial pass's visibility tests: queued, M untested, confidence if all see, M hidden"},
};
static_assert(std::size(kImages) == kDiffuseImageCount, "one table entry per DiffuseImage");

// The reservoir passes gi.diffuse.reservoir_view shows, in recorded order.
constexpr const char* kViewAfter[] = {"gather", "temporal_reuse", "spatial_reuse1", "spatial_reuse2"};

}  // namespace

std::span<const ImageSpec> diffuseImageTable() { return kImages; }

std::uint32_t brightPyramidLevels(Extent renderSize, std::uint32_t brightPixels) {
  std::uint32_t levels = 0;
  Extent level = renderSize;
  do {
    level = extentOf(Resolution::Half, level);
    ++levels;
  } while (std::uint64_t(level.width) * level.height > brightPixels && (level.width > 1 || level.height > 1));
  return levels;
}

struct DiffuseBranch::Passes {
  gpu::ComputePass brightPixels, brightReduce, gather, temporalReuse, spatialReuse, sampleMarch, resolve,
      temporalFilter;
  // Only with a bridge that traces (their shaders have nothing to do without one).
  std::unique_ptr<gpu::ComputePass> sampleVisibility, worldCandidates, neighbourVisibility, spatialNormalize;
  std::vector<std::unique_ptr<gpu::ComputePass>> reservoirViews;  // made on the first captured frame
  Passes(gpu::Context& context, const SceneBridgeBinding& scene)
      : brightPixels(context, brightPixelsPass()),
        brightReduce(context, brightPixelsReducePass()),
        gather(context, scene.adapt(gatherPass(), gatherRayResources())),
        temporalReuse(context, scene.adapt(temporalReusePass())),
        spatialReuse(context, scene.adapt(spatialReusePass(), neighbourTestResources())),
        sampleMarch(context, sampleMarchPass()),
        resolve(context, scene.adapt(resolvePass())),
        temporalFilter(context, temporalFilterPass()),
        sampleVisibility(scene.traces()
                             ? std::make_unique<gpu::ComputePass>(context, scene.adapt(sampleVisibilityPass()))
                             : nullptr),
        worldCandidates(scene.traces() ? std::make_unique<gpu::ComputePass>(
                                             context, scene.adapt(worldCandidatesPass(), cacheResources()))
                                       : nullptr),
        neighbourVisibility(scene.traces()
                                ? std::make_unique<gpu::ComputePass>(context, scene.adapt(neighbourVisibilityPass()))
                                : nullptr),
        spatialNormalize(scene.traces() ? std::make_unique<gpu::ComputePass>(context, spatialNormalizePass())
                                        : nullptr) {}
};

namespace {

// The waiting rays' directions: a vec4 per reservoir and ray candidate the
// budget allows (the queue is gi/world_queue.h's).
std::uint64_t pendingRayBytes(Extent maxSize, const WorldRayPlan& plan) {
  const Extent half = extentOf(Resolution::Half, maxSize);
  return std::uint64_t(half.width) * half.height * std::max(1u, plan.diffuseCandidates) * 16;
}

// How many neighbours one spatial pass may ask for their visibility of the
// chosen sample with a ray: every one it merges with the unbiased option,
// else the plan's sky tests (none when they are off or there is no reuse).
std::uint32_t neighbourTestSlots(const DiffuseBranchSettings& settings, const WorldRayPlan& plan) {
  const DiffuseSettings& d = settings.diffuse;
  if (!settings.restir) return 0;
  if (d.reuseVisibility) return std::min(std::max(d.spatialSamples, d.spatial2Samples), shared::kMaxSpatialNeighbours);
  return plan.skyReuseRays;
}

// The tests: a uvec2 per pixel and slot.
std::uint64_t neighbourTestBytes(Extent maxSize, std::uint32_t slots) {
  const Extent half = extentOf(Resolution::Half, maxSize);
  return std::uint64_t(half.width) * half.height * std::max(1u, slots) * 8;
}

}  // namespace

std::uint64_t DiffuseBranch::transientBufferBytes(Extent maxSize, const DiffuseBranchSettings& settings, bool bridgeTraces) {
  if (!bridgeTraces) return 0;
  const WorldRayPlan& plan = settings.rays;
  const std::uint32_t slots = neighbourTestSlots(settings, plan);
  return pendingRayBytes(maxSize, plan) + worldQueueBytes(maxSize) + neighbourTestBytes(maxSize, slots) +
         worldQueueBytes(maxSize, std::max(1u, slots));
}

std::span<const std::size_t> DiffuseBranch::unusedImages(bool ownFilter) {
  static constexpr std::size_t kFilterImages[] = {kFiltered, kMoments};
  return ownFilter ? std::span<const std::size_t>() : std::span<const std::size_t>(kFilterImages);
}

DiffuseBranch::DiffuseBranch(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize,
                             const DiffuseBranchSettings& settings, const SceneBridgeBinding& scene, bool ownFilter,
                             gpu::MemoryArena* transientPool)
    : BranchUnit(kSignal, settings.diffuse.enabled),
      context_(context),
      scene_(scene),
      settings_(settings),
      plan_(settings.rays),
      ownFilter_(ownFilter),
      images_(context, arena, kImages, maxSize, brightPyramidLevels(maxSize, settings.diffuse.brightPixels),
              unusedImages(ownFilter), transientPool),
      constants_(std::make_unique<gpu::Buffer>(context, "gi.diffuse.constants", sizeof(shared::DiffuseConstants),
                                               gpu::BufferUsage::DeviceLocal, &arena)),
      passes_(std::make_unique<Passes>(context, scene)) {
  if (scene.traces()) {
    // Written and read only while the branch records: in the transient pool.
    gpu::MemoryArena& frameLocal = transientPool ? *transientPool : arena;
    pendingRays_ = std::make_unique<gpu::Buffer>(context, "gi.diffuse.pending_rays", pendingRayBytes(maxSize, plan_),
                                                 gpu::BufferUsage::DeviceLocal, &frameLocal);
    worldQueue_ = makeWorldQueue(context, frameLocal, maxSize, "gi.diffuse.world_queue");
    testSlots_ = neighbourTestSlots(settings, plan_);
    neighbourTests_ = std::make_unique<gpu::Buffer>(context, "gi.diffuse.neighbour_test_slots",
                                                    neighbourTestBytes(maxSize, testSlots_),
                                                    gpu::BufferUsage::DeviceLocal, &frameLocal);
    testQueue_ =
        makeWorldQueue(context, frameLocal, maxSize, "gi.diffuse.neighbour_test_queue", std::max(1u, testSlots_));
  }
}

DiffuseBranch::~DiffuseBranch() = default;

std::vector<gpu::PassDesc> DiffuseBranch::passes() {
  std::vector<gpu::PassDesc> list = {brightPixelsPass(),
                                     brightPixelsReducePass(),
                                     gatherPass(),
                                     worldCandidatesPass(),
                                     temporalReusePass(),
                                     spatialReusePass(),
                                     neighbourVisibilityPass(),
                                     spatialNormalizePass(),
                                     sampleVisibilityPass(),
                                     sampleMarchPass(),
                                     resolvePass(),
                                     temporalFilterPass()};
  for (const char* after : kViewAfter) list.push_back(reservoirViewPass(after));
  return list;
}

void DiffuseBranch::viewReservoirs(const FrameState& frame, std::size_t after, gpu::Image& first,
                                   gpu::Image& second) {
  if (passes_->reservoirViews.empty()) {
    for (const char* name : kViewAfter)
      passes_->reservoirViews.push_back(std::make_unique<gpu::ComputePass>(context_, reservoirViewPass(name)));
    images_.makeDebugImages();
  }
  const Extent half = extentOf(Resolution::Half, frame.renderSize);
  const std::uint64_t f = frame.frameIndex;
  frame.recorder.dispatch(*passes_->reservoirViews[after], half.width, half.height, frame.group.binds(),
                          {{"gIn_Reservoir0", first},
                           {"gIn_Reservoir1", second},
                           {"gOut_Estimate", images_.current(kReservoirEstimate, f)},
                           {"gOut_M", images_.current(kReservoirM, f)},
                           {"gOut_W", images_.current(kReservoirW, f)}});
}

std::vector<std::string> DiffuseBranch::takes() const {
  std::vector<std::string> takes = {std::string(product::kPreviousSurface), std::string(product::kPreviousComposite),
                                    std::string(product::kMarchDepth),      std::string(product::kLightChange),
                                    std::string(product::kCache),           std::string(product::kEnvironment)};
  // Without a bridge that traces, the screen-only policy answers the rays screen space cannot decide.
  if (!scene_.traces()) takes.emplace_back(product::kScreenTiles);
  return takes;
}

void DiffuseBranch::record(const FrameState& frame) {
  gpu::Recorder& recorder = frame.recorder;
  const std::uint64_t f = frame.frameIndex;
  const DiffuseSettings& d = settings_.diffuse;
  if (!d.enabled) {
    recorder.clearImage(images_.current(kFiltered, f), {});  // no indirect diffuse: the composite is the direct light
    frame.products.put(kSignal, images_.current(kFiltered, f));
    return;
  }
  const Products& products = frame.products;
  gpu::Image& previousComposite = products.image(product::kPreviousComposite);
  gpu::Image& previousSurface = products.image(product::kPreviousSurface);
  gpu::Image& marchDepth = products.image(product::kMarchDepth);
  const Extent full = frame.renderSize;
  const Extent half = extentOf(Resolution::Half, full);
  const std::uint32_t levels = brightPyramidLevels(full, d.brightPixels);
  const Extent lastLevel = extentOf(Resolution::Pyramid, full, levels);

  shared::DiffuseConstants c{};
  c.brightLevelSize = glm::uvec2(lastLevel.width, lastLevel.height);
  c.brightLevel = levels;
  // Without last frame's composite there is nothing on screen to gather from.
  c.screenCandidates = frame.hasHistory ? d.screenCandidates : 0u;
  c.brightCandidates = frame.hasHistory ? d.brightCandidates : 0u;
  c.targetFunction = std::uint32_t(d.target);
  c.resolveReservoirs = d.resolveReservoirs;
  c.visibilitySteps = d.visibilitySteps;
  c.jacobian = d.jacobian ? 1u : 0u;
  c.temporalMaxM = float(d.temporalMaxM);
  c.temporalDepthTolerance = d.temporalDepthTolerance;
  c.temporalCosNormalTolerance = std::cos(glm::radians(d.temporalNormalToleranceDegrees));
  c.environmentMip = d.environmentMip;
  c.spatialCosNormalTolerance = std::cos(glm::radians(d.spatialNormalToleranceDegrees));
  c.spatialPlaneTolerance = d.spatialPlaneTolerance;
  c.visibilityThickness = d.visibilityThickness;
  c.varianceClippingGamma = d.varianceClippingGamma;
  c.temporalFilterFrames = float(d.temporalFilterFrames);
  const bool traces = scene_.traces();
  // The ray budget may cut ray candidates and sky tests (plan_).
  c.rayCandidates = traces ? plan_.diffuseCandidates : 0u;
  c.environmentCandidates = traces ? 0u : d.environmentCandidates;
  c.rayScreenSteps = d.rayScreenSteps;
  c.visibilityMode = traces ? std::uint32_t(d.visibility) : std::uint32_t(Visibility::Screen);
  c.reuseVisibility = traces && d.reuseVisibility ? 1u : 0u;
  c.skyReuseVisibility = traces && d.skyReuseVisibility ? 1u : 0u;
  c.skyReuseRays = plan_.skyReuseRays;
  // Per reservoir: hybrid trusts the sample-visibility rays; screen mode
  // marches each reservoir once (gi.diffuse.sample_march).
  const bool perReservoir = c.visibilityMode == std::uint32_t(Visibility::Hybrid)   ? !d.perPixelVisibility
                            : c.visibilityMode == std::uint32_t(Visibility::Screen) ? d.screenVisibilityPerReservoir
                                                                                     : false;
  c.perPixelVisibility = perReservoir ? 0u : 1u;
  recorder.updateBuffer(*constants_, &c, sizeof c);
  const gpu::Bind constants("gIn_DiffuseConstants", *constants_);

  if (frame.hasHistory && d.brightCandidates > 0) {
    const Extent first = extentOf(Resolution::Pyramid, full, 1);
    recorder.dispatch(passes_->brightPixels, first.width, first.height, frame.group.binds(GroupPart::Constants),
                      {constants,
                       {"gPrev_Composite", previousComposite},
                       {"gPrev_Surface", previousSurface},
                       {"gOut_Brightest", images_.level(kBrightLevels, 1)}});
    for (std::uint32_t level = 2; level <= levels; ++level) {
      const Extent below = extentOf(Resolution::Pyramid, full, level - 1);
      const Extent size = extentOf(Resolution::Pyramid, full, level);
      recorder.dispatch(passes_->brightReduce, size.width, size.height,
                        {{"gIn_Brightest", images_.level(kBrightLevels, level - 1)},
                         {"gOut_Brightest", images_.level(kBrightLevels, level)}},
                        BrightReduceParams{{below.width, below.height}, {size.width, size.height}});
    }
  }

  // Spatial reuse writes the test summary only with a bridge that traces;
  // cleared once, it holds zeros (in the layout every library image is in)
  // for whoever lists it otherwise.
  if (f == 0) images_.clearToZero(recorder, {kTestSummary}, f);

  gpu::Image& gathered0 = images_.current(kGathered0, f);
  gpu::Image& gathered1 = images_.current(kGathered1, f);
  std::vector<gpu::Bind> gatherBinds =
      scene_.binds(passes_->gather, {constants,
                                     {"gPrev_Composite", previousComposite},
                                     {"gPrev_Surface", previousSurface},
                                     {"gIn_Brightest", images_.level(kBrightLevels, levels)},
                                     {"gIn_Environment", frame.engine[Input::Environment], frame.environmentSampler},
                                     {"gIn_MarchDepth", marchDepth},
                                     {"gOut_Reservoir0", gathered0},
                                     {"gOut_Reservoir1", gathered1}});
  const std::span<const gpu::Bind> cache = products.binds(product::kCache);
  gatherBinds.insert(gatherBinds.end(), cache.begin(), cache.end());
  const std::span<const gpu::Bind> tiles = products.binds(product::kScreenTiles);
  gatherBinds.insert(gatherBinds.end(), tiles.begin(), tiles.end());
  if (worldQueue_) {
    recorder.fillBuffer(*worldQueue_, 0u);
    gatherBinds.emplace_back("gOut_PendingRays", *pendingRays_);
    gatherBinds.emplace_back("gOut_WorldQueue", *worldQueue_);
  }
  recorder.dispatch(passes_->gather, half.width, half.height, frame.group.binds(),
                    std::span<const gpu::Bind>(gpu::bindsDeclaredBy(passes_->gather, gatherBinds)));
  // The ray candidates the march left, traced together (one thread per
  // pixel that has any): the gather's reservoirs are finished there.
  if (passes_->worldCandidates) {
    std::vector<gpu::Bind> worldBinds = scene_.binds(
        *passes_->worldCandidates, {constants,
                                    {"gPrev_Composite", previousComposite},
                                    {"gPrev_Surface", previousSurface},
                                    {"gIn_Brightest", images_.level(kBrightLevels, levels)},
                                    {"gIn_Environment", frame.engine[Input::Environment], frame.environmentSampler},
                                    {"gIn_PendingRays", *pendingRays_},
                                    {"gIn_WorldQueue", *worldQueue_},
                                    {"gInOut_Reservoir0", gathered0},
                                    {"gInOut_Reservoir1", gathered1}});
    worldBinds.insert(worldBinds.end(), cache.begin(), cache.end());
    recorder.dispatch(*passes_->worldCandidates, half.width, half.height, frame.group.binds(),
                      std::span<const gpu::Bind>(gpu::bindsDeclaredBy(*passes_->worldCandidates, worldBinds)));
  }
  if (frame.capturing) viewReservoirs(frame, 0, gathered0, gathered1);

  gpu::Image* final0 = &gathered0;
  gpu::Image* final1 = &gathered1;
  if (settings_.restir) recordReuse(frame, final0, final1);
  // The reservoirs are the history only after reuse (the gathered ones are
  // this frame's alone); testing in place drops hidden samples from both.
  if (traces && d.visibility == Visibility::Hybrid)
    recorder.dispatch(*passes_->sampleVisibility, half.width, half.height, frame.group.binds(),
                      std::span<const gpu::Bind>(scene_.binds(*passes_->sampleVisibility,
                                                              {{"gIn_Reservoir0", *final0},
                                                               {"gInOut_Reservoir1", *final1}})));
  // Screen visibility tested once per reservoir: the resolve shares the verdict.
  if (c.perPixelVisibility == 0u && c.visibilityMode == std::uint32_t(Visibility::Screen))
    recorder.dispatch(passes_->sampleMarch, half.width, half.height, frame.group.binds(),
                      {constants,
                       {"gIn_Reservoir0", *final0},
                       {"gInOut_Reservoir1", *final1},
                       {"gIn_MarchDepth", marchDepth}});
  // Samples tested visible from their surface, which rough specular pixels
  // may take as their own (gi.specular.diffuse_sample_roughness); untested
  // ones (screen or world visibility: the resolve tests them) are not
  // offered, nor the gathered ones without reuse (transient: their memory
  // is the specular branch's while it records).
  if (traces && d.visibility == Visibility::Hybrid && settings_.restir)
    frame.products.put(product::kDiffuseReservoirs,
                       std::vector<gpu::Bind>{{"gIn_Diffuse_Reservoir0", *final0}, {"gIn_Diffuse_Reservoir1", *final1}});

  gpu::Image& resolved = images_.current(kResolved, f);
  recorder.dispatch(passes_->resolve, full.width, full.height, frame.group.binds(),
                    std::span<const gpu::Bind>(scene_.binds(passes_->resolve, {constants,
                                                                               {"gIn_Reservoir0", *final0},
                                                                               {"gIn_Reservoir1", *final1},
                                                                               {"gIn_MarchDepth", marchDepth},
                                                                               {"gOut_Diffuse", resolved}})));
  frame.products.put(product::noisy(kSignal), resolved);
  // A later unit (the denoiser) makes the signal from the resolved one: the filter's images were not made.
  if (!ownFilter_) return;
  recorder.dispatch(passes_->temporalFilter, full.width, full.height, frame.group.binds(),
                    {constants,
                     {"gIn_Motion", frame.engine[Input::Motion], frame.nearestSampler},
                     {"gIn_Diffuse", resolved},
                     {"gPrev_Surface", previousSurface},
                     {"gPrev_Filtered", images_.previous(kFiltered, f)},
                     {"gPrev_Moments", images_.previous(kMoments, f)},
                     {"gOut_Filtered", images_.current(kFiltered, f)},
                     {"gOut_Moments", images_.current(kMoments, f)},
                     {"gIn_LightChange", products.image(product::kLightChange)}});
  frame.products.put(kSignal, images_.current(kFiltered, f));
}

// Temporal reuse, then two spatial passes (one shader, other parameters).
void DiffuseBranch::recordReuse(const FrameState& frame, gpu::Image*& final0, gpu::Image*& final1) {
  gpu::Image& gathered0 = *final0;
  gpu::Image& gathered1 = *final1;
  gpu::Recorder& recorder = frame.recorder;
  const std::uint64_t f = frame.frameIndex;
  const DiffuseSettings& d = settings_.diffuse;
  const Extent half = extentOf(Resolution::Half, frame.renderSize);
  const gpu::Bind constants("gIn_DiffuseConstants", *constants_);
  // The reservoirs the next frame's temporal reuse starts from are the
  // history images; the others are scratch.
  const bool feedback = d.spatialFeedback;
  gpu::Image& temporalOut0 = feedback ? images_.current(kTransient0, f) : images_.current(kReservoirs0, f);
  gpu::Image& temporalOut1 = feedback ? images_.current(kTransient1, f) : images_.current(kReservoirs1, f);
  gpu::Image& spatialOut0 = feedback ? images_.current(kReservoirs0, f) : images_.current(kTransient0, f);
  gpu::Image& spatialOut1 = feedback ? images_.current(kReservoirs1, f) : images_.current(kTransient1, f);
  recorder.dispatch(passes_->temporalReuse, half.width, half.height, frame.group.binds(),
                    std::span<const gpu::Bind>(scene_.binds(
                        passes_->temporalReuse, {constants,
                                                 {"gIn_Motion", frame.engine[Input::Motion], frame.nearestSampler},
                                                 {"gPrev_Surface", frame.products.image(product::kPreviousSurface)},
                                                 {"gIn_Reservoir0", *final0},
                                                 {"gIn_Reservoir1", *final1},
                                                 {"gPrev_Reservoir0", images_.previous(kReservoirs0, f)},
                                                 {"gPrev_Reservoir1", images_.previous(kReservoirs1, f)},
                                                 {"gOut_Reservoir0", temporalOut0},
                                                 {"gOut_Reservoir1", temporalOut1},
                                                 {"gPrev_Composite", frame.products.image(product::kPreviousComposite)},
                                                 {"gIn_LightChange", frame.products.image(product::kLightChange)}})));
  if (frame.capturing) viewReservoirs(frame, 1, temporalOut0, temporalOut1);
  // A spatial pass merges; with a bridge that traces, the visibility tests
  // it queued are traced apart and counted in after it.
  gpu::Image& summary = images_.current(kTestSummary, f);
  const auto spatialPass = [&](gpu::Image& in0, gpu::Image& in1, gpu::Image& out0, gpu::Image& out1,
                               const SpatialReuseParams& params) {
    std::vector<gpu::Bind> binds = scene_.binds(passes_->spatialReuse, {constants,
                                                                        {"gIn_Reservoir0", in0},
                                                                        {"gIn_Reservoir1", in1},
                                                                        {"gOut_Reservoir0", out0},
                                                                        {"gOut_Reservoir1", out1}});
    if (testQueue_) {
      recorder.fillBuffer(*testQueue_, 0u);
      binds.emplace_back("gOut_TestSummary", summary);
      binds.emplace_back("gOut_NeighbourTests", *neighbourTests_);
      binds.emplace_back("gOut_WorldQueue", *testQueue_);
    }
    recorder.dispatch(passes_->spatialReuse, half.width, half.height, frame.group.binds(),
                      std::span<const gpu::Bind>(gpu::bindsDeclaredBy(passes_->spatialReuse, binds)), &params,
                      sizeof params);
    if (!testQueue_ || params.slotsPerPixel == 0) return;
    recorder.dispatch(*passes_->neighbourVisibility, half.width, half.height, frame.group.binds(),
                      std::span<const gpu::Bind>(
                          scene_.binds(*passes_->neighbourVisibility, {constants,
                                                                       {"gIn_Reservoir0", out0},
                                                                       {"gIn_Reservoir1", out1},
                                                                       {"gInOut_NeighbourTests", *neighbourTests_},
                                                                       {"gIn_WorldQueue", *testQueue_}})),
                      &params, sizeof params);
    recorder.dispatch(*passes_->spatialNormalize, half.width, half.height, frame.group.binds(GroupPart::Constants),
                      {{"gIn_Reservoir0", out0},
                       {"gInOut_Reservoir1", out1},
                       {"gInOut_TestSummary", summary},
                       {"gIn_NeighbourTests", *neighbourTests_}},
                      &params, sizeof params);
  };
  // The gathered reservoirs (the pair final0/1 points to on entry) are
  // read by temporal reuse alone: the first spatial pass writes over them.
  gpu::Image& spatial0 = gathered0;
  gpu::Image& spatial1 = gathered1;
  spatialPass(temporalOut0, temporalOut1, spatial0, spatial1, {d.spatialRadius, d.spatialSamples, 0u, testSlots_});
  if (frame.capturing) viewReservoirs(frame, 2, spatial0, spatial1);
  spatialPass(spatial0, spatial1, spatialOut0, spatialOut1, {d.spatial2Radius, d.spatial2Samples, 1u, testSlots_});
  final0 = &spatialOut0;
  final1 = &spatialOut1;
  if (frame.capturing) viewReservoirs(frame, 3, *final0, *final1);
}

UnitRegistration diffuseUnit() {
  return {.name = std::string(DiffuseBranch::kSignal),
          .produces =
              [](const UnitSetup&) {
                return std::vector<std::string>{std::string(DiffuseBranch::kSignal),
                                                product::noisy(DiffuseBranch::kSignal),
                                                std::string(product::kDiffuseReservoirs)};
              },
          .make = [](const UnitSetup& setup, const UnitResources& resources) -> std::unique_ptr<Unit> {
            const DiffuseBranchSettings settings = DiffuseBranch::settingsOf(setup.settings);
            const DiffuseSettings& d = settings.diffuse;
            // validate() made sure of a candidate without a bridge; with one, rays take the environment's place.
            if (d.enabled && resources.scene.traces() &&
                d.screenCandidates + d.brightCandidates + settings.rays.diffuseCandidates == 0)
              throw Error(
                  "gi: gi.diffuse.screen_candidates and bright_candidates are 0 and no ray candidate is left "
                  "(gi.diffuse.ray_candidates, or gi.world_ray_budget too small for one) with the scene bridge '" +
                  resources.scene.name() + "': every reservoir would stay empty");
            return std::make_unique<DiffuseBranch>(resources.context, resources.arena, setup.maxSize, settings,
                                                   resources.scene, DiffuseBranch::ownFilter(setup),
                                                   resources.transientPool);
          },
          .memoryBytes =
              [](const UnitSetup& setup) {
                const DiffuseBranchSettings settings = DiffuseBranch::settingsOf(setup.settings);
                return imageSetBytes(diffuseImageTable(), setup.maxSize,
                                     brightPyramidLevels(setup.maxSize, settings.diffuse.brightPixels),
                                     DiffuseBranch::unusedImages(DiffuseBranch::ownFilter(setup)));
              },
          .transientBytes =
              [](const UnitSetup& setup) {
                const DiffuseBranchSettings settings = DiffuseBranch::settingsOf(setup.settings);
                return transientImageBytes(diffuseImageTable(), setup.maxSize,
                                           brightPyramidLevels(setup.maxSize, settings.diffuse.brightPixels),
                                           DiffuseBranch::unusedImages(DiffuseBranch::ownFilter(setup))) +
                       DiffuseBranch::transientBufferBytes(setup.maxSize, settings, setup.bridgeTraces);
              }};
}

DiffuseBranchSettings DiffuseBranch::settingsOf(const Settings& settings) {
  return {settings.diffuse, settings.restir, planWorldRays(settings)};
}

bool DiffuseBranch::ownFilter(const UnitSetup& setup) {
  return branchKeepsOwnFilter(setup, kSignal, setup.settings.diffuse.enabled);
}

}  // namespace bounce::gi
