// GiContext: the library on the engine's device. It makes the units
// registered in gi/units.cpp (each with its own settings), asks them each
// frame whether they record and what they take, records them in order into
// the engine's command buffer and routes their products by name
// (gi/unit.h); it keeps per-frame-in-flight query pools and stage copies
// until collect(). What a unit does is its own business (src/gi/diffuse/,
// ...); docs/architecture.md lists the units and products, docs/gi.md
// explains the algorithm.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include <glm/glm.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "bounce/gi.h"
#include "gi/engine_images.h"
#include "gi/frame_constants.h"
#include "gi/frame_passes.h"
#include "gi/image_table.h"
#include "gi/library_device.h"
#include "gi/pass_log.h"
#include "gi/scene_bridge.h"
#include "gi/units.h"
#include "gpu/error.h"
#include "gpu/format.h"
#include "gpu/recorder.h"
#include "gpu/timing.h"
#include "shared/checkerboard.glsl"

namespace bounce::gi {
namespace {

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
  std::vector<std::string> seen;
  for (const SignalDesc& signal : kLibrarySignals) seen.push_back(signal.name);
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
      throw Error(where + ": the name is taken by " +
                  (std::find(seen.begin(), seen.begin() + kLibrarySignalCount, signal.name) !=
                           seen.begin() + kLibrarySignalCount
                       ? "the library's own signal"
                       : "an earlier signal"));
    if (signal.kind != SignalKind::Diffuse && signal.kind != SignalKind::Specular)
      throw Error(where + ": kind " + std::to_string(std::uint32_t(signal.kind)) +
                  " is neither SignalKind::Diffuse nor Specular");
    seen.push_back(signal.name);
  }
}

