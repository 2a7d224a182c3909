#include "gi/denoise/denoiser.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>
#include <stdexcept>

#include <glm/glm.hpp>

#include "gi/denoise/denoise_common.glsl"
#include "gi/denoise/denoise_passes.h"
#include "gi/units.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

using namespace gpu::formats;
using gpu::Visualize;

// The render height the settings' radii are given for.
constexpr float kReferenceRows = 1080.0f;
// The edge of the denoiser's tiles (denoise_common.glsl's kDenoiseTile),
// which the stages that share a neighbourhood take as their workgroups.
constexpr std::uint32_t kTile = 16;

constexpr ImageSpec kSharedImages[] = {
    {"gi.denoise.tiles", Resolution::Tile, kR16f, false, Visualize::Raw, "1 where a 16x16 tile has a surface", false,
     true},
    {"gi.denoise.surface", Resolution::Full, kRg32ui, false, Visualize::Raw,
     "this frame's viewZ bits, octahedral normal and roughness, one load a tap (viewZ 0: no usable surface)", false,
     true},
    {"gi.denoise.empty_slot", Resolution::Single, kRgba16f, false, Visualize::Raw,
     "bound to the slots of a dispatch that no signal takes; never read or written"},
    {"gi.denoise.validation", Resolution::Full, kRgba16f, false, Visualize::Color,
     "the validation view: viewZ, normals, motion, specular virtual history; diffuse and specular history "
     "length, denoised light with disocclusions in red (captured frames only)",
     true},
};
static_assert(std::size(kSharedImages) == kDenoiseSharedImages, "one table entry per DenoiseImage");

// Each signal's own images, named gi.denoise.SIGNAL.NAME.
struct SignalImage {
  const char* name;
  ImageSpec spec;
};
constexpr SignalImage kSignalImages[] = {
    {"pre_passed",
     {"", Resolution::Full, kRgba16f, false, Visualize::Radiance,
      "the pre-pass's output: the noisy signal pre-blurred; alpha: hit distance; from post-blur on, last frame's "
      "stabilised signal (stabilisation's history)",
      false, true}},
    {"accumulated",
     {"", Resolution::Full, kRgba16f, false, Visualize::Radiance,
      "temporal accumulation's output, then blur's: radiance, history length", false, true}},
    {"history",
     {"", Resolution::Full, kRgba16f, false, Visualize::Radiance,
      "last frame's history (read by temporal accumulation), then history fix's output, then post-blur's: next "
      "frame's history; alpha: history length"}},
    {"moments",
     {"", Resolution::Full, kRgba16f, true, Visualize::Raw,
      "luminance moments: mean and deviation over the history, mean of the fast history; specular kind: the "
      "virtual history's share"}},
    {"stabilized",
     {"", Resolution::Full, kRgba16f, false, Visualize::Radiance,
      "the denoised signal (temporal stabilisation's output), kept as next frame's stabilisation history; alpha: its "
      "history length"}},
};
static_assert(std::size(kSignalImages) == kDenoisePerSignal, "one table entry per DenoiseSignalImage");

// The binds of one dispatch: its shared ones, then each per-signal binding
// once per slot (the filler image in the slots no signal takes), captured
// as SIGNAL.BINDING (gi.denoise.blur's specular.gOut_Filtered). Owns the
// names the binds point to.
class SlotBinds {
 public:
  SlotBinds(std::span<const std::string> signalNames, std::initializer_list<gpu::Bind> shared)
      : signalNames_(signalNames), binds_(shared) {}
  // Binding `name` of every slot: `image(k)` for the batch's k-th signal,
  // the filler past them; a sampled slot with `sampler`.
  template <class ImageOf>
  void slots(std::string_view name, gpu::Image& filler, ImageOf image, VkSampler sampler = VK_NULL_HANDLE) {
    for (std::size_t k = 0; k < shared::kDenoiseSlots; ++k) {
      const std::string& slotName = names_.emplace_back(denoiseSlotName(name, k));
      gpu::Bind bind = gpu::Bind::filler(slotName, filler);
      if (k < signalNames_.size()) {
        const std::string& label = names_.emplace_back(signalNames_[k] + "." + std::string(name));
        bind = gpu::Bind::labelled(slotName, image(k), label);
      }
      bind.sampler = sampler;
      binds_.push_back(bind);
    }
  }
  std::span<const gpu::Bind> binds() const { return binds_; }

