#include "gi/denoise/denoiser.h"

#include <cmath>

#include <glm/glm.hpp>

#include "gi/denoise/denoise_common.glsl"
#include "gi/denoise/denoise_passes.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

using namespace gpu::formats;
using gpu::Visualize;

constexpr std::array<const char*, kDenoiseSignals> kSignalNames = {"diffuse", "specular"};

// The render height the settings' radii are given for.
constexpr float kReferenceRows = 1080.0f;

// The images of one signal (names gi.denoise.SIGNAL.*).
#define BOUNCE_DENOISE_SIGNAL_IMAGES(SIGNAL)                                                                       \
  {"gi.denoise." SIGNAL ".pre_passed", Resolution::Full, kRgba16f, false, Visualize::Radiance,                    \
   "the pre-pass's output: the noisy signal pre-blurred; alpha: hit distance"},                                    \
      {"gi.denoise." SIGNAL ".accumulated", Resolution::Full, kRgba32f, false, Visualize::Radiance,                   \
   "temporal accumulation's output, then blur's: radiance, history length"},                                      \
      {"gi.denoise." SIGNAL ".moments", Resolution::Full, kRgba32f, true, Visualize::Raw,                         \
       "luminance moments: mean and mean square over the history, mean of the fast history; specular: the "     \
       "virtual history's share"},                     \
      {"gi.denoise." SIGNAL ".fixed", Resolution::Full, kRgba32f, false, Visualize::Radiance,                     \
       "history fix's output: short histories rebuilt, fireflies removed"},                                       \
      {"gi.denoise." SIGNAL ".history", Resolution::Full, kRgba32f, true, Visualize::Radiance,                    \
       "post-blur's output: next frame's history; alpha: history length"},                                        \
      {"gi.denoise." SIGNAL ".stabilized", Resolution::Full, kRgba32f, true, Visualize::Radiance,                 \
       "the denoised signal (temporal stabilisation's output); alpha: its history length"}

constexpr ImageSpec kImages[] = {
    {"gi.denoise.tiles", Resolution::Tile, kR16f, false, Visualize::Raw, "1 where a 16x16 tile has a surface"},
    BOUNCE_DENOISE_SIGNAL_IMAGES("diffuse"),
    BOUNCE_DENOISE_SIGNAL_IMAGES("specular"),
    {"gi.denoise.validation", Resolution::Full, kRgba16f, false, Visualize::Color,
     "the validation view: viewZ, normals, motion, specular virtual history; diffuse and specular history "
     "length, denoised light with disocclusions in red (captured frames only)",
     true},
};
#undef BOUNCE_DENOISE_SIGNAL_IMAGES
static_assert(std::size(kImages) == kDenoiseImageCount, "one table entry per DenoiseImage");

std::size_t imageOf(std::size_t signal, DenoiseImage image) { return image + kDenoisePerSignal * signal; }

}  // namespace

std::span<const ImageSpec> denoiseImageTable() { return kImages; }

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
  std::array<std::unique_ptr<Signal>, kDenoiseSignals> signals;
  std::unique_ptr<gpu::ComputePass> validation;  // made on the first captured frame
  explicit Passes(gpu::Context& context) : classifyTiles(context, denoiseClassifyTilesPass()) {
    for (std::size_t s = 0; s < kDenoiseSignals; ++s) signals[s] = std::make_unique<Signal>(context, kSignalNames[s]);
  }
};

Denoiser::Denoiser(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize, const Settings& settings)
    : context_(context),
      settings_(settings),
      images_(context, arena, kImages, maxSize),
      constants_(std::make_unique<gpu::Buffer>(context, "gi.denoise.constants", sizeof(shared::DenoiseConstants),
                                               gpu::BufferUsage::DeviceLocal, &arena)),
      passes_(std::make_unique<Passes>(context)) {}

Denoiser::~Denoiser() = default;

