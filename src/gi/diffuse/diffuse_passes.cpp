#include "gi/diffuse/diffuse_passes.h"

#include <vector>

#include "gi/cache/radiance_cache.h"
#include "gi/frame_constants.h"
#include "gi/gi_shaders.h"
#include "gi/light_change.h"
#include "gi/pass_decls.h"
#include "gi/screen_tiles.h"
#include "gpu/constants_layout.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

using gpu::Access;
using gpu::ResourceDecl;
using gpu::ResourceKind;
using shared::DiffuseConstants;

using namespace gpu::formats;

ResourceDecl diffuseConstants() {
  return {"gIn_DiffuseConstants", Access::Read, VK_FORMAT_UNDEFINED, "the diffuse settings",
          ResourceKind::UniformBuffer};
}
gpu::ConstantsDecl diffuseConstantsLayout() {
  return BOUNCE_CONSTANTS_LAYOUT(
      "gIn_DiffuseConstants", DiffuseConstants, brightLevelSize, brightLevel, screenCandidates, brightCandidates,
      environmentCandidates, targetFunction, resolveReservoirs, visibilitySteps, jacobian, temporalMaxM,
      temporalDepthTolerance, temporalCosNormalTolerance, environmentMip, spatialCosNormalTolerance,
      spatialPlaneTolerance, visibilityThickness, varianceClippingGamma, temporalFilterFrames, rayCandidates,
      rayScreenSteps, visibilityMode, reuseVisibility, skyReuseVisibility, skyReuseRays, perPixelVisibility);
}
// A pass of the branch: (part of) the frame group and the branch's
// constants first, then its own resources.
gpu::PassDesc pass(const char* name, const char* shader, GroupPart group, std::vector<ResourceDecl> own,
                   std::vector<gpu::ConstantsDecl> push = {}) {
  own.insert(own.begin(), diffuseConstants());
  gpu::PassDesc desc = framePass(name, shader, group, own);
  desc.constants.push_back(diffuseConstantsLayout());
  desc.constants.insert(desc.constants.end(), push.begin(), push.end());
  return desc;
}

}  // namespace

gpu::PassDesc brightPixelsPass() {
  return pass("gi.diffuse.bright_pixels", "gi/diffuse/bright_pixels", GroupPart::Constants,
              {{"gPrev_Composite", Access::Read, kRgba16f, "last frame's composited radiance"},
               previousSurfaceDecl(),
               {"gOut_Brightest", Access::Write, kRgba32f, "per 2x2 tile: brightness, pixel x, y, valid"}});
}

gpu::PassDesc brightPixelsReducePass() {
  // Reads no frame constants: only the pyramid, and how much of it this render size fills.
  return {.name = "gi.diffuse.bright_pixels_reduce",
          .shader = "gi/diffuse/bright_pixels_reduce",
          .shaders = shaders(),
          .resources = {{"gIn_Brightest", Access::Read, kRgba32f, "the level below"},
                        {"gOut_Brightest", Access::Write, kRgba32f, "the brightest of each 2x2 of it"}},
          .constants = {BOUNCE_CONSTANTS_LAYOUT("", BrightReduceParams, inputSize, outputSize)}};
}

gpu::PassDesc gatherPass() {
  gpu::PassDesc desc =
      pass("gi.diffuse.gather", "gi/diffuse/gather", GroupPart::Surfaces,
           joinDecls({{"gPrev_Composite", Access::Read, kRgba16f, "radiance of screen candidates"},
                 previousSurfaceDecl(),
                 {"gIn_Brightest", Access::Read, kRgba32f, "the bright-pixel pyramid's last level"},
                 {"gIn_Environment", Access::Read, VK_FORMAT_UNDEFINED,
                  "prefiltered sky for environment candidates and rays that miss", ResourceKind::SampledImage}},
                reservoirDecls("gOut", Access::Write, "fresh reservoirs")));
  desc.constants.push_back(cacheConstantsLayout());
  return desc;
}