 private:
  std::span<const std::string> signalNames_;  // the batch's, one per slot in use
  std::deque<std::string> names_;             // a deque: growing it moves no name a bind points to
  std::vector<gpu::Bind> binds_;
};

}  // namespace

void addDenoiseImages(ImageTableBuilder& table, std::span<const SignalDesc> signals) {
  for (const ImageSpec& spec : kSharedImages) table.add(std::string(spec.name), spec);
  for (const SignalDesc& signal : signals)
    for (const SignalImage& image : kSignalImages)
      table.add("gi.denoise." + signal.name + "." + image.name, image.spec);
}

std::uint64_t denoiserMemoryBytes(Extent maxSize, std::span<const SignalDesc> signals) {
  ImageTableBuilder table;
  addDenoiseImages(table, signals);
  return imageSetBytes(table.specs(), maxSize) + sizeof(shared::DenoiseConstants);
}

std::uint64_t denoiserTransientBytes(Extent maxSize, std::span<const SignalDesc> signals) {
  ImageTableBuilder table;
  addDenoiseImages(table, signals);
  return transientImageBytes(table.specs(), maxSize);
}

struct Denoiser::Passes {
  gpu::ComputePass classifyTiles, prePass, temporalAccumulation, historyFix, blur, postBlur, temporalStabilization;
  std::unique_ptr<gpu::ComputePass> validation;  // made on the first captured frame
  explicit Passes(gpu::Context& context)
      : classifyTiles(context, denoiseClassifyTilesPass()),
        prePass(context, denoisePrePass()),
        temporalAccumulation(context, denoiseTemporalAccumulationPass()),
        historyFix(context, denoiseHistoryFixPass()),
        blur(context, denoiseBlurPass()),
        postBlur(context, denoisePostBlurPass()),
        temporalStabilization(context, denoiseTemporalStabilizationPass()) {}
};

Denoiser::Denoiser(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize, const DenoiseSettings& settings,
                   std::vector<SignalDesc> signals, gpu::MemoryArena* transientPool)
    : context_(context), settings_(settings), signals_(std::move(signals)), lastDenoised_(signals_.size()) {
  addDenoiseImages(table_, signals_);
  images_ = std::make_unique<ImageSet>(context, arena, table_.specs(), maxSize, 0, std::span<const std::size_t>(),
                                       transientPool);
  constants_ = std::make_unique<gpu::Buffer>(context, "gi.denoise.constants", sizeof(shared::DenoiseConstants),
                                             gpu::BufferUsage::DeviceLocal, &arena);
  passes_ = std::make_unique<Passes>(context);
}

Denoiser::~Denoiser() = default;

std::vector<gpu::PassDesc> Denoiser::passes(std::span<const SignalDesc>) {
  return {denoiseClassifyTilesPass(),
          denoisePrePass(),
          denoiseTemporalAccumulationPass(),
          denoiseHistoryFixPass(),
          denoiseBlurPass(),
          denoisePostBlurPass(),
          denoiseTemporalStabilizationPass(),
          denoiseValidationPass()};
}

std::size_t Denoiser::imageOf(std::size_t signal, DenoiseSignalImage image) const {
  return kDenoiseSharedImages + kDenoisePerSignal * signal + image;
}

gpu::Image& Denoiser::result(std::size_t signal, std::uint64_t frameIndex) {
  return images_->current(imageOf(signal, kDenoiseStabilized), frameIndex);
}