std::vector<gpu::PassDesc> Denoiser::passes() const {
  std::vector<gpu::PassDesc> all = {denoiseClassifyTilesPass()};
  for (const char* signal : kSignalNames)
    for (gpu::PassDesc desc : {denoisePrePass(signal), denoiseTemporalAccumulationPass(signal), denoiseHistoryFixPass(signal),
                               denoiseBlurPass(signal), denoisePostBlurPass(signal),
                               denoiseTemporalStabilizationPass(signal)})
      all.push_back(std::move(desc));
  all.push_back(denoiseValidationPass());
  return all;
}

gpu::Image& Denoiser::result(DenoiseSignal signal, std::uint64_t frameIndex) {
  return images_.current(imageOf(std::size_t(signal), kDenoiseStabilized), frameIndex);
}

gpu::Image& Denoiser::previousResult(DenoiseSignal signal, std::uint64_t frameIndex) {
  return images_.previous(imageOf(std::size_t(signal), kDenoiseStabilized), frameIndex);
}

void Denoiser::record(const FrameState& frame, const std::array<gpu::Image*, kDenoiseSignals>& noisy,
                      const std::array<bool, kDenoiseSignals>& checkerboarded) {
  gpu::Recorder& recorder = frame.recorder;
  const std::uint64_t f = frame.frameIndex;
  const DenoiseSettings& s = settings_.denoise;
  const Extent full = frame.renderSize;

  shared::DenoiseConstants c{};
  // REBLUR's hit-distance normalisation (A, B, C, D).
  c.hitDistanceParameters = glm::vec4(3.0f, 0.1f, 20.0f, -25.0f);
  for (std::size_t signal = 0; signal < kDenoiseSignals; ++signal) {
    if (noisy[signal]) c.signals |= 1u << signal;
    if (noisy[signal] && checkerboarded[signal]) c.checkerboard |= 1u << signal;
  }
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
  // Reprojection tolerances as the branches' temporal filters use them.
  c.depthTolerance = settings_.specular.temporalDepthTolerance;
  c.cosNormalTolerance = std::cos(glm::radians(settings_.specular.temporalNormalToleranceDegrees));
  c.disocclusionThreshold = s.disocclusionThreshold;
  c.hasHistory = frame.usableHistory ? 1u : 0u;
  c.frameIndex = std::uint32_t(f);
  c.antiFirefly = s.antiFirefly ? 1u : 0u;
  c.diffusePrePassRadius = s.diffusePrePassRadius * pixelScale;
  c.specularPrePassRadius = s.specularPrePassRadius * pixelScale;
  recorder.updateBuffer(*constants_, &c, sizeof c);
  const gpu::Bind constants("gIn_DenoiseConstants", *constants_);
  gpu::Image& tiles = images_.current(kDenoiseTiles, f);
  recorder.dispatch(passes_->classifyTiles, full.width, full.height, frame.group.binds(GroupPart::Depth),
                    {{"gOut_Tiles", tiles}});
  const gpu::Bind tilesBind("gIn_Tiles", tiles);
  const gpu::Bind motion("gIn_Motion", frame.engine[Input::Motion], frame.nearestSampler);

  for (std::size_t signal = 0; signal < kDenoiseSignals; ++signal) {
    if (!noisy[signal]) continue;
    Passes::Signal& p = *passes_->signals[signal];
    const auto image = [&](DenoiseImage which) -> gpu::Image& { return images_.current(imageOf(signal, which), f); };
    const auto previous = [&](DenoiseImage which) -> gpu::Image& {
      return images_.previous(imageOf(signal, which), f);
    };
    const DenoiseSignalParams atFullRadius{std::uint32_t(signal), 1.0f};
    const DenoiseSignalParams post{std::uint32_t(signal), s.postBlurRadiusScale};
    // The pre-pass's output takes the noisy signal's place in every later
    // pass; without a pre-pass, the noisy signal. A checkerboarded signal
    // always has one: it fills the pixels without a sample, even where it
    // blurs nothing (radius 0).
    const float prePassRadius = signal == 0 ? s.diffusePrePassRadius : s.specularPrePassRadius;
    const bool prePass = prePassRadius > 0.0f || checkerboarded[signal];
    if (prePass)
      recorder.dispatch(p.prePass, full.width, full.height, frame.group.binds(),
                        {constants, tilesBind, {"gIn_Signal", *noisy[signal]},
                         {"gOut_PrePassed", image(kDenoisePrePassed)}},
                        atFullRadius);
    const gpu::Bind input("gIn_Signal", prePass ? image(kDenoisePrePassed) : *noisy[signal]);
    recorder.dispatch(p.temporalAccumulation, full.width, full.height, frame.group.binds(),
                      {constants, tilesBind, motion, input,
                       {"gPrev_Surface", frame.previousSurface},
                       {"gPrev_Filtered", previous(kDenoiseHistory)},
                       {"gPrev_Moments", previous(kDenoiseMoments)},
                       {"gOut_Accumulated", image(kDenoiseAccumulated)},
                       {"gOut_Moments", image(kDenoiseMoments)},
                       {"gIn_Surface", frame.currentSurface}},
                      atFullRadius);
    recorder.dispatch(p.historyFix, full.width, full.height, frame.group.binds(),
                      {constants, tilesBind,
                       {"gIn_Accumulated", image(kDenoiseAccumulated)},
                       {"gOut_Fixed", image(kDenoiseFixed)}},
                      atFullRadius);
    recorder.dispatch(p.blur, full.width, full.height, frame.group.binds(),
                      {constants, tilesBind, input,
                       {"gIn_Filtered", image(kDenoiseFixed)},
                       {"gOut_Filtered", image(kDenoiseAccumulated)}},
                      atFullRadius);
    recorder.dispatch(p.postBlur, full.width, full.height, frame.group.binds(),
                      {constants, tilesBind, input,
                       {"gIn_Filtered", image(kDenoiseAccumulated)},
                       {"gOut_Filtered", image(kDenoiseHistory)}},
                      post);
    recorder.dispatch(p.temporalStabilization, full.width, full.height, frame.group.binds(),
                      {constants, tilesBind, motion,
                       {"gIn_Filtered", image(kDenoiseHistory)},
                       {"gPrev_Surface", frame.previousSurface},
                       {"gPrev_Stabilized", previous(kDenoiseStabilized)},
                       {"gOut_Stabilized", image(kDenoiseStabilized)},
                       {"gIn_Surface", frame.currentSurface}});
  }
  if (frame.capturing) recordValidation(frame, noisy);
}

