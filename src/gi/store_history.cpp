#include "gi/frame_constants.h"
#include "gi/frame_passes.h"
#include "gi/gi_shaders.h"
#include "gpu/format.h"

namespace bounce::gi {

gpu::PassDesc storeHistoryPass() {
  std::vector<gpu::ResourceDecl> resources = frameGroupDecls();
  resources.push_back({"gOut_Surface", gpu::Access::Write, gpu::formats::kRg32ui,
                       "this frame's viewZ, octahedral normal and material id, for the next"});
  // The engine's viewZ may be any format of its family and sampled only;
  // marches read this many times a pixel, and a storage image of the
  // library's own reads faster on GPUs than the engine's image through the
  // texture path (the resolve: 7 % on an H100).
  resources.push_back({"gOut_MarchDepth", gpu::Access::Write, gpu::formats::kR32f,
                       "this frame's viewZ, 0 where unusable, for visibility marches"});
  resources.push_back({"gIn_MaterialId", gpu::Access::Read, VK_FORMAT_UNDEFINED,
                       "the engine's material ids (any unsigned-integer format), when given",
                       gpu::ResourceKind::SampledImage});
  return {.name = "gi.store_history",
          .shader = "gi/store_history",
          .shaders = shaders(),
          .resources = std::move(resources),
          .constants = {frameConstantsLayout()}};
}

}  // namespace bounce::gi