void Denoiser::record(const FrameState& frame, std::span<const SignalInput> inputs) {
  if (inputs.size() != signals_.size())
    throw std::logic_error("gi: the denoiser has " + std::to_string(signals_.size()) + " signals, given " +
                           std::to_string(inputs.size()));
  gpu::Recorder& recorder = frame.recorder;
  const std::uint64_t f = frame.frameIndex;
  const DenoiseSettings& s = settings_;
  const Extent full = frame.renderSize;

  shared::DenoiseConstants c{};
  // REBLUR's hit-distance normalisation (A, B, C, D).
  c.hitDistanceParameters = glm::vec4(3.0f, 0.1f, 20.0f, -25.0f);
  c.maxAccumulatedFrames = float(s.maxAccumulatedFrames);
  c.historyFixFrames = float(s.historyFixFrames);
  // Radii are set for 1080 rows (REBLUR's pixels) and follow the render
  // height: the same blur covers the same part of the picture at any size.
  const float pixelScale = float(full.height) / kReferenceRows;
  c.historyFixStride = s.historyFixStride * pixelScale;
  c.blurRadius = s.blurRadius * pixelScale;
  c.postBlurRadiusScale = s.postBlurRadiusScale;
  c.minBlurRadius = s.minBlurRadius * pixelScale;
  c.planeDistanceSensitivity = s.planeDistanceSensitivity;
  c.lobeAngleFraction = s.lobeAngleFraction;
  c.roughnessFraction = s.roughnessFraction;
  c.stabilizationFrames = float(s.stabilizationFrames);
  c.clampSigma = s.clampSigma;
  c.depthTolerance = s.depthTolerance;
  c.cosNormalTolerance = std::cos(glm::radians(s.normalToleranceDegrees));
  c.disocclusionThreshold = s.disocclusionThreshold;
  c.frameIndex = std::uint32_t(f);
  c.antiFirefly = s.antiFirefly ? 1u : 0u;
  c.diffusePrePassRadius = s.diffusePrePassRadius * pixelScale;
  c.specularPrePassRadius = s.specularPrePassRadius * pixelScale;
  recorder.updateBuffer(*constants_, &c, sizeof c);
  // Every signal's result starts at zero: an engine may read indirect(id)
  // of a signal it has not given yet.
  // The filler of unused slots too, which no pass touches: whoever lists
  // the library's images reads zeros there.
  if (f == 0) {
    std::vector<std::size_t> results = {kDenoiseEmptySlot};
    for (std::size_t signal = 0; signal < signals_.size(); ++signal)
      results.push_back(imageOf(signal, kDenoiseStabilized));
    images_->clearToZero(recorder, results, f);
  }
  gpu::Image& tiles = images_->current(kDenoiseTiles, f);
  gpu::Image& surface = images_->current(kDenoiseSurface, f);
  recorder.dispatch(passes_->classifyTiles, full.width, full.height, frame.group.binds(GroupPart::Surfaces),
                    {{"gOut_Tiles", tiles}, {"gOut_Surface", surface}});
  // The signals with an input this frame, kDenoiseSlots to a dispatch.
  std::vector<std::size_t> given;
  for (std::size_t signal = 0; signal < signals_.size(); ++signal)
    if (inputs[signal].noisy) given.push_back(signal);
  for (std::size_t first = 0; first < given.size(); first += shared::kDenoiseSlots)
    recordBatch(frame, inputs,
                std::span<const std::size_t>(given).subspan(first, std::min<std::size_t>(shared::kDenoiseSlots,
                                                                                          given.size() - first)));
  if (frame.capturing) recordValidation(frame, inputs);
}