std::vector<gpu::ResourceDecl> gatherRayResources() {
  std::vector<ResourceDecl> resources = {
      {"gIn_MarchDepth", Access::Read, kR32f, "the depth ray candidates march through"},
      {"gOut_PendingRays", Access::Write, VK_FORMAT_UNDEFINED,
       "per reservoir and ray candidate, the direction of a ray left to the world trace", ResourceKind::StorageBuffer},
      {"gOut_WorldQueue", Access::ReadWrite, VK_FORMAT_UNDEFINED, "the pixels with such rays",
       ResourceKind::StorageBuffer}};
  for (const ResourceDecl& d : screenTilesDecls()) resources.push_back(d);
  for (const ResourceDecl& d : cacheResources()) resources.push_back(d);
  return resources;
}

gpu::PassDesc worldCandidatesPass() {
  gpu::PassDesc desc = pass(
      "gi.diffuse.world_candidates", "gi/diffuse/world_candidates", GroupPart::Surfaces,
      {{"gPrev_Composite", Access::Read, kRgba16f, "radiance of hits last frame showed"},
       previousSurfaceDecl(),
       {"gIn_Brightest", Access::Read, kRgba32f, "the bright-pixel pyramid's last level (MIS weights)"},
       {"gIn_Environment", Access::Read, VK_FORMAT_UNDEFINED, "the sky rays that miss see", ResourceKind::SampledImage},
       {"gIn_PendingRays", Access::Read, VK_FORMAT_UNDEFINED, "the directions of the rays left by the gather",
        ResourceKind::StorageBuffer},
       {"gIn_WorldQueue", Access::Read, VK_FORMAT_UNDEFINED, "the pixels with such rays", ResourceKind::StorageBuffer},
       {"gInOut_Reservoir0", Access::ReadWrite, kRgba32ui, "the gather's reservoirs, finished here"},
       {"gInOut_Reservoir1", Access::ReadWrite, kRgba32ui, "(second half of the pair)"}});
  desc.constants.push_back(cacheConstantsLayout());
  return desc;
}

gpu::PassDesc temporalReusePass() {
  return pass(
      "gi.diffuse.temporal_reuse", "gi/diffuse/temporal_reuse", GroupPart::Surfaces,
      joinDecls(
          joinDecls({motionDecl(), previousSurfaceDecl()}, reservoirDecls("gIn", Access::Read, "fresh reservoirs")),
          joinDecls(reservoirDecls("gPrev", Access::Read, "last frame's final reservoirs"),
                    joinDecls(reservoirDecls("gOut", Access::Write, "merged reservoirs"),
                              {{"gPrev_Composite", Access::Read, kRgba16f,
                                "last frame's composited radiance: what reused samples on its screen send now"},
                               lightChangeDecl()}))));
}

gpu::ConstantsDecl spatialReuseParamsLayout() {
  return BOUNCE_CONSTANTS_LAYOUT("", SpatialReuseParams, radius, samples, passIndex, slotsPerPixel);
}

gpu::PassDesc spatialReusePass() {
  return pass("gi.diffuse.spatial_reuse", "gi/diffuse/spatial_reuse", GroupPart::Surfaces,
              joinDecls(reservoirDecls("gIn", Access::Read, "reservoirs"),
                        reservoirDecls("gOut", Access::Write, "reservoirs merged with neighbours")),
              {spatialReuseParamsLayout()});
}

std::vector<gpu::ResourceDecl> neighbourTestResources() {
  return {{"gOut_TestSummary", Access::Write, kRgba32f,
           "per pixel: tests queued, M untested, confidence if all see the sample, M found hidden (later)"},
          {"gOut_NeighbourTests", Access::Write, VK_FORMAT_UNDEFINED,
           "per pixel and test: the neighbour to ask whether it sees the chosen sample, and its M",
           ResourceKind::StorageBuffer},
          {"gOut_WorldQueue", Access::ReadWrite, VK_FORMAT_UNDEFINED, "the test slots queued",
           ResourceKind::StorageBuffer}};
}

gpu::PassDesc neighbourVisibilityPass() {
  return pass("gi.diffuse.neighbour_visibility", "gi/diffuse/neighbour_visibility", GroupPart::Surfaces,
              joinDecls(reservoirDecls("gIn", Access::Read, "the merged reservoirs, whose samples are tested"),
                        {{"gInOut_NeighbourTests", Access::ReadWrite, VK_FORMAT_UNDEFINED,
                          "the tests; a neighbour's M is negated where it does not see the sample",
                          ResourceKind::StorageBuffer},
                         {"gIn_WorldQueue", Access::Read, VK_FORMAT_UNDEFINED, "the test slots queued",
                          ResourceKind::StorageBuffer}}),
              {spatialReuseParamsLayout()});
}

