#include "gi/specular/specular_passes.h"

#include <vector>

#include "gi/cache/radiance_cache.h"
#include "gi/depth_pyramid.h"
#include "gi/light_change.h"
#include "gi/pass_decls.h"
#include "gi/screen_tiles.h"
#include "gi/specular/specular_common.glsl"
#include "gpu/constants_layout.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

using gpu::Access;
using gpu::ResourceDecl;
using gpu::ResourceKind;
using shared::SpecularConstants;

using namespace gpu::formats;

ResourceDecl specularConstants() {
  return {"gIn_SpecularConstants", Access::Read, VK_FORMAT_UNDEFINED, "the specular settings",
          ResourceKind::UniformBuffer};
}

gpu::ConstantsDecl specularConstantsLayout() {
  return BOUNCE_CONSTANTS_LAYOUT("gIn_SpecularConstants", SpecularConstants, sampling, lobeFraction,
                                 reuseMinRoughness, traceSteps, traceThickness, temporalMaxM, temporalDepthTolerance,
                                 temporalCosNormalTolerance, spatialSamples, spatialMaxRadius,
                                 spatialCosNormalTolerance, spatialPlaneTolerance, jacobian, resolveMaxSamples,
                                 resolveFullRoughness, resolveMaxRadius, reprojection, varianceClippingGamma,
                                 temporalFilterFrames, environmentLevels, hasPreviousFrame,
                                 diffuseSampleRoughness, cachedDirectRoughness);
}

ResourceDecl baseColorMetallic() {
  return {"gIn_BaseColorMetallic", Access::Read, VK_FORMAT_UNDEFINED,
          "the engine's base colour and metallic: the specular reflectance F0", ResourceKind::SampledImage};
}

// A pass of the branch: the frame's surfaces, the branch's constants and
// the engine's material first (every pass but the filter weighs samples
// with the BRDF), then its own resources.
gpu::PassDesc pass(const char* name, const char* shader, std::vector<ResourceDecl> own, bool material = true) {
  std::vector<ResourceDecl> resources = {specularConstants()};
  if (material) resources.push_back(baseColorMetallic());
  resources.insert(resources.end(), own.begin(), own.end());
  gpu::PassDesc desc = framePass(name, shader, GroupPart::Surfaces, resources);
  desc.constants.push_back(specularConstantsLayout());
  return desc;
}

}  // namespace

gpu::PassDesc specularTracePass() {
  gpu::PassDesc desc =
      pass("gi.specular.trace", "gi/specular/trace",
           joinDecls({{"gPrev_Composite", Access::Read, kRgba16f, "last frame's composite: what screen hits send"},
                      previousSurfaceDecl(),
                      {"gIn_Environment", Access::Read, VK_FORMAT_UNDEFINED,
                       "prefiltered sky for rays that miss", ResourceKind::SampledImage}},
                     joinDecls(reservoirDecls("gOut", Access::Write, "fresh reservoirs (hit point, its radiance)"),
                               joinDecls(depthPyramidDecls(),
                                         reservoirDecls("gIn_Diffuse", Access::Read,
                                                        "the diffuse branch's final reservoirs: rough pixels' "
                                                        "samples (gi.specular.diffuse_sample_roughness)")))));
  desc.constants.push_back(cacheConstantsLayout());
  return desc;
}

std::vector<gpu::ResourceDecl> specularTraceRayResources() {
  // With a bridge that traces, the rays screen space cannot finish wait in
  // a queue for gi.specular.world_trace (without one the trace writes
  // neither, and reads screen-only mode's answers for them instead).
  return joinDecls(
      joinDecls(cacheResources(), {{"gOut_PendingRay", Access::Write, kRgba32f, "each queued ray's direction and pdf"},
                                   {"gOut_WorldQueue", Access::ReadWrite, VK_FORMAT_UNDEFINED,
                                    "the pixels whose ray goes on through the bridge", ResourceKind::StorageBuffer}}),
      screenTilesDecls());
}

