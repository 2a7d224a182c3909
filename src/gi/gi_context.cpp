// GiContext: the library on the engine's device. It owns the frame's
// images and its units, records store_history, the depth pyramid, screen
// tiles, the light change, the cache's inject, the branches, the cache's
// update and resolve, the denoiser and the composite (in that order;
// docs/architecture.md) into the engine's command buffer, and keeps per-frame-in-flight query
// pools and stage copies until collect(). What each branch does is its own
// business (src/gi/diffuse/); docs/gi.md explains the algorithm.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "bounce/gi.h"
#include "gi/cache/radiance_cache.h"
#include "gi/denoise/denoiser.h"
#include "gi/depth_pyramid.h"
#include "gi/diffuse/diffuse_branch.h"
#include "gi/engine_images.h"
#include "gi/frame_constants.h"
#include "gi/frame_passes.h"
#include "gi/image_table.h"
#include "gi/library_device.h"
#include "gi/light_change.h"
#include "gi/pass_log.h"
#include "gi/scene_bridge.h"
#include "gi/screen_tiles.h"
#include "gi/specular/specular_branch.h"
#include "gpu/error.h"
#include "gpu/format.h"
#include "gpu/recorder.h"
#include "gpu/timing.h"
#include "shared/checkerboard.glsl"

