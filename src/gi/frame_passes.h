// The passes GiContext records around the branches, and the images they
// keep: gi.store_history (this frame's depth and normals, for the next
// frame, and the depth the visibility marches read) before them, gi.composite (the frame) after them;
// gi.engine_signal.SIGNAL (an engine's own noisy signal taken in for the
// denoiser, in place of a branch) when the engine gives one.
// Shaders: shaders/gi/store_history.comp, shaders/gi/composite.comp, shaders/gi/engine_signal.comp.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "bounce/gi.h"
#include "gi/image_table.h"
#include "gpu/pass.h"

namespace bounce::gi {

// The library's own signals, SignalId kDiffuseSignal and kSpecularSignal:
// what its branches make (or an engine gives in their place), before any of
// ContextDesc::signals.
inline const SignalDesc kLibrarySignals[] = {{"diffuse", SignalKind::Diffuse}, {"specular", SignalKind::Specular}};

gpu::PassDesc storeHistoryPass();
gpu::PassDesc compositePass();

// The frame's own images: the history unit's (gi.history_surface,
// gi.march_depth), then the composite's (gi.composite).
std::span<const ImageSpec> frameImageTable();
std::span<const ImageSpec> historyImageTable();
std::span<const ImageSpec> compositeImageTable();

struct UnitRegistration;
// The units of these passes (gi/units.h): gi.store_history, first of a
// frame; gi.engine_signal.SIGNAL for the signals the engine gives, before
// the denoiser; gi.composite, last.
UnitRegistration historyUnit();
UnitRegistration engineSignalUnit();
UnitRegistration compositeUnit();

// `signal` ("diffuse", "specular", an engine's): gi.engine_signal.SIGNAL,
// the engine's noisy signal (FrameInputs::noisy) into the
// library's rgba16f image of it, non-finite values dropped; in
// checkerboard mode unpacked to full width, the pixels without a sample
// marked (shaders/gi/engine_signal.comp).
gpu::PassDesc engineSignalPass(const std::string& signal);
// Its push constants.
struct EngineSignalParams {
  std::uint32_t checkerboard;  // 1: gi.denoise.checkerboard, the engine's image is packed to half width
  std::uint32_t dataParity;    // shared::kCheckerboardDiffuseParity or kCheckerboardSpecularParity (by kind)
};
// The image signal `signal`'s engine signal is taken into
// (gi.engine_signal.SIGNAL); made for every signal on the first frame that
// gives one.
void addEngineSignalImage(ImageTableBuilder& table, const std::string& signal);

}  // namespace bounce::gi