gpu::PassDesc specularWorldTracePass() {
  gpu::PassDesc desc =
      pass("gi.specular.world_trace", "gi/specular/world_trace",
           joinDecls({{"gPrev_Composite", Access::Read, kRgba16f, "last frame's composite: what hits it showed send"},
                      previousSurfaceDecl(),
                      {"gIn_Environment", Access::Read, VK_FORMAT_UNDEFINED, "the sky rays that miss see",
                       ResourceKind::SampledImage},
                      {"gIn_PendingRay", Access::Read, kRgba32f, "each queued ray's direction and pdf"},
                      {"gIn_WorldQueue", Access::Read, VK_FORMAT_UNDEFINED, "the pixels whose ray goes on",
                       ResourceKind::StorageBuffer}},
                     reservoirDecls("gOut", Access::Write, "the queued pixels' fresh reservoirs")));
  desc.constants.push_back(cacheConstantsLayout());
  return desc;
}

gpu::PassDesc specularTemporalReusePass() {
  return pass(
      "gi.specular.temporal_reuse", "gi/specular/temporal_reuse",
      joinDecls(
          joinDecls({motionDecl(), previousSurfaceDecl()}, reservoirDecls("gIn", Access::Read, "fresh reservoirs")),
          joinDecls(reservoirDecls("gPrev", Access::Read, "last frame's temporal reservoirs"),
                    joinDecls(reservoirDecls("gOut", Access::Write, "merged reservoirs, next frame's history"),
                              {{"gPrev_Composite", Access::Read, kRgba16f,
                                "last frame's composite: what reused samples on its screen send now"},
                               lightChangeDecl()}))));
}

gpu::PassDesc specularSpatialReusePass() {
  return pass("gi.specular.spatial_reuse", "gi/specular/spatial_reuse",
              joinDecls(reservoirDecls("gIn", Access::Read, "temporal reservoirs"),
                        reservoirDecls("gOut", Access::Write, "reservoirs merged with neighbours in the lobe's footprint")));
}

gpu::PassDesc specularResolvePass() {
  return pass("gi.specular.resolve", "gi/specular/resolve",
              joinDecls(reservoirDecls("gIn", Access::Read, "this frame's final reservoirs"),
                        {{"gOut_Specular", Access::Write, kRgba16f,
                          "indirect specular, demodulated, unfiltered; alpha: hit distance"}}));
}

gpu::PassDesc specularTemporalFilterPass() {
  return pass("gi.specular.temporal_filter", "gi/specular/temporal_filter",
              {motionDecl(),
               {"gIn_Specular", Access::Read, kRgba16f, "this frame's resolve (alpha: hit distance)"},
               previousSurfaceDecl(),
               {"gPrev_Filtered", Access::Read, kRgba32f, "last frame's output (alpha: history length)"},
               {"gPrev_Moments", Access::Read, kRgba32f, "last frame's luminance moments"},
               {"gOut_Filtered", Access::Write, kRgba32f, "indirect specular, filtered; alpha: history length"},
               lightChangeDecl(),
               {"gOut_Moments", Access::Write, kRgba32f,
                "luminance moments: mean and deviation over the history, mean of the fast history"},
               {"gOut_Reprojection", Access::Write, kRgba16f,
                "which history was used: surface weight, virtual weight, history length / the longest"}},
              false);
}

gpu::PassDesc specularValidationPass() {
  return framePass("gi.specular.validation", "gi/specular/validation", GroupPart::Surfaces,
                   joinDecls(reservoirDecls("gIn", Access::Read, "this frame's final reservoirs"),
                             {{"gOut_M", Access::Write, kR32f, "confidence M"},
                              {"gOut_HitDistance", Access::Write, kR32f,
                               "distance to the sample's hit (the environment: 10^4)"}}));
}

}  // namespace bounce::gi