namespace bounce::gi {
namespace {

using namespace gpu::formats;

constexpr ImageSpec kFrameImages[] = {
    {"gi.history_surface", Resolution::Full, kRg32ui, true, gpu::Visualize::Raw,
     "viewZ bits, octahedral normal and material id of every pixel, for the next frame (and this frame's id)"},
    {"gi.march_depth", Resolution::Full, kR32f, false, gpu::Visualize::Range,
     "this frame's viewZ (0 where unusable) in the library's own storage image: what visibility marches read"},
    {"gi.composite", Resolution::Full, kRgba16f, true, gpu::Visualize::Radiance,
     "the frame, linear HDR: direct light + remodulated indirect light; next frame's light source"},
};
static_assert(std::size(kFrameImages) == kFrameImageCount, "one table entry per FrameImage");

constexpr std::size_t kLibrarySignalCount = std::size(kLibrarySignals);

// Every signal of a context: the library's two, then the engine's (ContextDesc::signals).
std::vector<SignalDesc> signalsOf(const ContextDesc& desc) {
  std::vector<SignalDesc> all(std::begin(kLibrarySignals), std::end(kLibrarySignals));
  all.insert(all.end(), desc.signals.begin(), desc.signals.end());
  return all;
}

// ContextDesc::signals as the denoiser can take them: names that make pass
// names (and clash with no other), known kinds, not too many.
void checkSignals(const ContextDesc& desc, const Settings& settings) {
  if (desc.signals.empty()) return;
  if (!settings.denoise.enabled)
    throw Error("gi: ContextDesc::signals declares " + std::to_string(desc.signals.size()) +
                " signal(s) of the engine's, but the denoiser is off (Settings::denoise.enabled, "
                "gi.denoise.enabled): the library takes an engine's signal only to denoise it");
  if (kLibrarySignalCount + desc.signals.size() > kMaxSignals)
    throw Error("gi: ContextDesc::signals declares " + std::to_string(desc.signals.size()) + " signals; at most " +
                std::to_string(kMaxSignals - kLibrarySignalCount) + " besides the library's diffuse and specular");
  std::vector<std::string> seen = {"diffuse", "specular"};
  for (std::size_t i = 0; i < desc.signals.size(); ++i) {
    const SignalDesc& signal = desc.signals[i];
    const std::string where = "gi: ContextDesc::signals[" + std::to_string(i) + "] ('" + signal.name + "')";
    const bool wellFormed = !signal.name.empty() && signal.name.size() <= 32 &&
                            std::all_of(signal.name.begin(), signal.name.end(), [](char c) {
                              return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
                            });
    if (!wellFormed)
      throw Error(where + ": a signal's name is 1-32 of a-z, 0-9 and '_' (its passes are gi.denoise.NAME.*)");
    if (std::find(seen.begin(), seen.end(), signal.name) != seen.end())
      throw Error(
          where + ": the name is taken by " +
          (signal.name == "diffuse" || signal.name == "specular" ? "the library's own signal" : "an earlier signal"));
    if (signal.kind != SignalKind::Diffuse && signal.kind != SignalKind::Specular)
      throw Error(where + ": kind " + std::to_string(std::uint32_t(signal.kind)) +
                  " is neither SignalKind::Diffuse nor Specular");
    seen.push_back(signal.name);
  }
}

// Whether a library signal's branch makes the images of its own temporal
// filter: it runs the filter (no denoiser), or it is disabled and its
// result is that filter image, cleared. An enabled branch whose signal the
// denoiser takes never reads them: 269 MiB at 1080p for the two.
bool branchEnabled(const Settings& settings, SignalId signal) {
  return signal == kDiffuseSignal ? settings.diffuse.enabled : settings.specular.enabled;
}

bool ownFilter(const Settings& settings, SignalId signal) {
  return !settings.denoise.enabled || !branchEnabled(settings, signal);
}

// Which signals the engine gives this frame, by SignalId.
using SignalFlags = std::vector<bool>;

// What errors call each signal's noisy input: "noisy[2] (ao)".
std::vector<std::string> noisyInputNames(std::span<const SignalDesc> signals) {
  std::vector<std::string> names;
  for (std::size_t id = 0; id < signals.size(); ++id)
    names.push_back("noisy[" + std::to_string(id) + "] (" + signals[id].name + ")");
  return names;
}

// The engine's noisy signals of a frame, one per signal of the context
// (FrameInputs::noisy, with the library's two also under their older names
// noisyDiffuse and noisySpecular), named as errors call them (`names`:
// noisyInputNames of the context's signals).
std::vector<EngineImages::Noisy> noisyInputsOf(const FrameInputs& frame, std::span<const std::string> names) {
  if (frame.noisy.size() > names.size())
    throw Error("gi: frame input noisy has " + std::to_string(frame.noisy.size()) + " entries; the context denoises " +
                std::to_string(names.size()) + " signals (diffuse, specular and the " +
                std::to_string(names.size() - kLibrarySignalCount) + " of ContextDesc::signals)");
  std::vector<EngineImages::Noisy> noisy;
  for (std::size_t id = 0; id < names.size(); ++id) {
    EngineImages::Noisy input{names[id], id < frame.noisy.size() ? frame.noisy[id] : ImageRef{}};
    if (id < kLibrarySignalCount) {
      const ImageRef& older = id == kDiffuseSignal ? frame.noisyDiffuse : frame.noisySpecular;
      const char* olderName = id == kDiffuseSignal ? "noisyDiffuse" : "noisySpecular";
      if (older.image != VK_NULL_HANDLE) {
        if (input.ref.image != VK_NULL_HANDLE && input.ref.image != older.image)
          throw Error("gi: frame inputs " + names[id] + " and " + olderName + " are both given, as different " +
                      "images; " + olderName + " is the older name of " + names[id] + ": give the signal once");
        input = {olderName, older};
      }
    }
    noisy.push_back(input);
  }
  return noisy;
}

std::string sizeText(std::uint32_t width, std::uint32_t height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

}  // namespace

std::span<const ImageSpec> frameImageTable() { return kFrameImages; }

Camera cameraFromBasis(const float position[3], const float right[3], const float up[3], const float forward[3],
                       float fovY, float aspect, const float jitter[2]) {
  const glm::vec3 p = glm::make_vec3(position), r = glm::make_vec3(right), u = glm::make_vec3(up),
                  f = glm::make_vec3(forward);
  const glm::mat4 viewToWorld(glm::vec4(r, 0.0f), glm::vec4(u, 0.0f), glm::vec4(-f, 0.0f), glm::vec4(p, 1.0f));
  const glm::mat4 worldToView = glm::inverse(viewToWorld);
  const float tanHalf = std::tan(fovY * 0.5f);
  glm::mat4 projection(0.0f);
  projection[0][0] = 1.0f / (tanHalf * aspect);
  projection[1][1] = 1.0f / tanHalf;
  projection[2][2] = -1.0f;
  projection[2][3] = -1.0f;
  projection[3][2] = -0.1f;  // near plane 0.1: only the depth row needs one, and GI reads no clip depth
  Camera camera;
  std::copy_n(glm::value_ptr(worldToView), 16, camera.worldToView);
  std::copy_n(glm::value_ptr(projection), 16, camera.viewToClip);
  if (jitter) {
    camera.jitter[0] = jitter[0];
    camera.jitter[1] = jitter[1];
  }
  return camera;
}

struct GiContext::Impl {
  ContextDesc desc;
  Settings settings;
  std::unique_ptr<gpu::Context> context;
  SceneBridgeBinding scene;
  gpu::MemoryArena arena;
  ImageSet frameImages;
  std::unique_ptr<gpu::Buffer> frameConstants;
  RadianceCache cache;
  DepthPyramid depthPyramid;
  ScreenTiles screenTiles;
  LightChange lightChange;
  std::vector<std::unique_ptr<Branch>> branches;
  std::vector<SignalDesc> signals;         // by SignalId: the library's two, then ContextDesc::signals
  std::vector<std::string> noisyNames;     // noisyInputNames(signals)
  std::unique_ptr<Denoiser> denoiser;      // made only when gi.denoise.enabled: its images are large
  // The engine's own noisy signals as the denoiser reads them, and the
  // passes that take them in: made on the first frame that gives one, so
  // a context whose engine never does holds no memory for them.
  ImageTableBuilder engineSignalTable;
  std::unique_ptr<ImageSet> engineSignals;
  std::vector<std::unique_ptr<gpu::ComputePass>> engineSignalPasses;
  gpu::ComputePass storeHistory, compositor;
  EngineImages engine;
  std::vector<std::unique_ptr<PassLog>> logs;  // one per frame in flight, used in turn

