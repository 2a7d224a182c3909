#include "gi/frame_constants.h"
#include "gi/frame_passes.h"
#include "gi/gi_shaders.h"
#include "gpu/format.h"

namespace bounce::gi {

gpu::PassDesc storeHistoryPass() {
  std::vector<gpu::ResourceDecl> resources = frameGroupDecls();
  resources.push_back({"gOut_Surface", gpu::Access::Write, gpu::formats::kRg32ui,
                       "this frame's viewZ and octahedral normal, for the next"});
  return {.name = "gi.store_history",
          .shader = "gi/store_history",
          .shaders = shaders(),
          .resources = std::move(resources),
          .constants = {frameConstantsLayout()}};
}

}  // namespace bounce::gi
