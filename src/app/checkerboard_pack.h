// bounce denoise --checkerboard: the engine's side of the denoiser's
// checkerboard mode (gi.denoise.checkerboard, docs/gi.md "Checkerboard
// input"). Each frame, of the path tracer's full-resolution noisy diffuse
// and specular, the pixels each signal's checkerboard parity keeps, packed
// into images half as wide: what the library takes in that mode.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"

namespace bounce::app {

class CheckerboardPacker {
 public:
  // Signals: 0 diffuse, 1 specular (their parities differ).
  static constexpr std::size_t kSignals = 2;
  CheckerboardPacker(gpu::Context& context, std::uint32_t width, std::uint32_t height);
  ~CheckerboardPacker();

  // Records the packing of `full` (rgba32f, width x height) for the frame
  // handed over as FrameInputs::frameIndex `frameIndex`.
  void record(gpu::Recorder& recorder, std::size_t signal, gpu::Image& full, std::uint64_t frameIndex);
  // The packed image (rgba32f, ceil(width / 2) x height).
  gpu::Image& packed(std::size_t signal) { return *packed_[signal]; }

 private:
  std::uint32_t width_, height_;
  std::array<std::unique_ptr<gpu::Image>, kSignals> packed_;
  std::array<std::unique_ptr<gpu::ComputePass>, kSignals> passes_;
};

}  // namespace bounce::app