// Calls `visit(registration, setup, products)` for every registered unit
// in recording order, with the setup it is made for: `products` what it
// makes, and the setup's madeLater what the units after it make.
template <typename Visit>
void forEachUnit(const ContextDesc& desc, const Settings& settings, std::span<const SignalDesc> signals,
                 bool bridgeTraces, Visit visit) {
  const std::vector<UnitRegistration> registered = registeredUnits();
  const Extent maxSize{desc.maxWidth, desc.maxHeight};
  const UnitSetup base{maxSize, settings, signals, bridgeTraces, [](std::string_view) { return false; }};
  std::vector<std::vector<std::string>> made;
  for (const UnitRegistration& registration : registered) made.push_back(registration.produces(base));
  for (std::size_t i = 0; i < registered.size(); ++i) {
    const UnitSetup setup{maxSize, settings, signals, bridgeTraces, [&made, i](std::string_view product) {
                            for (std::size_t later = i + 1; later < made.size(); ++later)
                              if (std::find(made[later].begin(), made[later].end(), product) != made[later].end())
                                return true;
                            return false;
                          }};
    visit(registered[i], setup, made[i]);
  }
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

namespace {

// What the units a context makes hold of their own, each sized as it
// sizes itself; and the transient pool: the most one unit's transient
// images take (the units record one at a time and share it).
std::uint64_t ownBytes(const ContextDesc& desc, const Settings& settings) {
  std::uint64_t bytes = sizeof(shared::GiFrameConstants);
  forEachUnit(desc, settings, signalsOf(desc), !desc.sceneBridge.shaders.empty(),
              [&](const UnitRegistration& registration, const UnitSetup& setup, const std::vector<std::string>&) {
                bytes += registration.memoryBytes(setup);
              });
  return bytes;
}

std::uint64_t transientBytes(const ContextDesc& desc, const Settings& settings) {
  std::uint64_t most = 0;
  forEachUnit(desc, settings, signalsOf(desc), !desc.sceneBridge.shaders.empty(),
              [&](const UnitRegistration& registration, const UnitSetup& setup, const std::vector<std::string>&) {
                if (registration.transientBytes) most = std::max(most, registration.transientBytes(setup));
              });
  return most;
}

}  // namespace

struct GiContext::Impl {
  ContextDesc desc;
  Settings settings;
  std::unique_ptr<gpu::Context> context;
  SceneBridgeBinding scene;
  gpu::MemoryArena arena;
  // The units' transient images (ImageSpec::transient): the units record
  // one after another, so their frame-local images share this memory,
  // rewound for each unit as it is made.
  gpu::MemoryArena transientPool;
  std::unique_ptr<gpu::Buffer> frameConstants;
  std::vector<SignalDesc> signals;      // by SignalId: the library's two, then ContextDesc::signals
  std::vector<std::string> noisyNames;  // noisyInputNames(signals)
  // The units in recording order (gi/units.h), and the products each makes.
  std::vector<std::unique_ptr<Unit>> units;
  std::vector<std::vector<std::string>> unitProducts;
  EngineImages engine;
  std::vector<std::unique_ptr<PassLog>> logs;  // one per frame in flight, used in turn

  // What the last frame left.
  std::uint64_t recorded = 0;  // frames recorded; the history images swap by this count
  std::optional<std::uint64_t> lastFrameIndex;
  Camera lastCamera;
  Extent lastSize;
  SignalFlags lastEngineSignals;  // which signals the engine gave
  Products lastProducts;          // the last frame's products (what indirect() and composite() hand out)

  Impl(const Device& device, const ContextDesc& d, const Settings& s)
      : desc(d),
        settings(s),
        context(openLibraryContext(device)),
        scene(*context, d.sceneBridge),
        arena(*context, VkDeviceSize(128) << 20, ownBytes(d, s)),
        transientPool(*context, VkDeviceSize(128) << 20, transientBytes(d, s)),
        frameConstants(std::make_unique<gpu::Buffer>(*context, "gi.frame_constants", sizeof(shared::GiFrameConstants),
                                                     gpu::BufferUsage::DeviceLocal, &arena)),
        signals(signalsOf(d)),
        noisyNames(noisyInputNames(signals)),
        engine(*context),
        lastEngineSignals(signals.size(), false) {
    const UnitResources resources{*context, arena, scene, &transientPool};
    forEachUnit(desc, settings, signals, scene.traces(),
                [&](const UnitRegistration& registration, const UnitSetup& setup, std::vector<std::string> made) {
                  transientPool.rewind();
                  std::unique_ptr<Unit> unit = registration.make(setup, resources);
                  if (!unit) return;
                  units.push_back(std::move(unit));
                  unitProducts.push_back(std::move(made));
                });
    for (std::uint32_t i = 0; i < desc.framesInFlight; ++i)
      logs.push_back(std::make_unique<PassLog>(*context, desc.timestamps, scene.traces()));
  }

  std::uint64_t current() const { return recorded == 0 ? 0 : recorded - 1; }

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
    if (!(frame.lightChange >= 0.0f && frame.lightChange <= 1.0f))
      throw Error("gi: FrameInputs::lightChange is " + std::to_string(frame.lightChange) +
                  "; it is a share of the light, within [0, 1]");
    // The noisy signals' size depends on the mode (EngineImages checks the
    // rest of them): the render size, or in checkerboard mode half its
    // width, rounded up. As every input, an image may be larger.
    std::vector<EngineImages::Noisy> noisy = noisyInputsOf(frame, noisyNames);
    for (const EngineImages::Noisy& given : noisy) {
      const ImageRef& ref = given.ref;
      if (ref.image == VK_NULL_HANDLE) continue;
      const std::string input = "gi: frame input " + std::string(given.name);
      if (!settings.denoise.enabled)
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
    c.declaredLightChange = frame.lightChange;
    return c;
  }

  // Which units record this frame and what they take: asked last to first,
  // each told what the units after it take (so a unit whose products
  // nobody takes this frame, the depth pyramid without a Hi-Z trace, rests).
  std::vector<Unit::Plan> planFrame(const SignalFlags& given, std::set<std::string, std::less<>>& wanted) const {
    std::vector<Unit::Plan> plans(units.size());
    for (std::size_t i = units.size(); i-- > 0;) {
      plans[i] = units[i]->plan({.signals = signals, .given = given, .wanted = wanted});
      if (!plans[i].records) continue;
      for (const std::string& taken : plans[i].takes) {
        const bool made = taken == product::kEnvironment ||
                          std::any_of(unitProducts.begin(), unitProducts.end(), [&](const auto& products) {
                            return std::find(products.begin(), products.end(), taken) != products.end();
                          });
        if (!made)
          throw Error("gi: unit '" + std::string(units[i]->name()) + "' takes the product '" + taken +
                      "', which no unit of the context makes");
        wanted.insert(taken);
      }
    }
    return plans;
  }

  // For each unit, the last unit recording this frame that takes one of its
  // products (its recordAfterConsumers follows that unit's record), or itself.
  std::vector<std::size_t> lastConsumers(const std::vector<Unit::Plan>& plans) const {
    std::vector<std::size_t> last(units.size());
    for (std::size_t producer = 0; producer < units.size(); ++producer) {
      last[producer] = producer;
      const std::vector<std::string>& made = unitProducts[producer];
      for (std::size_t consumer = producer + 1; consumer < units.size(); ++consumer)
        if (plans[consumer].records &&
            std::any_of(plans[consumer].takes.begin(), plans[consumer].takes.end(), [&](const std::string& taken) {
              return std::find(made.begin(), made.end(), taken) != made.end();
            }))
          last[producer] = consumer;
    }
    return last;
  }

  void record(VkCommandBuffer commandBuffer, const FrameInputs& frame) {
    if (commandBuffer == VK_NULL_HANDLE) throw Error("gi: record() needs a command buffer in the recording state");
    const std::vector<EngineImages::Noisy> noisy = check(frame);
    SignalFlags given(signals.size());
    for (std::size_t id = 0; id < signals.size(); ++id) given[id] = noisy[id].ref.image != VK_NULL_HANDLE;
    std::set<std::string, std::less<>> wanted;
    const std::vector<Unit::Plan> plans = planFrame(given, wanted);
    const std::vector<std::size_t> after = lastConsumers(plans);
    scene.take(frame);
    // Only units that take the environment (the branches) read it: without them it may be left out.
    engine.take(frame, noisy, desc.inputState, wanted.contains(product::kEnvironment));

    const Extent size{frame.width, frame.height};
    // A new render size makes last frame's images another picture: nothing of them is reused.
    const bool hasHistory = recorded > 0 && size.width == lastSize.width && size.height == lastSize.height;
    // A library signal that changed hands (the branch's last frame, the
    // engine's now, or back) finds histories the other never wrote: the
    // branch's reservoirs and filters, the denoiser's history of that
    // signal. All restart, as on a cut; engines switch rarely (a debug
    // toggle). (An engine's own signal given again restarts only its own
    // history: the denoiser's SignalInput::historyKept.)
    bool sameSources = true;
    for (std::size_t id = 0; id < kLibrarySignalCount; ++id)
      sameSources = sameSources && (recorded == 0 || given[id] == lastEngineSignals[id]);
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
    Products products;
    for (const std::unique_ptr<Unit>& unit : units) unit->putHistory(products, f);
    const glm::vec3 cameraPosition = glm::inverse(glm::make_mat4(frame.camera.worldToView))[3];
    const FrameState state{.recorder = recorder,
                           .group = group,
                           .engine = engine,
                           .environmentSampler = frame.environmentSampler,
                           .nearestSampler = context->nearestSampler(),
                           .frameIndex = f,
                           .renderSize = size,
                           .hasHistory = hasHistory,
                           .usableHistory = usableHistory,
                           .capturing = frame.captureStages,
                           .cameraPosition = {cameraPosition.x, cameraPosition.y, cameraPosition.z},
                           .signals = signals,
                           .given = given,
                           .givenLastFrame = lastEngineSignals,
                           .products = products,
                           .previous = lastProducts};
    for (std::size_t i = 0; i < units.size(); ++i) {
      if (plans[i].records) {
        for (ImageSet* set : units[i]->imageSets()) set->takeTransients();
        for (gpu::Buffer* buffer : units[i]->transientBuffers()) takeTransient(*buffer);
        units[i]->record(state);
      }
      for (std::size_t producer = 0; producer <= i; ++producer)
        if (plans[producer].records && after[producer] == i) units[producer]->recordAfterConsumers(state);
    }
    log.end(recorder);

    engine.handBack(recorder);
    // Stage copies moved some images to transfer layouts: every library
    // image is left as LibraryImage says.
    if (frame.captureStages) {
      for (const std::unique_ptr<Unit>& unit : units)
        for (ImageSet* set : unit->imageSets())
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
    lastProducts = std::move(products);
  }

  // An image product of the last frame, for the engine; `what` names the call.
  gpu::Image& lastProduct(std::string_view name, const std::string& what) const {
    if (recorded == 0) throw Error("gi: " + what + ": no frame has been recorded yet");
    return lastProducts.image(name);
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
  return libraryRef(impl_->lastProduct(impl_->signals[signal].name, "indirect(" + std::to_string(signal) + ")"));
}

std::vector<SignalDesc> GiContext::signals() const { return impl_->signals; }

ImageRef GiContext::indirectDiffuse() const { return indirect(kDiffuseSignal); }

ImageRef GiContext::indirectSpecular() const { return indirect(kSpecularSignal); }

ImageRef GiContext::composite() const { return libraryRef(impl_->lastProduct(product::kComposite, "composite()")); }

std::vector<LibraryImage> GiContext::images() const {
  std::vector<LibraryImage> list;
  for (const std::unique_ptr<Unit>& unit : impl_->units)
    for (const ImageSet::Listed& image : unit->listImages(impl_->current()))
      list.push_back(
          {image.name, libraryRef(*image.image), visualization(image.spec->view), std::string(image.spec->purpose)});
  return list;
}

std::uint64_t GiContext::memoryBytes() const { return impl_->arena.bytes() + impl_->transientPool.bytes(); }

std::vector<UnitMemory> GiContext::memoryByUnit() const {
  std::vector<UnitMemory> units = {{"diffuse"}, {"specular"}, {"cache"}, {"denoise"}, {"frame"}};
  for (const auto& [name, bytes] : impl_->arena.bytesByName()) {
    UnitMemory* owner = &units[4];
    for (UnitMemory& unit : units)
      if (name.rfind("gi." + unit.unit + ".", 0) == 0) owner = &unit;
    owner->bytes += bytes;
  }
  units.push_back({"transient", impl_->transientPool.peakRequested()});
  return units;
}

std::uint64_t GiContext::estimateMemoryBytes(const ContextDesc& desc, const Settings& settings) {
  return ownBytes(desc, settings) + transientBytes(desc, settings);
}

const Settings& GiContext::settings() const { return impl_->settings; }
std::uint32_t GiContext::maxWidth() const { return impl_->desc.maxWidth; }
std::uint32_t GiContext::maxHeight() const { return impl_->desc.maxHeight; }

}  // namespace bounce::gi
