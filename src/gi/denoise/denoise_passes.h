// The host declarations of the denoiser's passes (shaders/gi/denoise/,
// folder = stage, file = pass): each runs once per signal, named
// gi.denoise.SIGNAL.PASS (SIGNAL: the signal's name, "diffuse", "specular"
// or an engine's), except the tile classification, which all signals share,
// and the validation view.
#pragma once

#include <cstdint>
#include <string>

#include "gpu/pass.h"

namespace bounce::gi {

// Push constants of every per-signal pass (denoise_common.glsl's
// SignalParams): which signal, its kind and flags, and the blur's radius scale.
struct DenoiseSignalParams {
  std::uint32_t slot;   // the signal's index among the denoiser's
  std::uint32_t kind;   // gi::SignalKind: shared::kSignalKindDiffuse or kSignalKindSpecular
  std::uint32_t flags;  // shared::kSignalHasHistory, kSignalCheckerboard
  float radiusScale;
};
// The validation view's: which kinds' panels show a signal.
struct DenoiseValidationParams {
  std::uint32_t diffuseShown;
  std::uint32_t specularShown;
};

gpu::PassDesc denoiseClassifyTilesPass();
gpu::PassDesc denoisePrePass(const std::string& signal);
gpu::PassDesc denoiseTemporalAccumulationPass(const std::string& signal);
gpu::PassDesc denoiseHistoryFixPass(const std::string& signal);
// Blur and post-blur run the same shader (shaders/gi/denoise/blur.comp).
gpu::PassDesc denoiseBlurPass(const std::string& signal);
gpu::PassDesc denoisePostBlurPass(const std::string& signal);
gpu::PassDesc denoiseTemporalStabilizationPass(const std::string& signal);
// For --dump-stages (captured frames) only: the validation view.
gpu::PassDesc denoiseValidationPass();

}  // namespace bounce::gi
