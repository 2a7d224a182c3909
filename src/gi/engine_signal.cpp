// gi.engine_signal.SIGNAL: how an engine's own noisy signal reaches the
// denoiser (FrameInputs::noisy). The denoiser reads
// its input as a storage image in rgba16f, the format of the branches'
// resolved signals; an engine's image is sampled only and may be rgba32f,
// so one full-resolution pass copies it into an image of the library's,
// and drops non-finite values on the way (docs/gi.md, "Denoising an
// engine's own signals"). In checkerboard mode (gi.denoise.checkerboard)
// the engine's image is half as wide: the same pass unpacks it, marking the
// pixels without a sample for the denoiser's pre-pass to fill.
#include "gi/frame_passes.h"
#include "gi/pass_decls.h"
#include "gpu/constants_layout.h"
#include "gpu/format.h"

namespace bounce::gi {
void addEngineSignalImage(ImageTableBuilder& table, const std::string& signal) {
  table.add("gi.engine_signal." + signal,
            {"", Resolution::Full, gpu::formats::kRgba16f, false, gpu::Visualize::Radiance,
             "the engine's noisy signal as the denoiser reads it: demodulated radiance, hit distance (-1: no "
             "sample, checkerboard mode)"});
}

gpu::PassDesc engineSignalPass(const std::string& signal) {
  gpu::PassDesc desc = framePass(
      "gi.engine_signal." + signal, "gi/engine_signal", GroupPart::Constants,
      {{"gIn_Noisy", gpu::Access::Read, VK_FORMAT_UNDEFINED,
        "the engine's noisy signal: demodulated radiance, hit distance (world units, 0 unknown); in checkerboard "
        "mode half as wide, the pixels with a sample packed",
        gpu::ResourceKind::SampledImage},
       {"gOut_Signal", gpu::Access::Write, gpu::formats::kRgba16f,
        "the same, finite, full width: what the denoiser reads (checkerboard: hit distance -1 where no sample)"}});
  desc.constants.push_back(BOUNCE_CONSTANTS_LAYOUT("", EngineSignalParams, checkerboard, dataParity));
  return desc;
}

}  // namespace bounce::gi