gpu::PassDesc spatialNormalizePass() {
  // No diffuse constants: the summary, the tests and the reservoirs.
  gpu::PassDesc desc = framePass(
      "gi.diffuse.spatial_normalize", "gi/diffuse/spatial_normalize", GroupPart::Constants,
      {{"gIn_Reservoir0", Access::Read, kRgba32ui, "the merged reservoirs: sample position, normal"},
       {"gInOut_Reservoir1", Access::ReadWrite, kRgba32ui, "their radiance, M, W, flags: W and M corrected here"},
       {"gInOut_TestSummary", Access::ReadWrite, kRgba32f, "the merge's summary; w: the M found hidden"},
       {"gIn_NeighbourTests", Access::Read, VK_FORMAT_UNDEFINED, "the tests and their verdicts",
        ResourceKind::StorageBuffer}});
  desc.constants.push_back(spatialReuseParamsLayout());
  return desc;
}

gpu::PassDesc sampleVisibilityPass() {
  // No diffuse constants: the frame's surfaces, the reservoirs and the bridge.
  return framePass("gi.diffuse.sample_visibility", "gi/diffuse/sample_visibility", GroupPart::Surfaces,
                   {{"gIn_Reservoir0", Access::Read, kRgba32ui, "this frame's final reservoirs: sample position, normal"},
                    {"gInOut_Reservoir1", Access::ReadWrite, kRgba32ui,
                     "their radiance, M, W, flags; W = 0 where the sample is hidden from the reservoir's surface"}});
}

gpu::PassDesc sampleMarchPass() {
  return pass("gi.diffuse.sample_march", "gi/diffuse/sample_march", GroupPart::Surfaces,
              {{"gIn_Reservoir0", Access::Read, kRgba32ui, "this frame's final reservoirs: sample position, normal"},
               {"gInOut_Reservoir1", Access::ReadWrite, kRgba32ui,
                "their radiance, M, W, flags; W = 0 where the march finds the sample hidden from the reservoir's "
                "surface"},
               {"gIn_MarchDepth", Access::Read, kR32f, "the depth the march tests against"}});
}

gpu::PassDesc resolvePass() {
  return pass("gi.diffuse.resolve", "gi/diffuse/resolve", GroupPart::Surfaces,
              joinDecls(reservoirDecls("gIn", Access::Read, "this frame's final reservoirs"),
                   {{"gIn_MarchDepth", Access::Read, kR32f, "the depth the visibility marches test against"},
                    {"gOut_Diffuse", Access::Write, kRgba16f, "indirect diffuse, demodulated, unfiltered"}}));
}

gpu::PassDesc temporalFilterPass() {
  return pass("gi.diffuse.temporal_filter", "gi/diffuse/temporal_filter", GroupPart::Surfaces,
              {motionDecl(),
               {"gIn_Diffuse", Access::Read, kRgba16f, "this frame's resolve"},
               previousSurfaceDecl(),
               {"gPrev_Filtered", Access::Read, kRgba32f, "last frame's output (alpha: history length)"},
               {"gPrev_Moments", Access::Read, kRgba32f, "last frame's luminance moments"},
               {"gOut_Filtered", Access::Write, kRgba32f, "indirect diffuse, filtered; alpha: history length"},
               lightChangeDecl(),
               {"gOut_Moments", Access::Write, kRgba32f,
                "luminance moments: mean and deviation over the history, mean of the fast history"}});
}

gpu::PassDesc reservoirViewPass(const std::string& after) {
  // The view reads no diffuse constants: only the group and the reservoirs.
  return framePass("gi.diffuse.reservoir_view." + after, "gi/diffuse/reservoir_view", GroupPart::Surfaces,
                   joinDecls(reservoirDecls("gIn", Access::Read, "reservoirs"),
                        {{"gOut_Estimate", Access::Write, kRgba16f, "radiance * cos / pi * W at the reservoir's surface"},
                         {"gOut_M", Access::Write, kR32f, "confidence M"},
                         {"gOut_W", Access::Write, kR32f, "contribution weight W"}}));
}

}  // namespace bounce::gi
