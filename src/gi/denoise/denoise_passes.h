// The host declarations of the denoiser's passes (shaders/gi/denoise/,
// folder = stage, file = pass), named gi.denoise.PASS: each stage is one
// dispatch for up to kDenoiseSlots signals (denoise_common.glsl), whose
// per-signal images it binds in slots NAME0..NAME3; the tile
// classification and the validation view see no signal's images.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "gpu/pass.h"

namespace bounce::gi {

// Push constants of every stage (denoise_common.glsl's SignalParams): per
// slot the signal's kind, flags and index; the slots in use; the blur's
// radius scale.
struct DenoiseSignalParams {
  std::array<std::uint32_t, 4> kinds;    // gi::SignalKind: shared::kSignalKindDiffuse or kSignalKindSpecular
  std::array<std::uint32_t, 4> flags;    // shared::kSignalHasHistory, kSignalCheckerboard
  std::array<std::uint32_t, 4> indices;  // the signal's index among the denoiser's
  std::uint32_t count;                   // slots in use
  float radiusScale;
};
// The validation view's: which kinds' panels show a signal.
struct DenoiseValidationParams {
  std::uint32_t diffuseShown;
  std::uint32_t specularShown;
};

// The name of slot `slot` of a per-signal binding: "gIn_Signal" 1 -> "gIn_Signal1".
std::string denoiseSlotName(std::string_view binding, std::size_t slot);

gpu::PassDesc denoiseClassifyTilesPass();
gpu::PassDesc denoisePrePass();
gpu::PassDesc denoiseTemporalAccumulationPass();
gpu::PassDesc denoiseHistoryFixPass();
// Blur and post-blur run the same shader (shaders/gi/denoise/blur.comp).
gpu::PassDesc denoiseBlurPass();
gpu::PassDesc denoisePostBlurPass();
gpu::PassDesc denoiseTemporalStabilizationPass();
// For --dump-stages (captured frames) only: the validation view.
gpu::PassDesc denoiseValidationPass();

}  // namespace bounce::gi