  // What the last frame left.
  std::uint64_t recorded = 0;  // frames recorded; the history images swap by this count
  std::optional<std::uint64_t> lastFrameIndex;
  Camera lastCamera;
  Extent lastSize;
  SignalFlags lastEngineSignals;    // which signals the engine gave
  bool pyramidBuilt = false;        // the depth pyramid holds last frame's depth
  bool tilesBuilt = false;          // the screen tiles hold this frame's (screen-only mode)
  bool lightChangeBuilt = false;    // the light change was recorded this frame

  Impl(const Device& device, const ContextDesc& d, const Settings& s)
      : desc(d),
        settings(s),
        context(openLibraryContext(device)),
        scene(*context, d.sceneBridge),
        arena(*context, VkDeviceSize(128) << 20, GiContext::estimateMemoryBytes(d, s)),
        frameImages(*context, arena, kFrameImages, {d.maxWidth, d.maxHeight}),
        frameConstants(std::make_unique<gpu::Buffer>(*context, "gi.frame_constants", sizeof(shared::GiFrameConstants),
                                                     gpu::BufferUsage::DeviceLocal, &arena)),
        cache(*context, arena, {d.maxWidth, d.maxHeight}, settings, scene),
        depthPyramid(*context, arena, {d.maxWidth, d.maxHeight}),
        screenTiles(*context, arena, {d.maxWidth, d.maxHeight}),
        lightChange(*context, arena, {d.maxWidth, d.maxHeight}),
        signals(signalsOf(d)),
        noisyNames(noisyInputNames(signals)),
        storeHistory(*context, storeHistoryPass()),
        compositor(*context, compositePass()),
        engine(*context),
        lastEngineSignals(signals.size(), false) {
    const DiffuseSettings& diffuse = settings.diffuse;
    // validate() made sure of a candidate without a bridge; with one, rays take the environment's place.
    if (diffuse.enabled && scene.traces() &&
        diffuse.screenCandidates + diffuse.brightCandidates + planWorldRays(settings).diffuseCandidates == 0)
      throw Error(
          "gi: gi.diffuse.screen_candidates and bright_candidates are 0 and no ray candidate is left (gi.diffuse."
          "ray_candidates, or gi.world_ray_budget too small for one) with the scene bridge '" +
          scene.name() + "': every reservoir would stay empty");
    branches.push_back(std::make_unique<DiffuseBranch>(*context, arena, Extent{d.maxWidth, d.maxHeight}, settings,
                                                       scene, cache, ownFilter(settings, kDiffuseSignal)));
    branches.push_back(std::make_unique<SpecularBranch>(*context, arena, Extent{d.maxWidth, d.maxHeight}, settings,
                                                        scene, cache, ownFilter(settings, kSpecularSignal)));
    if (settings.denoise.enabled)
      denoiser =
          std::make_unique<Denoiser>(*context, arena, Extent{d.maxWidth, d.maxHeight}, settings.denoise, signals);
    for (std::uint32_t i = 0; i < desc.framesInFlight; ++i)
      logs.push_back(std::make_unique<PassLog>(*context, desc.timestamps, scene.traces()));
  }

