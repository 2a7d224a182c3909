#include "gi/frame_constants.h"
#include "gi/frame_passes.h"
#include "gi/gi_shaders.h"
#include "gpu/format.h"

namespace bounce::gi {

gpu::PassDesc compositePass() {
  using gpu::Access;
  using gpu::ResourceKind;
  std::vector<gpu::ResourceDecl> resources = frameGroupDecls(GroupPart::Surfaces);
  resources.insert(
      resources.end(),
      {{"gIn_Direct", Access::Read, VK_FORMAT_UNDEFINED, "the engine's direct light (and emission), sky behind",
        ResourceKind::SampledImage},
       {"gIn_BaseColorMetallic", Access::Read, VK_FORMAT_UNDEFINED, "remodulation of indirect diffuse and specular",
        ResourceKind::SampledImage},
       {"gIn_Emissive", Access::Read, VK_FORMAT_UNDEFINED, "emission, when given apart", ResourceKind::SampledImage},
       // Sampled, so that any float format reads: the denoiser's results
       // are rgba16f, the branches' own filters' rgba32f.
       {"gIn_IndirectDiffuse", Access::Read, VK_FORMAT_UNDEFINED, "the diffuse signal's result",
        ResourceKind::SampledImage},
       {"gIn_IndirectSpecular", Access::Read, VK_FORMAT_UNDEFINED, "the specular signal's result",
        ResourceKind::SampledImage},
       {"gOut_Composite", Access::Write, gpu::formats::kRgba16f, "the frame, linear HDR; next frame's light source"}});
  return {.name = "gi.composite",
          .shader = "gi/composite",
          .shaders = shaders(),
          .resources = std::move(resources),
          .constants = {frameConstantsLayout()}};
}

}  // namespace bounce::gi
