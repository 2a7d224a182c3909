#include "gi/denoise/denoiser.h"

#include <cmath>
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

constexpr ImageSpec kSharedImages[] = {
    {"gi.denoise.tiles", Resolution::Tile, kR16f, false, Visualize::Raw, "1 where a 16x16 tile has a surface"},
    {"gi.denoise.surface", Resolution::Full, kRg32ui, false, Visualize::Raw,
     "this frame's viewZ bits, octahedral normal and roughness, one load a tap (viewZ 0: no usable surface)"},
    {"gi.denoise.pre_passed", Resolution::Full, kRgba16f, false, Visualize::Radiance,
     "the pre-pass's output: the noisy signal pre-blurred; alpha: hit distance (each signal in turn)"},
    {"gi.denoise.accumulated", Resolution::Full, kRgba16f, false, Visualize::Radiance,
     "temporal accumulation's output, then blur's: radiance, history length (each signal in turn)"},
    {"gi.denoise.fixed", Resolution::Full, kRgba16f, false, Visualize::Radiance,
     "history fix's output: short histories rebuilt, fireflies removed (each signal in turn)"},
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
    {"moments",
     {"", Resolution::Full, kRgba16f, true, Visualize::Raw,
      "luminance moments: mean and deviation over the history, mean of the fast history; specular kind: the "
      "virtual history's share"}},
    {"history",
     {"", Resolution::Full, kRgba16f, true, Visualize::Radiance,
      "post-blur's output: next frame's history; alpha: history length"}},
    {"stabilized",
     {"", Resolution::Full, kRgba16f, true, Visualize::Radiance,
      "the denoised signal (temporal stabilisation's output); alpha: its history length"}},
};
static_assert(std::size(kSignalImages) == kDenoisePerSignal, "one table entry per DenoiseSignalImage");

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

struct Denoiser::Passes {
  struct Signal {
    gpu::ComputePass prePass, temporalAccumulation, historyFix, blur, postBlur, temporalStabilization;
    Signal(gpu::Context& context, const std::string& name)
        : prePass(context, denoisePrePass(name)),
          temporalAccumulation(context, denoiseTemporalAccumulationPass(name)),
          historyFix(context, denoiseHistoryFixPass(name)),
          blur(context, denoiseBlurPass(name)),
          postBlur(context, denoisePostBlurPass(name)),
          temporalStabilization(context, denoiseTemporalStabilizationPass(name)) {}
  };
  gpu::ComputePass classifyTiles;
  std::vector<std::unique_ptr<Signal>> signals;
  std::unique_ptr<gpu::ComputePass> validation;  // made on the first captured frame
  Passes(gpu::Context& context, std::span<const SignalDesc> descs)
      : classifyTiles(context, denoiseClassifyTilesPass()) {
    for (const SignalDesc& signal : descs) signals.push_back(std::make_unique<Signal>(context, signal.name));
  }
};

Denoiser::Denoiser(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize, const DenoiseSettings& settings,
                   std::vector<SignalDesc> signals)
    : context_(context), settings_(settings), signals_(std::move(signals)), lastDenoised_(signals_.size()) {
  addDenoiseImages(table_, signals_);
  images_ = std::make_unique<ImageSet>(context, arena, table_.specs(), maxSize);
  constants_ = std::make_unique<gpu::Buffer>(context, "gi.denoise.constants", sizeof(shared::DenoiseConstants),
                                             gpu::BufferUsage::DeviceLocal, &arena);
  passes_ = std::make_unique<Passes>(context, signals_);
}

Denoiser::~Denoiser() = default;

std::vector<gpu::PassDesc> Denoiser::passes(std::span<const SignalDesc> signals) {
  std::vector<gpu::PassDesc> all = {denoiseClassifyTilesPass()};
  for (const SignalDesc& signal : signals)
    for (gpu::PassDesc desc : {denoisePrePass(signal.name), denoiseTemporalAccumulationPass(signal.name),
                               denoiseHistoryFixPass(signal.name), denoiseBlurPass(signal.name),
                               denoisePostBlurPass(signal.name), denoiseTemporalStabilizationPass(signal.name)})
      all.push_back(std::move(desc));
  all.push_back(denoiseValidationPass());
  return all;
}

std::size_t Denoiser::imageOf(std::size_t signal, DenoiseSignalImage image) const {
  return kDenoiseSharedImages + kDenoisePerSignal * signal + image;
}

gpu::Image& Denoiser::result(std::size_t signal, std::uint64_t frameIndex) {
  return images_->current(imageOf(signal, kDenoiseStabilized), frameIndex);
}