  // The branch that makes a library signal (kDiffuseSignal, kSpecularSignal).
  Branch& branchOf(SignalId signal) { return *branches[signal]; }
  bool branchEnabled(SignalId signal) const { return gi::branchEnabled(settings, signal); }
  // Whether the library's branch of each library signal makes it this
  // frame: it is enabled and the engine does not give the signal itself.
  std::array<bool, kLibrarySignalCount> branchesRunning(const SignalFlags& given) const {
    return {branchEnabled(kDiffuseSignal) && !given[kDiffuseSignal],
            branchEnabled(kSpecularSignal) && !given[kSpecularSignal]};
  }
  std::uint64_t current() const { return recorded == 0 ? 0 : recorded - 1; }
  // The pyramid is built when a running branch marches it (today the
  // specular trace; the diffuse visibility marches read gi.march_depth pixel
  // by pixel).
  bool needsDepthPyramid(const std::array<bool, kLibrarySignalCount>& running) const {
    for (const SignalId signal : {kDiffuseSignal, kSpecularSignal})
      if (running[signal] && branches[signal]->marchesDepthPyramid()) return true;
    return false;
  }

  // Everything that can be refused, before anything is recorded; returns
  // the frame's noisy signals (noisyInputsOf), checked.
  std::vector<EngineImages::Noisy> check(const FrameInputs& frame) {
    if (frame.width == 0 || frame.height == 0 || frame.width > desc.maxWidth || frame.height > desc.maxHeight)
      throw Error("gi: render size " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                  " is outside 1x1.." + std::to_string(desc.maxWidth) + "x" + std::to_string(desc.maxHeight) +
                  " (ContextDesc::maxWidth, maxHeight)");
    if (lastFrameIndex && frame.frameIndex <= *lastFrameIndex)
      throw Error("gi: frameIndex " + std::to_string(frame.frameIndex) + " is not after the last frame recorded (" +
                  std::to_string(*lastFrameIndex) + "); frame indices must increase");
    screenView(frame.camera, "camera");
    if (!frame.cameraCut) screenView(frame.previousCamera, "previousCamera");
    // The noisy signals' size depends on the mode (EngineImages checks the
    // rest of them): the render size, or in checkerboard mode half its
    // width, rounded up. As every input, an image may be larger.
    std::vector<EngineImages::Noisy> noisy = noisyInputsOf(frame, noisyNames);
    for (const EngineImages::Noisy& given : noisy) {
      const ImageRef& ref = given.ref;
      if (ref.image == VK_NULL_HANDLE) continue;
      const std::string input = "gi: frame input " + std::string(given.name);
      if (!denoiser)
        throw Error(input +
                    " is given, but the denoiser is off (Settings::denoise.enabled, gi.denoise.enabled): "
                    "the library takes an engine's signal only to denoise it");
      if (!settings.denoise.checkerboard) {
        if (ref.width < frame.width || ref.height < frame.height)
          throw Error(input + " is " + sizeText(ref.width, ref.height) + ", smaller than the render size " +
                      sizeText(frame.width, frame.height));
        continue;
      }
      const std::uint32_t packedWidth = shared::checkerboardPackedWidth(frame.width);
      if (ref.width < packedWidth || ref.height < frame.height)
        throw Error(input + " is " + sizeText(ref.width, ref.height) +
                    "; with gi.denoise.checkerboard on it holds every other pixel of each row, packed to half "
                    "width: it must cover " + sizeText(packedWidth, frame.height) + " (ceil(width / 2) x height of "
                    "the render size " + sizeText(frame.width, frame.height) + ")");
    }
    return noisy;
  }

  // The passes and images that take the engine's signals in, made before
  // the first frame that gives one records anything.
  void makeEngineSignalUnit() {
    if (engineSignals) return;
    for (const SignalDesc& signal : signals) {
      addEngineSignalImage(engineSignalTable, signal.name);
      engineSignalPasses.push_back(std::make_unique<gpu::ComputePass>(*context, engineSignalPass(signal.name)));
    }
    engineSignals =
        std::make_unique<ImageSet>(*context, arena, engineSignalTable.specs(), Extent{desc.maxWidth, desc.maxHeight});
  }

