// The diffuse branch's settings, gi.diffuse.*: its section of the settings table (gi/settings_table.h).
#include <array>

#include "gi/settings_table.h"

namespace bounce::gi::settings_table {
namespace {

constexpr std::array kEntries{
    Entry{"diffuse.enabled", inDiffuse(&DiffuseSettings::enabled), kNoBounds,
          "compute indirect diffuse at all (off: the frame has direct light only)"},
    Entry{"diffuse.screen_candidates", inDiffuse(&DiffuseSettings::screenCandidates), closed(0, 64),
          "initial candidates per pixel from random pixels of the previous composited frame"},
    Entry{"diffuse.bright_candidates", inDiffuse(&DiffuseSettings::brightCandidates), closed(0, 64),
          "initial candidates per pixel picked among the brightest pixels of the previous frame"},
    Entry{"diffuse.environment_candidates", inDiffuse(&DiffuseSettings::environmentCandidates), closed(0, 64),
          "initial candidates per pixel from uniform hemisphere directions into the environment (without a scene "
          "bridge; with one, ray candidates take their place)"},
    Entry{"diffuse.ray_candidates", inDiffuse(&DiffuseSettings::rayCandidates), closed(0, 64),
          "with a scene bridge: initial candidates per pixel from cosine-distributed rays, marched through the "
          "depth buffer, then traced through the bridge where the screen cannot decide"},
    Entry{"diffuse.ray_screen_steps", inDiffuse(&DiffuseSettings::rayScreenSteps), closed(0, 64),
          "with a scene bridge: depth-buffer march steps of a ray candidate before it continues through the bridge "
          "(0: straight to the bridge)"},
    Entry{"diffuse.bright_pixels", inDiffuse(&DiffuseSettings::brightPixels), closed(1, 4096),
          "the brightness reduction pyramid stops at about this many pixels to pick bright candidates from"},
    Entry{"diffuse.environment_mip", inDiffuse(&DiffuseSettings::environmentMip), closed(0, 16),
          "level of the prefiltered environment that environment samples read (higher: blurrier, less noise)"},
    Entry{"diffuse.target", inDiffuse(&DiffuseSettings::target), kNoBounds,
          "scalar weight of a sample's radiance in the target function (times the cosine)"},
    Entry{"diffuse.temporal_max_m", inDiffuse(&DiffuseSettings::temporalMaxM), closed(1, 1000),
          "temporal reuse: the history counts as at most this many frames of samples"},
    Entry{"diffuse.temporal_depth_tolerance", inDiffuse(&DiffuseSettings::temporalDepthTolerance), aboveUpTo(0, 1),
          "temporal reuse: reprojected depth may differ by this fraction of viewZ"},
    Entry{"diffuse.temporal_normal_tolerance_degrees", inDiffuse(&DiffuseSettings::temporalNormalToleranceDegrees),
          open(0, 180), "temporal reuse: reprojected normal may differ by this many degrees"},
    Entry{"diffuse.spatial_radius", inDiffuse(&DiffuseSettings::spatialRadius), closed(0, 256),
          "first spatial reuse pass: radius of the disk its neighbours are taken from, in half-resolution pixels"},
    Entry{"diffuse.spatial_samples", inDiffuse(&DiffuseSettings::spatialSamples), closed(0, 64),
          "first spatial reuse pass: neighbours merged per pixel"},
    Entry{"diffuse.spatial2_radius", inDiffuse(&DiffuseSettings::spatial2Radius), closed(0, 256),
          "second spatial reuse pass: radius of the disk its neighbours are taken from, in half-resolution pixels"},
    Entry{"diffuse.spatial2_samples", inDiffuse(&DiffuseSettings::spatial2Samples), closed(0, 64),
          "second spatial reuse pass: neighbours merged per pixel"},
    Entry{"diffuse.spatial_normal_tolerance_degrees", inDiffuse(&DiffuseSettings::spatialNormalToleranceDegrees),
          open(0, 180), "spatial reuse: neighbours whose normal differs by more degrees are rejected"},
    Entry{"diffuse.spatial_plane_tolerance", inDiffuse(&DiffuseSettings::spatialPlaneTolerance), aboveUpTo(0, 1),
          "spatial reuse: neighbours farther from the tangent plane than this fraction of viewZ are rejected"},
    Entry{"diffuse.jacobian", inDiffuse(&DiffuseSettings::jacobian), kNoBounds,
          "apply ReSTIR GI's reconnection Jacobian to reused samples"},
    Entry{"diffuse.spatial_feedback", inDiffuse(&DiffuseSettings::spatialFeedback), kNoBounds,
          "the next frame's temporal reuse starts from the spatially reused reservoirs (the Jitter gi pass's "
          "diffuse ReSTIR) instead of the temporal ones"},
    Entry{"diffuse.resolve_reservoirs", inDiffuse(&DiffuseSettings::resolveReservoirs), closed(1, 4),
          "resolve: neighbouring half-resolution reservoirs each full-resolution pixel evaluates"},
    Entry{"diffuse.visibility_steps", inDiffuse(&DiffuseSettings::visibilitySteps), closed(0, 256),
          "resolve: screen-space ray-march steps from the pixel to each sample (0: no visibility test)"},
    Entry{"diffuse.visibility", inDiffuse(&DiffuseSettings::visibility), kNoBounds,
          "resolve: how a sample's visibility is tested: screen (depth-buffer march), world (an any-hit ray through "
          "the scene bridge) or hybrid (the march, and a world ray where it cannot decide); without a bridge, screen"},
    Entry{"diffuse.per_pixel_visibility", inDiffuse(&DiffuseSettings::perPixelVisibility), kNoBounds,
          "resolve (hybrid visibility): each full-resolution pixel also marches to each sample; off: it trusts the "
          "sample-visibility world ray, which tested each reservoir's sample once from its own surface"},
    Entry{"diffuse.screen_visibility_per_reservoir", inDiffuse(&DiffuseSettings::screenVisibilityPerReservoir),
          kNoBounds,
          "resolve (screen visibility): each reservoir's sample is marched once from its own surface "
          "(gi.diffuse.sample_march) and its four pixels share the verdict; off: each pixel marches to each sample"},
    Entry{"diffuse.reuse_visibility", inDiffuse(&DiffuseSettings::reuseVisibility), kNoBounds,
          "temporal and spatial reuse test each reused sample's visibility with an any-hit ray through the scene "
          "bridge (unbiased reuse; without a bridge, ignored)"},
    Entry{"diffuse.sky_reuse_visibility", inDiffuse(&DiffuseSettings::skyReuseVisibility), kNoBounds,
          "spatial reuse counts a neighbour towards a sky sample's normalisation only if an any-hit ray finds the sky "
          "open from it (less darkening under windows and arches; costs rays; without a bridge, ignored)"},
    Entry{"diffuse.sky_reuse_rays", inDiffuse(&DiffuseSettings::skyReuseRays), closed(0, 64),
          "spatial reuse: neighbours per pass whose view of a sky sample is tested with a ray, at most (16: all); the "
          "others count with the tested ones' share that saw it, which brightens sky light"},
    Entry{"diffuse.visibility_thickness", inDiffuse(&DiffuseSettings::visibilityThickness), aboveUpTo(0, 1),
          "resolve: surfaces are assumed this fraction of their viewZ thick"},
    Entry{"diffuse.variance_clipping_gamma", inDiffuse(&DiffuseSettings::varianceClippingGamma), aboveUpTo(0, 100),
          "temporal filter: history is clamped to the pixel's fast history +- gamma * its temporal sigma"},
    Entry{"diffuse.temporal_filter_frames", inDiffuse(&DiffuseSettings::temporalFilterFrames), closed(1, 1024),
          "temporal filter: the longest history it accumulates, in frames"},
};

}  // namespace

std::span<const Entry> diffuseSection() { return kEntries; }

}  // namespace bounce::gi::settings_table
