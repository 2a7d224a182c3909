// The denoiser (docs/gi.md, "The denoiser"): NVIDIA's REBLUR as seed 004
// walks through it, for any number of noisy signals of a frame (here the
// diffuse and specular branches' resolved, demodulated light). It sees the
// frame's surfaces (viewZ, normal, roughness), the motion vectors and last
// frame's surfaces, and nothing of the branches. Its passes, per signal:
//   gi.denoise.classify_tiles                   16x16 tiles with a surface (both signals)
//   gi.denoise.SIGNAL.pre_pass                 checkerboard resolve; 8-tap pre-blur, radius from hit distance
//                                              and lobe
//   gi.denoise.SIGNAL.temporal_accumulation    Catmull-Rom surface-motion history (specular: + reflection
//                                              motion), history length, fast-history clamp, anti-lag
//   gi.denoise.SIGNAL.history_fix              short histories rebuilt from a wide neighbourhood; anti-firefly
//   gi.denoise.SIGNAL.blur                     8-tap disk, radius from history length, lobe and hit distance
//   gi.denoise.SIGNAL.post_blur                the same at half the radius: next frame's history
//   gi.denoise.SIGNAL.temporal_stabilization   a second, clamped history: the result
//   gi.denoise.validation                      captured frames only: NRD-style validation view
#pragma once

#include <array>
#include <memory>
#include <span>

#include "bounce/gi_settings.h"
#include "gi/branch.h"

namespace bounce::gi {

// The two signals the library denoises (shared::kSignalDiffuse, kSignalSpecular).
enum class DenoiseSignal : std::uint32_t { Diffuse = 0, Specular = 1 };
constexpr std::size_t kDenoiseSignals = 2;

// The denoiser's images, in the order of denoiseImageTable(): the tiles,
// then per signal (diffuse first) the same six.
enum DenoiseImage : std::size_t {
  kDenoiseTiles,
  kDenoisePrePassed,    // + kDenoisePerSignal * signal
  kDenoiseAccumulated,  // also blur's output
  kDenoiseMoments,
  kDenoiseFixed,
  kDenoiseHistory,      // post-blur's output, next frame's history
  kDenoiseStabilized,   // the result
  kDenoisePerSignal = kDenoiseStabilized,  // images per signal
  kDenoiseValidation = 1 + kDenoisePerSignal * kDenoiseSignals,  // captured frames only
  kDenoiseImageCount
};
std::span<const ImageSpec> denoiseImageTable();

class Denoiser {
 public:
  Denoiser(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize, const Settings& settings);
  ~Denoiser();

  ImageSet& images() { return images_; }
  // Denoises each signal whose noisy image is given (rgba16f: demodulated
  // radiance, hit distance in world units or 0): `noisy[signal]`, null for
  // a signal that is off. `checkerboarded[signal]`: the image holds samples
  // only at the pixels of the signal's checkerboard parity
  // (shared/checkerboard.glsl; an engine's signal in gi.denoise.checkerboard
  // mode, unpacked by gi.engine_signal), which the pre-pass fills in.
  void record(const FrameState& frame, const std::array<gpu::Image*, kDenoiseSignals>& noisy,
              const std::array<bool, kDenoiseSignals>& checkerboarded);
  // This frame's denoised signal (rgba32f: radiance, history length).
  gpu::Image& result(DenoiseSignal signal, std::uint64_t frameIndex);
  gpu::Image& previousResult(DenoiseSignal signal, std::uint64_t frameIndex);
  std::vector<gpu::PassDesc> passes() const;

 private:
  struct Passes;
  void recordValidation(const FrameState& frame, const std::array<gpu::Image*, kDenoiseSignals>& noisy);
  gpu::Context& context_;
  Settings settings_;
  ImageSet images_;
  std::unique_ptr<gpu::Buffer> constants_;
  std::unique_ptr<Passes> passes_;
};

}  // namespace bounce::gi
