// gi.engine_signal.SIGNAL: how an engine's own noisy signal reaches the
// denoiser (FrameInputs::noisyDiffuse, noisySpecular). The denoiser reads
// its input as a storage image in rgba16f, the format of the branches'
// resolved signals; an engine's image is sampled only and may be rgba32f,
// so one full-resolution pass copies it into an image of the library's,
// and drops non-finite values on the way (docs/gi.md, "Denoising an
// engine's own signals").
#include "gi/frame_passes.h"
#include "gi/pass_decls.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

constexpr ImageSpec kEngineSignalImages[] = {
    {"gi.engine_signal.diffuse", Resolution::Full, gpu::formats::kRgba16f, false, gpu::Visualize::Radiance,
     "the engine's noisy indirect diffuse as the denoiser reads it: demodulated radiance, hit distance"},
    {"gi.engine_signal.specular", Resolution::Full, gpu::formats::kRgba16f, false, gpu::Visualize::Radiance,
     "the engine's noisy indirect specular as the denoiser reads it: demodulated radiance, hit distance"},
};

}  // namespace

std::span<const ImageSpec> engineSignalImageTable() { return kEngineSignalImages; }

gpu::PassDesc engineSignalPass(const std::string& signal) {
  return framePass("gi.engine_signal." + signal, "gi/engine_signal", GroupPart::Constants,
                   {{"gIn_Noisy", gpu::Access::Read, VK_FORMAT_UNDEFINED,
                     "the engine's noisy signal: demodulated radiance, hit distance (world units, 0 unknown)",
                     gpu::ResourceKind::SampledImage},
                    {"gOut_Signal", gpu::Access::Write, gpu::formats::kRgba16f,
                     "the same, finite: what the denoiser reads"}});
}

}  // namespace bounce::gi