  // gi.engine_signal.SIGNAL: the engine's signal into the library's image
  // of it (in checkerboard mode, unpacked to full width).
  gpu::Image& takeEngineSignal(const FrameState& state, std::size_t signal) {
    gpu::Image& taken = engineSignals->current(signal, state.frameIndex);
    const EngineSignalParams params{settings.denoise.checkerboard ? 1u : 0u,
                                    shared::checkerboardParityOfKind(signals[signal].kind == SignalKind::Specular)};
    state.recorder.dispatch(*engineSignalPasses[signal], state.renderSize.width, state.renderSize.height,
                            state.group.binds(GroupPart::Constants),
                            {{"gIn_Noisy", *state.engine.noisy(signal), state.nearestSampler}, {"gOut_Signal", taken}},
                            params);
    return taken;
  }

  shared::GiFrameConstants frameConstantsOf(const FrameInputs& frame, bool hasHistory, bool usableHistory) const {
    shared::GiFrameConstants c{};
    c.view = screenView(frame.camera, "camera");
    // Last frame's images were made with the camera given last frame; the
    // engine's previousCamera is that same camera unless it cut.
    c.previousView = usableHistory ? screenView(frame.previousCamera, "previousCamera")
                     : hasHistory  ? screenView(lastCamera, "last frame's camera")
                                   : c.view;
    const Extent half = extentOf(Resolution::Half, {frame.width, frame.height});
    c.renderSize = glm::vec2(float(frame.width), float(frame.height));
    c.halfSize = glm::vec2(float(half.width), float(half.height));
    const InputSettings& input = settings.input;
    const glm::vec2 units = input.motionUnits == MotionUnits::Uv ? c.renderSize : glm::vec2(1.0f);
    c.motionScale = units * glm::vec2(input.motionScaleX, input.motionScaleY);
    c.frameIndex = std::uint32_t(frame.frameIndex);
    c.noHistory = usableHistory ? 0u : 1u;
    c.seed = settings.seed;
    c.normalEncoding = frame.normalRoughness.format == VK_FORMAT_A2B10G10R10_UNORM_PACK32
                           ? shared::kNormalEncodingOctahedral
                           : shared::kNormalEncodingXyz;
    c.hasEmissive = frame.emissive.image != VK_NULL_HANDLE ? 1u : 0u;
    c.hasMaterialId = frame.materialId.image != VK_NULL_HANDLE ? 1u : 0u;
    return c;
  }