gpu::Image& Denoiser::previousResult(std::size_t signal, std::uint64_t frameIndex) {
  return images_->previous(imageOf(signal, kDenoiseStabilized), frameIndex);
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
  if (f == 0) {
    std::vector<std::size_t> results;
    for (std::size_t signal = 0; signal < signals_.size(); ++signal)
      results.push_back(imageOf(signal, kDenoiseStabilized));
    images_->clearToZero(recorder, results, f);
  }
  const gpu::Bind constants("gIn_DenoiseConstants", *constants_);
  gpu::Image& tiles = images_->current(kDenoiseTiles, f);
  gpu::Image& surface = images_->current(kDenoiseSurface, f);
  recorder.dispatch(passes_->classifyTiles, full.width, full.height, frame.group.binds(GroupPart::Surfaces),
                    {{"gOut_Tiles", tiles}, {"gOut_Surface", surface}});
  const gpu::Bind tilesBind("gIn_Tiles", tiles);
  const gpu::Bind surfaceBind("gIn_DenoiseSurface", surface);
  const gpu::Bind motion("gIn_Motion", frame.engine[Input::Motion], frame.nearestSampler);
  gpu::Image& prePassed = images_->current(kDenoisePrePassed, f);
  gpu::Image& accumulated = images_->current(kDenoiseAccumulated, f);
  gpu::Image& fixed = images_->current(kDenoiseFixed, f);

  for (std::size_t signal = 0; signal < signals_.size(); ++signal) {
    const SignalInput& in = inputs[signal];
    if (!in.noisy) continue;
    Passes::Signal& p = *passes_->signals[signal];
    const bool specular = signals_[signal].kind == SignalKind::Specular;
    const auto image = [&](DenoiseSignalImage which) -> gpu::Image& {
      return images_->current(imageOf(signal, which), f);
    };
    const auto previous = [&](DenoiseSignalImage which) -> gpu::Image& {
      return images_->previous(imageOf(signal, which), f);
    };
    const std::uint32_t flags = (frame.usableHistory && in.historyKept ? shared::kSignalHasHistory : 0u) |
                                (in.checkerboarded ? shared::kSignalCheckerboard : 0u);
    const DenoiseSignalParams atFullRadius{std::uint32_t(signal), std::uint32_t(signals_[signal].kind), flags, 1.0f};
    DenoiseSignalParams post = atFullRadius;
    post.radiusScale = s.postBlurRadiusScale;
    // The pre-pass's output takes the noisy signal's place in every later
    // pass; without a pre-pass, the noisy signal. A checkerboarded signal
    // always has one: it fills the pixels without a sample, even where it
    // blurs nothing (radius 0).
    const float prePassRadius = specular ? s.specularPrePassRadius : s.diffusePrePassRadius;
    const bool prePass = prePassRadius > 0.0f || in.checkerboarded;
    if (prePass)
      recorder.dispatch(p.prePass, full.width, full.height, frame.group.binds(GroupPart::Constants),
                        {constants, tilesBind, surfaceBind, {"gIn_Signal", *in.noisy}, {"gOut_PrePassed", prePassed}},
                        atFullRadius);
    const gpu::Bind input("gIn_Signal", prePass ? prePassed : *in.noisy);
    recorder.dispatch(p.temporalAccumulation, full.width, full.height, frame.group.binds(GroupPart::Constants),
                      {constants,
                       tilesBind,
                       surfaceBind,
                       motion,
                       input,
                       {"gPrev_Surface", frame.products.image(product::kPreviousSurface)},
                       {"gPrev_Filtered", previous(kDenoiseHistory)},
                       {"gPrev_Moments", previous(kDenoiseMoments)},
                       {"gOut_Accumulated", accumulated},
                       {"gOut_Moments", image(kDenoiseMoments)},
                       {"gIn_Surface", frame.products.image(product::kSurface)},
                       {"gIn_LightChange", frame.products.image(product::kLightChange)}},
                      atFullRadius);
    recorder.dispatch(p.historyFix, full.width, full.height, frame.group.binds(GroupPart::Constants),
                      {constants, tilesBind, surfaceBind, {"gIn_Accumulated", accumulated}, {"gOut_Fixed", fixed}},
                      atFullRadius);
    recorder.dispatch(
        p.blur, full.width, full.height, frame.group.binds(GroupPart::Constants),
        {constants, tilesBind, surfaceBind, input, {"gIn_Filtered", fixed}, {"gOut_Filtered", accumulated}},
        atFullRadius);
    recorder.dispatch(p.postBlur, full.width, full.height, frame.group.binds(GroupPart::Constants),
                      {constants,
                       tilesBind,
                       surfaceBind,
                       input,
                       {"gIn_Filtered", accumulated},
                       {"gOut_Filtered", image(kDenoiseHistory)}},
                      post);
    recorder.dispatch(p.temporalStabilization, full.width, full.height, frame.group.binds(GroupPart::Constants),
                      {constants,
                       tilesBind,
                       surfaceBind,
                       motion,
                       {"gIn_Filtered", image(kDenoiseHistory)},
                       {"gPrev_Surface", frame.products.image(product::kPreviousSurface)},
                       {"gPrev_Stabilized", previous(kDenoiseStabilized)},
                       {"gOut_Stabilized", image(kDenoiseStabilized)},
                       {"gIn_Surface", frame.products.image(product::kSurface)},
                       {"gIn_LightChange", frame.products.image(product::kLightChange)}},
                      atFullRadius);
  }
  if (frame.capturing) recordValidation(frame, inputs);
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
                                              std::vector<SignalDesc>(setup.signals.begin(), setup.signals.end()));
          },
          .memoryBytes =
              [](const UnitSetup& setup) {
                return setup.settings.denoise.enabled ? denoiserMemoryBytes(setup.maxSize, setup.signals)
                                                      : std::uint64_t(0);
              }};
}

}  // namespace bounce::gi