void Denoiser::recordBatch(const FrameState& frame, std::span<const SignalInput> inputs,
                           std::span<const std::size_t> batch) {
  gpu::Recorder& recorder = frame.recorder;
  const std::uint64_t f = frame.frameIndex;
  const Extent full = frame.renderSize;
  std::vector<std::string> names;
  for (std::size_t signal : batch) names.push_back(signals_[signal].name);
  gpu::Image& filler = images_->current(kDenoiseEmptySlot, f);
  const auto image = [&](DenoiseSignalImage which) {
    return [&, which](std::size_t k) -> gpu::Image& { return images_->current(imageOf(batch[k], which), f); };
  };
  const auto previous = [&](DenoiseSignalImage which) {
    return [&, which](std::size_t k) -> gpu::Image& { return images_->previous(imageOf(batch[k], which), f); };
  };

  DenoiseSignalParams atFullRadius{};
  atFullRadius.count = std::uint32_t(batch.size());
  atFullRadius.radiusScale = 1.0f;
  for (std::size_t k = 0; k < batch.size(); ++k) {
    const SignalInput& in = inputs[batch[k]];
    atFullRadius.kinds[k] = std::uint32_t(signals_[batch[k]].kind);
    atFullRadius.flags[k] = (frame.usableHistory && in.historyKept ? shared::kSignalHasHistory : 0u) |
                            (in.checkerboarded ? shared::kSignalCheckerboard : 0u);
    atFullRadius.indices[k] = std::uint32_t(batch[k]);
  }
  DenoiseSignalParams post = atFullRadius;
  post.radiusScale = settings_.postBlurRadiusScale;

  const gpu::Bind constants("gIn_DenoiseConstants", *constants_);
  const gpu::Bind tiles("gIn_Tiles", images_->current(kDenoiseTiles, f));
  const gpu::Bind surface("gIn_DenoiseSurface", images_->current(kDenoiseSurface, f));
  const gpu::Bind motion("gIn_Motion", frame.engine[Input::Motion], frame.nearestSampler);
  const gpu::Bind previousSurface("gPrev_Surface", frame.products.image(product::kPreviousSurface));
  const gpu::Bind currentSurface("gIn_Surface", frame.products.image(product::kSurface));
  const gpu::Bind lightChange("gIn_LightChange", frame.products.image(product::kLightChange));
  const auto dispatch = [&](const gpu::ComputePass& pass, const SlotBinds& binds, const DenoiseSignalParams& params) {
    recorder.dispatch(pass, full.width, full.height, frame.group.binds(GroupPart::Constants), binds.binds(), &params,
                      sizeof params);
  };
  const auto noisy = [&](std::size_t k) -> gpu::Image& { return *inputs[batch[k]].noisy; };

  // Every signal has a pre-pass: at radius 0 it hands the later passes a
  // sanitised copy (and a checkerboarded signal's filled pixels).
  SlotBinds prePass(names, {constants, tiles, surface});
  prePass.slots("gIn_Signal", filler, noisy);
  prePass.slots("gOut_PrePassed", filler, image(kDenoisePrePassed));
  dispatch(passes_->prePass, prePass, atFullRadius);

  SlotBinds accumulation(names, {constants, tiles, surface, motion, previousSurface, currentSurface, lightChange});
  accumulation.slots("gIn_Signal", filler, image(kDenoisePrePassed));
  // Sampled in texel coordinates (the Catmull-Rom history's bilinear fetches).
  const VkSampler texels = context_.texelLinearSampler();
  accumulation.slots("gPrev_Filtered", filler, image(kDenoiseHistory), texels);
  accumulation.slots("gPrev_Moments", filler, previous(kDenoiseMoments));
  accumulation.slots("gOut_Accumulated", filler, image(kDenoiseAccumulated));
  accumulation.slots("gOut_Moments", filler, image(kDenoiseMoments));
  // A workgroup per signal: the slots' frames one under another, each
  // rounded up to whole tiles (the shader's workgroups are tiles).
  const std::uint32_t rowsPerSlot = (full.height + kTile - 1u) / kTile * kTile;
  recorder.dispatch(passes_->temporalAccumulation, full.width, rowsPerSlot * std::uint32_t(batch.size()),
                    frame.group.binds(GroupPart::Constants), accumulation.binds(), &atFullRadius,
                    sizeof atFullRadius);

  SlotBinds historyFix(names, {constants, tiles, surface});
  historyFix.slots("gIn_Accumulated", filler, image(kDenoiseAccumulated));
  historyFix.slots("gOut_Fixed", filler, image(kDenoiseHistory));
  dispatch(passes_->historyFix, historyFix, atFullRadius);

  SlotBinds blur(names, {constants, tiles, surface});
  blur.slots("gIn_Filtered", filler, image(kDenoiseHistory));
  blur.slots("gIn_Signal", filler, image(kDenoisePrePassed));
  blur.slots("gOut_Filtered", filler, image(kDenoiseAccumulated));
  dispatch(passes_->blur, blur, atFullRadius);

  // Post-blur also hands last frame's stabilised value to stabilisation
  // through the pre-passed image, which nothing reads after it: the one
  // stabilised image is then free for stabilisation to write.
  SlotBinds postBlur(names, {constants, tiles, surface});
  postBlur.slots("gIn_Filtered", filler, image(kDenoiseAccumulated));
  postBlur.slots("gPrev_Stabilized", filler, image(kDenoiseStabilized));
  postBlur.slots("gInOut_PrePassed", filler, image(kDenoisePrePassed));
  postBlur.slots("gOut_Filtered", filler, image(kDenoiseHistory));
  dispatch(passes_->postBlur, postBlur, post);

  SlotBinds stabilization(names, {constants, tiles, surface, motion, previousSurface, currentSurface, lightChange});
  stabilization.slots("gIn_Filtered", filler, image(kDenoiseHistory));
  stabilization.slots("gPrev_Stabilized", filler, image(kDenoisePrePassed), texels);
  stabilization.slots("gOut_Stabilized", filler, image(kDenoiseStabilized));
  dispatch(passes_->temporalStabilization, stabilization, atFullRadius);
}

