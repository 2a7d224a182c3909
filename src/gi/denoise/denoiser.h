// The denoiser (docs/gi.md, "The denoiser"): NVIDIA's REBLUR as an analysis of its
// source walks through it, for any number of noisy signals of a frame, each of a
// kind its producer declares (gi::SignalKind: diffuse-like, or specular-like
// with roughness, hit distance and reflection motion). It sees the frame's
// surfaces (viewZ, normal, roughness), the motion vectors and last frame's
// surfaces, its own settings, and nothing of who made the signals. Its
// passes, each one dispatch for up to four signals (more are taken four at
// a time), every signal of the dispatch worked in turn by each invocation
// (temporal accumulation: a workgroup per signal):
//   gi.denoise.classify_tiles           16x16 tiles with a surface; the surfaces packed for the taps
//   gi.denoise.pre_pass                 checkerboard resolve; 8-tap pre-blur, radius from hit distance and lobe
//   gi.denoise.temporal_accumulation    Catmull-Rom surface-motion history (specular kind: + reflection
//                                       motion), history length, fast-history clamp, anti-lag
//   gi.denoise.history_fix              short histories rebuilt from a wide neighbourhood; anti-firefly
//   gi.denoise.blur                     8-tap disk, radius from history length, lobe and hit distance
//   gi.denoise.post_blur                the same at half the radius: next frame's history
//   gi.denoise.temporal_stabilization   a second, clamped history: the result
//   gi.denoise.validation               captured frames only: NRD-style validation view
// Each signal has its own images: two that live within a frame
// (pre_passed; accumulated, which holds temporal accumulation's output and
// then blur's), its history (one image: temporal accumulation reads last
// frame's, history fix writes this frame's rebuilt signal into it for
// blur, and post-blur writes next frame's), and two that need last
// frame's beside this frame's (moments, stabilized).
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bounce/gi.h"
#include "bounce/gi_settings.h"
#include "gi/unit.h"

namespace bounce::gi {

// The denoiser's images: the shared ones first (in this order), then per
// signal the kDenoisePerSignal of DenoiseSignalImage.
enum DenoiseImage : std::size_t {
  kDenoiseTiles,
  kDenoiseSurface,     // this frame's surfaces packed for the taps (viewZ, normal, roughness)
  kDenoiseEmptySlot,   // 1x1: fills the slots of a dispatch that no signal takes
  kDenoiseValidation,  // captured frames only
  kDenoiseSharedImages
};
enum DenoiseSignalImage : std::size_t {
  kDenoisePrePassed,    // the pre-pass's output, then last frame's stabilised signal (within the frame)
  kDenoiseAccumulated,  // temporal accumulation's output, then blur's (within the frame)
  kDenoiseHistory,      // last frame's history until temporal accumulation; then history fix's output; then
                        // post-blur's: next frame's history
  kDenoiseMoments,      // luminance moments (this frame's and last frame's)
  kDenoiseStabilized,   // the result, one copy: last frame's until post-blur has copied it
  kDenoisePerSignal
};

// The denoiser knows a signal as the public API declares one (SignalDesc:
// its name, which names its passes and images gi.denoise.NAME.*, and kind).

// The denoiser's image table for these signals (names of the signals' own
// images follow theirs).
void addDenoiseImages(ImageTableBuilder& table, std::span<const SignalDesc> signals);
// Its device memory at `maxSize` (images and constants), and what its
// transient images take of the context's transient pool.
std::uint64_t denoiserMemoryBytes(Extent maxSize, std::span<const SignalDesc> signals);
std::uint64_t denoiserTransientBytes(Extent maxSize, std::span<const SignalDesc> signals);

struct UnitRegistration;
// The denoiser as a unit (gi/units.h), made when gi.denoise.enabled: it
// takes SIGNAL.noisy of every signal some unit before it made this frame
// and makes SIGNAL, the denoised signal, in place of any earlier one.
UnitRegistration denoiseUnit();

class Denoiser final : public Unit {
 public:
  Denoiser(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize, const DenoiseSettings& settings,
           std::vector<SignalDesc> signals, gpu::MemoryArena* transientPool = nullptr);
  ~Denoiser() override;

  std::string_view name() const override { return "denoise"; }
  Plan plan(const FramePlan& frame) const override;
  void putHistory(Products& products, std::uint64_t frameIndex) override;
  void record(const FrameState& frame) override;
  std::vector<ImageSet*> imageSets() override { return {images_.get()}; }
  std::span<const SignalDesc> signals() const { return signals_; }

  // What a signal brings to a frame.
  struct SignalInput {
    // The noisy image (rgba16f: demodulated radiance, hit distance in
    // world units or 0); null: the signal is not denoised this frame.
    gpu::Image* noisy = nullptr;
    // The image holds samples only at the pixels of the kind's checkerboard
    // parity (shared/checkerboard.glsl; an engine's signal in
    // gi.denoise.checkerboard mode, unpacked by gi.engine_signal), which
    // the pre-pass fills in.
    bool checkerboarded = false;
    // Last frame's history of this signal may be reprojected (besides the
    // frame's own FrameState::usableHistory): false on the first frame a
    // signal is given after one without it.
    bool historyKept = true;
  };
  // Denoises each signal whose noisy image is given; `inputs`: one per signal.
  void record(const FrameState& frame, std::span<const SignalInput> inputs);
  // A signal's denoised result of this frame (rgba16f: radiance, history
  // length).
  gpu::Image& result(std::size_t signal, std::uint64_t frameIndex);
  // Every pass a denoiser of `signals` may record (gi/unit_catalog.h).
  static std::vector<gpu::PassDesc> passes(std::span<const SignalDesc> signals);

 private:
  struct Passes;
  std::size_t imageOf(std::size_t signal, DenoiseSignalImage image) const;
  // Records the stages for `batch` (up to kDenoiseSlots signals with an input).
  void recordBatch(const FrameState& frame, std::span<const SignalInput> inputs, std::span<const std::size_t> batch);
  void recordValidation(const FrameState& frame, std::span<const SignalInput> inputs);
  gpu::Context& context_;
  DenoiseSettings settings_;
  std::vector<SignalDesc> signals_;
  ImageTableBuilder table_;
  std::unique_ptr<ImageSet> images_;
  std::unique_ptr<gpu::Buffer> constants_;
  std::unique_ptr<Passes> passes_;
  std::vector<std::optional<std::uint64_t>>
      lastDenoised_;  // by signal: the last frame (history index) that denoised it
};

}  // namespace bounce::gi