void Denoiser::recordValidation(const FrameState& frame, const std::array<gpu::Image*, kDenoiseSignals>& noisy) {
  if (!passes_->validation) {
    passes_->validation = std::make_unique<gpu::ComputePass>(context_, denoiseValidationPass());
    images_.makeDebugImages();
  }
  const std::uint64_t f = frame.frameIndex;
  // A signal that is off shows black; its slot is filled with the other's image.
  const std::size_t diffuse = noisy[0] ? 0 : 1, specular = noisy[1] ? 1 : 0;
  frame.recorder.dispatch(
      *passes_->validation, frame.renderSize.width, frame.renderSize.height, frame.group.binds(),
      {{"gIn_DenoiseConstants", *constants_},
       {"gIn_Motion", frame.engine[Input::Motion], frame.nearestSampler},
       {"gIn_DiffuseAccumulated", images_.current(imageOf(diffuse, kDenoiseAccumulated), f)},
       {"gIn_SpecularAccumulated", images_.current(imageOf(specular, kDenoiseAccumulated), f)},
       {"gIn_SpecularMoments", images_.current(imageOf(specular, kDenoiseMoments), f)},
       {"gIn_Diffuse", images_.current(imageOf(diffuse, kDenoiseStabilized), f)},
       {"gIn_Specular", images_.current(imageOf(specular, kDenoiseStabilized), f)},
       {"gOut_Validation", images_.current(kDenoiseValidation, f)}});
}

}  // namespace bounce::gi
