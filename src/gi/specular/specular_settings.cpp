// The specular branch's settings, gi.specular.*: its section of the settings table (gi/settings_table.h).
#include <array>

#include "gi/settings_table.h"

namespace bounce::gi::settings_table {
namespace {

constexpr std::array kEntries{
    Entry{"specular.enabled", inSpecular(&SpecularSettings::enabled), kNoBounds,
          "compute indirect specular at all (off: metals and glossy surfaces reflect only direct light)"},
    Entry{"specular.sampling", inSpecular(&SpecularSettings::sampling), kNoBounds,
          "how each pixel's ray is drawn: vndf (GGX visible normals, target BRDF * cos * radiance) or uniform (a cone "
          "around the lobe's dominant direction, view-independent target = radiance, resampled with the BRDF at the "
          "resolve; Zyanide's uniform-lobe reservoirs)"},
    Entry{"specular.lobe_fraction", inSpecular(&SpecularSettings::lobeFraction), open(0, 1),
          "uniform sampling: the cone holds this fraction of the lobe's microfacet normals"},
    Entry{"specular.reuse_min_roughness", inSpecular(&SpecularSettings::reuseMinRoughness), closed(0, 1),
          "below this perceptual roughness no reservoir is reused in time or space: each pixel keeps its own ray"},
    Entry{"specular.diffuse_sample_roughness", inSpecular(&SpecularSettings::diffuseSampleRoughness), closed(0, 2),
          "at and above this perceptual roughness a pixel traces no ray: its fresh sample is the diffuse branch's "
          "final one at the same surface, weighed by its contribution weight (above 1: every pixel traces)"},
    Entry{"specular.cached_direct_roughness", inSpecular(&SpecularSettings::cachedDirectRoughness), closed(0, 2),
          "at and above this perceptual roughness the hits of a pixel's world ray take their direct light from the "
          "radiance cache where it knows it, instead of shadow rays (above 1: every hit casts its own)"},
    Entry{"specular.trace_steps", inSpecular(&SpecularSettings::traceSteps), closed(0, 512),
          "screen-space march steps of a ray through the depth buffer before it continues through the scene bridge (0: "
          "the "
          "bridge at once)"},
    Entry{"specular.trace_thickness", inSpecular(&SpecularSettings::traceThickness), aboveUpTo(0, 1),
          "trace: depth-buffer surfaces are assumed this fraction of their viewZ thick"},
    Entry{"specular.temporal_max_m", inSpecular(&SpecularSettings::temporalMaxM), closed(1, 1000),
          "temporal reuse: the history counts as at most this many frames of samples (short: reflections react fast)"},
    Entry{"specular.temporal_depth_tolerance", inSpecular(&SpecularSettings::temporalDepthTolerance), aboveUpTo(0, 1),
          "temporal reuse and filter: reprojected depth may differ by this fraction of viewZ"},
    Entry{"specular.temporal_normal_tolerance_degrees", inSpecular(&SpecularSettings::temporalNormalToleranceDegrees),
          open(0, 180), "temporal reuse and filter: reprojected normal may differ by this many degrees"},
    Entry{"specular.spatial_samples", inSpecular(&SpecularSettings::spatialSamples), closed(0, 16),
          "spatial reuse: neighbours merged per pixel"},
    Entry{"specular.spatial_max_radius", inSpecular(&SpecularSettings::spatialMaxRadius), closed(0, 256),
          "spatial reuse: the largest radius, in half-resolution pixels (the lobe's footprint at the hit sets it "
          "below that)"},
    Entry{"specular.spatial_normal_tolerance_degrees", inSpecular(&SpecularSettings::spatialNormalToleranceDegrees),
          open(0, 180), "spatial reuse: neighbours whose normal differs by more degrees are rejected"},
    Entry{"specular.spatial_plane_tolerance", inSpecular(&SpecularSettings::spatialPlaneTolerance), aboveUpTo(0, 1),
          "spatial reuse: neighbours farther from the tangent plane than this fraction of viewZ are rejected"},
    Entry{"specular.jacobian", inSpecular(&SpecularSettings::jacobian), kNoBounds,
          "apply ReSTIR GI's reconnection Jacobian to reused samples"},
    Entry{"specular.resolve_max_samples", inSpecular(&SpecularSettings::resolveMaxSamples), closed(1, 16),
          "resolve: reservoirs a pixel evaluates at resolve_full_roughness and above (one for a mirror)"},
    Entry{"specular.resolve_full_roughness", inSpecular(&SpecularSettings::resolveFullRoughness), aboveUpTo(0, 1),
          "resolve: the perceptual roughness at which a pixel evaluates resolve_max_samples reservoirs (linear from "
          "one at 0)"},
    Entry{"specular.resolve_max_radius", inSpecular(&SpecularSettings::resolveMaxRadius), closed(0, 64),
          "resolve: the largest radius neighbours are taken from, in full-resolution pixels (the lobe's footprint "
          "at the hit sets it below that)"},
    Entry{"specular.reprojection", inSpecular(&SpecularSettings::reprojection), kNoBounds,
          "temporal filter: history reprojected with the surface's motion, the reflection's (virtual) motion, or "
          "both blended by roughness and agreement with this frame"},
    Entry{"specular.variance_clipping_gamma", inSpecular(&SpecularSettings::varianceClippingGamma), aboveUpTo(0, 100),
          "temporal filter: history clamped to the fast history +- gamma * temporal sigma"},
    Entry{"specular.temporal_filter_frames", inSpecular(&SpecularSettings::temporalFilterFrames), closed(1, 1024),
          "temporal filter: the longest history, for rough surfaces (smooth ones keep fewer frames)"},
};

}  // namespace

std::span<const Entry> specularSection() { return kEntries; }

}  // namespace bounce::gi::settings_table