  void record(VkCommandBuffer commandBuffer, const FrameInputs& frame) {
    if (commandBuffer == VK_NULL_HANDLE) throw Error("gi: record() needs a command buffer in the recording state");
    const std::vector<EngineImages::Noisy> noisy = check(frame);
    SignalFlags given(signals.size());
    for (std::size_t id = 0; id < signals.size(); ++id) given[id] = noisy[id].ref.image != VK_NULL_HANDLE;
    const auto running = branchesRunning(given);
    const bool anyBranch = running[kDiffuseSignal] || running[kSpecularSignal];
    scene.take(frame);
    // Only the branches read the environment: without them it may be left out.
    engine.take(frame, noisy, desc.inputState, anyBranch);
    if (std::find(given.begin(), given.end(), true) != given.end()) makeEngineSignalUnit();

    const Extent size{frame.width, frame.height};
    // A new render size makes last frame's images another picture: nothing of them is reused.
    const bool hasHistory = recorded > 0 && size.width == lastSize.width && size.height == lastSize.height;
    // A library signal that changed hands (the branch's last frame, the
    // engine's now, or back) finds histories the other never wrote: the
    // branch's reservoirs and filters, the denoiser's history of that
    // signal. All restart, as on a cut; engines switch rarely (a debug
    // toggle). (An engine's own signal given again restarts only its own
    // history: below.)
    const bool sameSources = recorded == 0 || (given[kDiffuseSignal] == lastEngineSignals[kDiffuseSignal] &&
                                               given[kSpecularSignal] == lastEngineSignals[kSpecularSignal]);
    const bool usableHistory = hasHistory && !frame.cameraCut && sameSources;
    const shared::GiFrameConstants constants = frameConstantsOf(frame, hasHistory, usableHistory);
    const std::uint64_t f = recorded;  // the history images' index

    // The log of frame recorded - framesInFlight, which has completed; if
    // nobody collected it, it is dropped.
    PassLog& log = *logs[recorded % logs.size()];
    gpu::Recorder recorder(*context, commandBuffer, log.sink());
    log.begin(commandBuffer, recorder, frame.frameIndex, frame.captureStages);
    if (scene.traces()) scene.countRaysInto(log.rayCounters());

    recorder.updateBuffer(*frameConstants, &constants, sizeof constants);
    const FrameGroup group(*frameConstants, engine[Input::ViewZ], engine[Input::NormalRoughness],
                           context->nearestSampler());
    recorder.dispatch(storeHistory, size.width, size.height, group.binds(),
                      {{"gOut_Surface", frameImages.current(kHistorySurface, f)},
                       {"gOut_MarchDepth", frameImages.current(kMarchDepth, f)},
                       // Not read without material ids (the constants say so): last frame's
                       // surfaces, an unsigned-integer image, only fill the slot.
                       {"gIn_MaterialId",
                        engine.has(Input::MaterialId) ? engine[Input::MaterialId]
                                                      : frameImages.previous(kHistorySurface, f),
                        context->nearestSampler()}});
    pyramidBuilt = needsDepthPyramid(running);
    if (pyramidBuilt) depthPyramid.record(recorder, frameImages.current(kMarchDepth, f), size);
    // Screen-only mode's answer for rays screen space cannot decide, from
    // this frame's direct light (with a bridge that traces, world rays answer them).
    tilesBuilt = anyBranch && !scene.traces();
    if (tilesBuilt) screenTiles.record(recorder, group, engine[Input::Direct], context->nearestSampler(), size);
    // How much of the light changed, and so how much of their history the
    // temporal histories keep: for every unit with one.
    lightChangeBuilt = anyBranch || denoiser != nullptr;
    if (lightChangeBuilt)
      lightChange.record(recorder, group, engine, frameImages.previous(kHistorySurface, f),
                         frameImages.current(kHistorySurface, f), context->nearestSampler(), f, size);

    const FrameState state{.recorder = recorder,
                           .group = group,
                           .engine = engine,
                           .environmentSampler = frame.environmentSampler,
                           .nearestSampler = context->nearestSampler(),
                           .frameIndex = f,
                           .renderSize = size,
                           .hasHistory = hasHistory,
                           .usableHistory = usableHistory,
                           .previousComposite = frameImages.previous(kComposite, f),
                           .previousSurface = frameImages.previous(kHistorySurface, f),
                           .currentSurface = frameImages.current(kHistorySurface, f),
                           .marchDepth = frameImages.current(kMarchDepth, f),
                           .depthPyramid = depthPyramid,
                           .screenTiles = screenTiles,
                           .lightChange = lightChange.verdict(f),
                           .capturing = frame.captureStages,
                           .denoised = denoiser != nullptr};
    // The radiance cache serves the branches; with none running it rests.
    if (anyBranch) {
      const glm::vec3 cameraPosition = glm::inverse(glm::make_mat4(frame.camera.worldToView))[3];
      cache.recordBegin(state, glm::value_ptr(cameraPosition),
                        denoiser && settings.diffuse.enabled ? denoiser->previousResult(kDiffuseSignal, f)
                                                             : branchOf(kDiffuseSignal).previousResult(f));
    }
    // A branch whose signal the engine gives records nothing; one that is
    // disabled records the clearing of its result (what the composite reads).
    for (const SignalId signal : {kDiffuseSignal, kSpecularSignal})
      if (!given[signal]) branchOf(signal).record(state);
    if (anyBranch) cache.recordEnd(state);
    if (denoiser) {
      std::vector<Denoiser::SignalInput> inputs(signals.size());
      for (std::size_t id = 0; id < signals.size(); ++id) {
        Denoiser::SignalInput& in = inputs[id];
        const bool library = id < kLibrarySignalCount;
        in.noisy = given[id]                ? &takeEngineSignal(state, id)
                   : library && running[id] ? &branchOf(SignalId(id)).resolved(f)
                                            : nullptr;
        // Checkerboard mode is the engine's: the branches' signals are full.
        in.checkerboarded = given[id] && settings.denoise.checkerboard;
        // An engine's own signal not given last frame has no history of last frame's.
        in.historyKept = library || lastEngineSignals[id];
      }
      denoiser->record(state, inputs);
    }

    gpu::Image& direct = engine[Input::Direct];
    const VkSampler nearest = context->nearestSampler();
    recorder.dispatch(compositor, size.width, size.height, group.binds(GroupPart::Surfaces),
                      {{"gIn_Direct", direct, nearest},
                       {"gIn_BaseColorMetallic", engine[Input::BaseColorMetallic], nearest},
                       // Not read without an emissive image (the constants say so); bound only to fill the slot.
                       {"gIn_Emissive", engine.has(Input::Emissive) ? engine[Input::Emissive] : direct, nearest},
                       {"gIn_IndirectDiffuse", result(kDiffuseSignal, f, given), nearest},
                       {"gIn_IndirectSpecular", result(kSpecularSignal, f, given), nearest},
                       {"gOut_Composite", frameImages.current(kComposite, f)}});
    log.end(recorder);

    engine.handBack(recorder);
    // Stage copies moved some images to transfer layouts: every library
    // image is left as LibraryImage says.
    if (frame.captureStages) {
      for (ImageSet* set : imageSets())
        for (const ImageSet::Listed& listed : set->list(f))
          if (listed.image->sync().layout != VK_IMAGE_LAYOUT_GENERAL)
            recorder.handOver(*listed.image, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                              kLibraryImageAccess);
      recorder.flush();
    }

    ++recorded;
    lastFrameIndex = frame.frameIndex;
    lastCamera = frame.camera;
    lastSize = size;
    lastEngineSignals = given;
  }

