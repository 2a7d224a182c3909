#include "gi/pass_decls.h"

#include "gi/gi_shaders.h"
#include "gpu/format.h"

namespace bounce::gi {

using gpu::Access;
using gpu::ResourceDecl;

ResourceDecl previousSurfaceDecl() {
  return {"gPrev_Surface", Access::Read, gpu::formats::kRg32ui,
          "last frame's viewZ, octahedral normal and material id"};
}

ResourceDecl currentSurfaceDecl() {
  return {"gIn_Surface", Access::Read, gpu::formats::kRg32ui,
          "this frame's viewZ, octahedral normal and material id (gi.store_history): its material ids"};
}

ResourceDecl motionDecl() {
  return {"gIn_Motion", Access::Read, VK_FORMAT_UNDEFINED, "the engine's motion vectors (times the motion scale)",
          gpu::ResourceKind::SampledImage};
}

std::vector<ResourceDecl> reservoirDecls(const char* prefix, Access access, const char* purpose) {
  const std::string base = std::string(prefix) + "_Reservoir";
  return {{base + "0", access, gpu::formats::kRgba32ui, std::string(purpose) + ": sample position, normal"},
          {base + "1", access, gpu::formats::kRgba32ui, std::string(purpose) + ": radiance, M, W, flags"}};
}

std::vector<ResourceDecl> joinDecls(std::vector<ResourceDecl> a, const std::vector<ResourceDecl>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

gpu::PassDesc framePass(std::string name, const char* shader, GroupPart group, const std::vector<ResourceDecl>& own) {
  std::vector<ResourceDecl> resources = frameGroupDecls(group);
  resources.insert(resources.end(), own.begin(), own.end());
  return {.name = std::move(name), .shader = shader, .shaders = shaders(), .resources = std::move(resources),
          .constants = {frameConstantsLayout()}};
}

}  // namespace bounce::gi