void Denoiser::recordValidation(const FrameState& frame, std::span<const SignalInput> inputs) {
  // The panels show the first signal of each kind denoised this frame.
  std::optional<std::size_t> diffuse, specular;
  for (std::size_t signal = 0; signal < signals_.size(); ++signal) {
    if (!inputs[signal].noisy) continue;
    std::optional<std::size_t>& shown = signals_[signal].kind == SignalKind::Specular ? specular : diffuse;
    if (!shown) shown = signal;
  }
  if (!diffuse && !specular) return;
  if (!passes_->validation) {
    passes_->validation = std::make_unique<gpu::ComputePass>(context_, denoiseValidationPass());
    images_->makeDebugImages();
  }
  const std::uint64_t f = frame.frameIndex;
  // A kind none of whose signals ran shows black; its slots hold the other kind's images.
  const std::size_t d = diffuse.value_or(*specular), s = specular.value_or(*diffuse);
  const DenoiseValidationParams params{diffuse ? 1u : 0u, specular ? 1u : 0u};
  frame.recorder.dispatch(*passes_->validation, frame.renderSize.width, frame.renderSize.height, frame.group.binds(),
                          {{"gIn_DenoiseConstants", *constants_},
                           {"gIn_Motion", frame.engine[Input::Motion], frame.nearestSampler},
                           {"gIn_DiffuseHistory", images_->current(imageOf(d, kDenoiseHistory), f)},
                           {"gIn_SpecularHistory", images_->current(imageOf(s, kDenoiseHistory), f)},
                           {"gIn_SpecularMoments", images_->current(imageOf(s, kDenoiseMoments), f)},
                           {"gIn_Diffuse", images_->current(imageOf(d, kDenoiseStabilized), f)},
                           {"gIn_Specular", images_->current(imageOf(s, kDenoiseStabilized), f)},
                           {"gOut_Validation", images_->current(kDenoiseValidation, f)}},
                          params);
}

Unit::Plan Denoiser::plan(const FramePlan&) const {
  return {.records = true,
          .takes = {std::string(product::kSurface), std::string(product::kPreviousSurface),
                    std::string(product::kLightChange)}};
}

void Denoiser::record(const FrameState& frame) {
  std::vector<SignalInput> inputs(signals_.size());
  for (std::size_t id = 0; id < signals_.size(); ++id) {
    const std::string noisy = product::noisy(signals_[id].name);
    SignalInput& in = inputs[id];
    in.noisy = frame.products.find(noisy);
    // Checkerboard mode is the engine's: the library's branches make full signals.
    in.checkerboarded = frame.given[id] && settings_.checkerboard;
    // A signal not made last frame (an engine's, given again) has no history of last frame's.
    in.historyKept = frame.previous.has(noisy);
  }
  record(frame, inputs);
  for (std::size_t id = 0; id < signals_.size(); ++id)
    if (inputs[id].noisy) {
      frame.products.put(signals_[id].name, result(id, frame.frameIndex));
      lastDenoised_[id] = frame.frameIndex;
    }
}

void Denoiser::putHistory(Products& products, std::uint64_t frameIndex) {
  // A signal not given this frame (an engine's own) stays as the last frame
  // that gave it left it (zero before the first): its result image of that
  // frame, which no later frame wrote. A signal denoised this frame is put
  // again by record(); the library's, when not denoised, by its branch.
  for (std::size_t id = 0; id < signals_.size(); ++id)
    products.put(signals_[id].name, result(id, lastDenoised_[id].value_or(frameIndex)));
}

UnitRegistration denoiseUnit() {
  return {.name = "denoise",
          .produces =
              [](const UnitSetup& setup) {
                std::vector<std::string> names;
                if (setup.settings.denoise.enabled)
                  for (const SignalDesc& signal : setup.signals) names.push_back(signal.name);
                return names;
              },
          .make = [](const UnitSetup& setup, const UnitResources& resources) -> std::unique_ptr<Unit> {
            if (!setup.settings.denoise.enabled) return nullptr;
            return std::make_unique<Denoiser>(resources.context, resources.arena, setup.maxSize, setup.settings.denoise,
                                              std::vector<SignalDesc>(setup.signals.begin(), setup.signals.end()),
                                              resources.transientPool);
          },
          .memoryBytes =
              [](const UnitSetup& setup) {
                return setup.settings.denoise.enabled ? denoiserMemoryBytes(setup.maxSize, setup.signals)
                                                      : std::uint64_t(0);
              },
          .transientBytes =
              [](const UnitSetup& setup) {
                return setup.settings.denoise.enabled ? denoiserTransientBytes(setup.maxSize, setup.signals)
                                                      : std::uint64_t(0);
              }};
}

}  // namespace bounce::gi
