// The host declarations of the denoiser's passes (shaders/gi/denoise/,
// folder = stage, file = pass): each runs once per signal, named
// gi.denoise.SIGNAL.PASS (SIGNAL: diffuse or specular), except the tile
// classification, which both signals share.
#pragma once

#include <cstdint>
#include <string>

#include "gpu/pass.h"

namespace bounce::gi {

// Push constants of every per-signal pass: which signal (its weights and
// radii) and the blur's radius scale.
struct DenoiseSignalParams {
  std::uint32_t signal;  // shared::kSignalDiffuse (0) or kSignalSpecular (1)
  float radiusScale;
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
