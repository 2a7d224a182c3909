#include "gi/passes.h"

#include <vector>

#include "gpu/format.h"

namespace bounce::gi {
namespace {

using gpu::Access;
using gpu::ResourceDecl;
using gpu::ResourceKind;

using namespace gpu::formats;

ResourceDecl frameConstants() {
  return {"gIn_Frame", Access::Read, VK_FORMAT_UNDEFINED, "cameras, sizes, settings", ResourceKind::UniformBuffer};
}
ResourceDecl viewZ() { return {"gIn_ViewZ", Access::Read, kR32f, "positive view depth; 0 = background"}; }
ResourceDecl normalRoughness() {
  return {"gIn_NormalRoughness", Access::Read, kRgba16f, "world shading normal, roughness"};
}
ResourceDecl previousSurface() {
  return {"gPrev_Surface", Access::Read, kRg32ui, "last frame's viewZ and octahedral normal"};
}
// A reservoir image pair: rgba32ui each, 32 bytes a reservoir (shared/reservoir.glsl).
std::vector<ResourceDecl> reservoirs(const char* prefix, Access access, const char* purpose) {
  const std::string base = std::string(prefix) + "_Reservoir";
  return {{base + "0", access, kRgba32ui, std::string(purpose) + ": sample position, normal"},
          {base + "1", access, kRgba32ui, std::string(purpose) + ": radiance, M, W, flags"}};
}

gpu::PassDesc pass(const char* name, const char* shader, std::vector<ResourceDecl> resources,
                   std::uint32_t pushConstantSize = 0) {
  return {.name = name, .shader = shader, .resources = std::move(resources), .pushConstantSize = pushConstantSize};
}

std::vector<ResourceDecl> join(std::vector<ResourceDecl> a, const std::vector<ResourceDecl>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

gpu::PassDesc storeHistoryPass() {
  return pass("gi.store_history", "gi/store_history",
              {frameConstants(),
               viewZ(),
               normalRoughness(),
               {"gOut_Surface", Access::Write, kRg32ui, "this frame's viewZ and octahedral normal, for the next"}});
}

gpu::PassDesc brightPixelsPass() {
  return pass("gi.diffuse.bright_pixels", "gi/diffuse/bright_pixels",
              {frameConstants(),
               {"gPrev_Composite", Access::Read, kRgba16f, "last frame's composited radiance"},
               previousSurface(),
               {"gOut_Brightest", Access::Write, kRgba32f, "per 2x2 tile: brightness, pixel x, y, valid"}});
}

gpu::PassDesc brightPixelsReducePass() {
  return pass("gi.diffuse.bright_pixels_reduce", "gi/diffuse/bright_pixels_reduce",
              {{"gIn_Brightest", Access::Read, kRgba32f, "the level below"},
               {"gOut_Brightest", Access::Write, kRgba32f, "the brightest of each 2x2 of it"}});
}

gpu::PassDesc gatherPass() {
  return pass("gi.diffuse.gather", "gi/diffuse/gather",
              join({frameConstants(),
                    viewZ(),
                    normalRoughness(),
                    {"gPrev_Composite", Access::Read, kRgba16f, "radiance of screen candidates"},
                    previousSurface(),
                    {"gIn_Brightest", Access::Read, kRgba32f, "the bright-pixel pyramid's last level"},
                    {"gIn_Environment", Access::Read, VK_FORMAT_UNDEFINED, "prefiltered sky for environment candidates",
                     ResourceKind::SampledImage}},
                   reservoirs("gOut", Access::Write, "fresh reservoirs")));
}

gpu::PassDesc temporalReusePass() {
  return pass("gi.diffuse.temporal_reuse", "gi/diffuse/temporal_reuse",
              join(join({frameConstants(),
                         viewZ(),
                         normalRoughness(),
                         {"gIn_Motion", Access::Read, kRg16f, "pixels to last frame"},
                         previousSurface()},
                        reservoirs("gIn", Access::Read, "fresh reservoirs")),
                   join(reservoirs("gPrev", Access::Read, "last frame's final reservoirs"),
                        reservoirs("gOut", Access::Write, "merged reservoirs"))));
}

gpu::PassDesc spatialReusePass() {
  return pass("gi.diffuse.spatial_reuse", "gi/diffuse/spatial_reuse",
              join(join({frameConstants(), viewZ(), normalRoughness()}, reservoirs("gIn", Access::Read, "reservoirs")),
                   reservoirs("gOut", Access::Write, "reservoirs merged with neighbours")),
              sizeof(SpatialReuseParams));
}

gpu::PassDesc resolvePass() {
  return pass("gi.diffuse.resolve", "gi/diffuse/resolve",
              join(join({frameConstants(), viewZ(), normalRoughness()},
                        reservoirs("gIn", Access::Read, "this frame's final reservoirs")),
                   {{"gOut_Diffuse", Access::Write, kRgba16f, "indirect diffuse, demodulated, unfiltered"}}));
}

gpu::PassDesc temporalFilterPass() {
  return pass("gi.diffuse.temporal_filter", "gi/diffuse/temporal_filter",
              {frameConstants(),
               viewZ(),
               normalRoughness(),
               {"gIn_Motion", Access::Read, kRg16f, "pixels to last frame"},
               {"gIn_Diffuse", Access::Read, kRgba16f, "this frame's resolve"},
               previousSurface(),
               {"gPrev_Filtered", Access::Read, kRgba16f, "last frame's output (alpha: history length)"},
               {"gPrev_Moments", Access::Read, kRg32f, "last frame's luminance moments"},
               {"gOut_Filtered", Access::Write, kRgba16f, "indirect diffuse, filtered; alpha: history length"},
               {"gOut_Moments", Access::Write, kRg32f, "first and second moments of the luminance over the history"}});
}

gpu::PassDesc compositePass() {
  return pass("gi.composite", "gi/composite",
              {frameConstants(),
               viewZ(),
               {"gIn_Direct", Access::Read, kRgba16f, "direct light (and emission), sky behind"},
               {"gIn_BaseColorMetallic", Access::Read, kRgba8, "remodulation of indirect diffuse"},
               {"gIn_Emissive", Access::Read, kRgba16f, "emission, when given apart"},
               {"gIn_IndirectDiffuse", Access::Read, kRgba16f, "filtered indirect diffuse"},
               {"gOut_Composite", Access::Write, kRgba16f, "the frame, linear HDR; next frame's light source"}});
}

gpu::PassDesc reservoirViewPass(const std::string& after) {
  gpu::PassDesc desc =
      pass("gi.diffuse.reservoir_view", "gi/diffuse/reservoir_view",
           join(join({frameConstants(), viewZ(), normalRoughness()}, reservoirs("gIn", Access::Read, "reservoirs")),
                {{"gOut_Estimate", Access::Write, kRgba16f, "radiance * cos / pi * W at the reservoir's surface"},
                 {"gOut_M", Access::Write, kR32f, "confidence M"},
                 {"gOut_W", Access::Write, kR32f, "contribution weight W"}}));
  desc.name += "." + after;
  return desc;
}

}  // namespace bounce::gi