  std::vector<ImageSet*> imageSets() {
    std::vector<ImageSet*> sets = {&frameImages, &cache.images()};
    if (tilesBuilt) sets.push_back(&screenTiles.images());
    if (lightChangeBuilt) sets.push_back(&lightChange.images());
    for (const std::unique_ptr<Branch>& branch : branches) sets.push_back(&branch->images());
    if (denoiser) sets.push_back(&denoiser->images());
    if (engineSignals) sets.push_back(engineSignals.get());
    return sets;
  }

  // What the composite reads for a library signal: the denoised one (the
  // branch's or the engine's), or the branch's own filtered one (denoiser
  // off, or the branch off: then it is the branch's cleared result); an
  // engine's own signal: the denoised one. `given`: the engine gave the
  // signal that frame.
  gpu::Image& result(SignalId signal, std::uint64_t f, const SignalFlags& given) {
    if (signal >= kLibrarySignalCount) return denoiser->result(signal, f);
    const bool denoised = branchEnabled(signal) || given[signal];
    return denoiser && denoised ? denoiser->result(signal, f) : branchOf(signal).result(f);
  }

  FrameResults collect(std::uint64_t completedFrameIndex) {
    if (!lastFrameIndex || completedFrameIndex > *lastFrameIndex)
      throw Error("gi: collect(" + std::to_string(completedFrameIndex) + "): no frame with that index was recorded" +
                  (lastFrameIndex ? " (the last was " + std::to_string(*lastFrameIndex) + ")" : std::string()));
    std::vector<PassLog*> ready;  // oldest first
    for (const std::unique_ptr<PassLog>& log : logs)
      if (log->frameIndex() && *log->frameIndex() <= completedFrameIndex) ready.push_back(log.get());
    std::sort(ready.begin(), ready.end(),
              [](const PassLog* a, const PassLog* b) { return *a->frameIndex() < *b->frameIndex(); });
    FrameResults results;
    for (PassLog* log : ready) log->collectInto(results, "gi: collect(" + std::to_string(completedFrameIndex) + ")");
    return results;
  }
};

GiContext::GiContext(const Device& device, const ContextDesc& desc, const Settings& settings) {
  if (desc.maxWidth == 0 || desc.maxHeight == 0 || desc.maxWidth > 16384 || desc.maxHeight > 16384)
    throw Error("gi: ContextDesc maximum size " + std::to_string(desc.maxWidth) + "x" + std::to_string(desc.maxHeight) +
                " is outside 1x1..16384x16384");
  if (desc.framesInFlight == 0 || desc.framesInFlight > 16)
    throw Error("gi: ContextDesc::framesInFlight " + std::to_string(desc.framesInFlight) + " is outside 1..16");
  try {
    validate(settings);
  } catch (const std::invalid_argument& e) {
    throw Error(e.what());
  }
  checkSignals(desc, settings);
  try {
    impl_ = std::make_unique<Impl>(device, desc, settings);
  } catch (const gpu::GpuError& e) {
    throw Error(std::string("gi: ") + e.what());
  }
}

GiContext::~GiContext() = default;

void GiContext::record(VkCommandBuffer commandBuffer, const FrameInputs& frame) {
  try {
    impl_->record(commandBuffer, frame);
  } catch (const gpu::GpuError& e) {
    throw Error(std::string("gi: ") + e.what());
  }
}

FrameResults GiContext::collect(std::uint64_t completedFrameIndex) {
  try {
    return impl_->collect(completedFrameIndex);
  } catch (const gpu::GpuError& e) {
    throw Error(std::string("gi: ") + e.what());
  }
}

ImageRef GiContext::indirect(SignalId signal) const {
  if (signal >= impl_->signals.size())
    throw Error("gi: indirect(" + std::to_string(signal) + "): the context has " +
                std::to_string(impl_->signals.size()) + " signals (diffuse, specular and ContextDesc::signals)");
  return libraryRef(impl_->result(signal, impl_->current(), impl_->lastEngineSignals));
}

std::vector<SignalDesc> GiContext::signals() const { return impl_->signals; }

ImageRef GiContext::indirectDiffuse() const { return indirect(kDiffuseSignal); }

ImageRef GiContext::indirectSpecular() const { return indirect(kSpecularSignal); }

ImageRef GiContext::composite() const { return libraryRef(impl_->frameImages.current(kComposite, impl_->current())); }

std::vector<LibraryImage> GiContext::images() const {
  std::vector<ImageSet::Listed> listed;
  for (ImageSet* set : impl_->imageSets()) {
    const std::vector<ImageSet::Listed> ofSet = set->list(impl_->current());
    listed.insert(listed.end(), ofSet.begin(), ofSet.end());
  }
  if (impl_->pyramidBuilt) listed.push_back(impl_->depthPyramid.listed());
  std::vector<LibraryImage> list;
  for (const ImageSet::Listed& image : listed)
    list.push_back({image.name, libraryRef(*image.image), visualization(image.spec->view),
                    std::string(image.spec->purpose)});
  return list;
}

std::uint64_t GiContext::memoryBytes() const { return impl_->arena.bytes(); }

std::vector<UnitMemory> GiContext::memoryByUnit() const {
  std::vector<UnitMemory> units = {{"diffuse"}, {"specular"}, {"cache"}, {"denoise"}, {"frame"}};
  for (const auto& [name, bytes] : impl_->arena.bytesByName()) {
    UnitMemory* owner = &units.back();
    for (UnitMemory& unit : units)
      if (name.rfind("gi." + unit.unit + ".", 0) == 0) owner = &unit;
    owner->bytes += bytes;
  }
  return units;
}

std::uint64_t GiContext::estimateMemoryBytes(const ContextDesc& desc, const Settings& settings) {
  // The units Impl makes, each sized as it sizes itself.
  const Extent size{desc.maxWidth, desc.maxHeight};
  std::uint64_t bytes =
      imageSetBytes(frameImageTable(), size) + sizeof(shared::GiFrameConstants) +
      RadianceCache::memoryBytes(size, settings) + DepthPyramid::memoryBytes(size) + ScreenTiles::memoryBytes(size) +
      LightChange::memoryBytes(size) +
      imageSetBytes(diffuseImageTable(), size, brightPyramidLevels(size, settings.diffuse.brightPixels),
                    DiffuseBranch::unusedImages(ownFilter(settings, kDiffuseSignal))) +
      DiffuseBranch::bufferBytes(size, settings, !desc.sceneBridge.shaders.empty()) +
      imageSetBytes(specularImageTable(), size, 0, SpecularBranch::unusedImages(ownFilter(settings, kSpecularSignal))) +
      SpecularBranch::bufferBytes(size, !desc.sceneBridge.shaders.empty());
  if (settings.denoise.enabled) bytes += denoiserMemoryBytes(size, signalsOf(desc));
  return bytes;
}
const Settings& GiContext::settings() const { return impl_->settings; }
std::uint32_t GiContext::maxWidth() const { return impl_->desc.maxWidth; }
std::uint32_t GiContext::maxHeight() const { return impl_->desc.maxHeight; }

}  // namespace bounce::gi
