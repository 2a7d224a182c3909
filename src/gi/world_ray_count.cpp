// The names of the world-ray purposes (bounce/gi.h), kept in step with the
// shaders' counters (gi/world_ray_count.glsl).
#include "gi/world_ray_count.glsl"
#include "bounce/gi.h"

namespace bounce::gi {

static_assert(kWorldRayPurposeCount == shared::kWorldRayPurposes, "one counter per WorldRayPurpose");
static_assert(std::uint32_t(WorldRayPurpose::DiffuseCandidates) == shared::kWorldRaysDiffuseCandidates);
static_assert(std::uint32_t(WorldRayPurpose::SkyReuse) == shared::kWorldRaysSkyReuse);
static_assert(std::uint32_t(WorldRayPurpose::ReuseVisibility) == shared::kWorldRaysReuseVisibility);
static_assert(std::uint32_t(WorldRayPurpose::SampleVisibility) == shared::kWorldRaysSampleVisibility);
static_assert(std::uint32_t(WorldRayPurpose::ResolveVisibility) == shared::kWorldRaysResolveVisibility);
static_assert(std::uint32_t(WorldRayPurpose::Specular) == shared::kWorldRaysSpecular);
static_assert(std::uint32_t(WorldRayPurpose::CacheUpdate) == shared::kWorldRaysCacheUpdate);
static_assert(std::uint32_t(WorldRayPurpose::HitShadows) == shared::kWorldRaysHitShadows);

const char* worldRayPurposeName(WorldRayPurpose purpose) {
  switch (purpose) {
    case WorldRayPurpose::DiffuseCandidates:
      return "diffuse_candidates";
    case WorldRayPurpose::SkyReuse:
      return "sky_reuse";
    case WorldRayPurpose::ReuseVisibility:
      return "reuse_visibility";
    case WorldRayPurpose::SampleVisibility:
      return "sample_visibility";
    case WorldRayPurpose::ResolveVisibility:
      return "resolve_visibility";
    case WorldRayPurpose::Specular:
      return "specular";
    case WorldRayPurpose::CacheUpdate:
      return "cache_update";
    case WorldRayPurpose::HitShadows:
      return "hit_shadows";
    case WorldRayPurpose::Count:
      break;
  }
  return "unknown";
}

static_assert(kWorldRayPassCount == shared::kWorldRayPasses, "one counter set per pass that casts world rays");

const char* worldRayPassName(std::size_t pass) {
  switch (pass) {
    case shared::kWorldRayPassGather:
      return "gi.diffuse.gather";
    case shared::kWorldRayPassWorldCandidates:
      return "gi.diffuse.world_candidates";
    case shared::kWorldRayPassTemporalReuse:
      return "gi.diffuse.temporal_reuse";
    case shared::kWorldRayPassSpatialReuse:
      return "gi.diffuse.spatial_reuse";
    case shared::kWorldRayPassNeighbourVisibility:
      return "gi.diffuse.neighbour_visibility";
    case shared::kWorldRayPassSampleVisibility:
      return "gi.diffuse.sample_visibility";
    case shared::kWorldRayPassResolve:
      return "gi.diffuse.resolve";
    case shared::kWorldRayPassSpecularTrace:
      return "gi.specular.trace";
    case shared::kWorldRayPassSpecularWorldTrace:
      return "gi.specular.world_trace";
    case shared::kWorldRayPassCacheUpdate:
      return "gi.cache.update";
    default:
      break;
  }
  return "unknown";
}

std::uint64_t WorldRayCount::total() const {
  std::uint64_t sum = 0;
  for (std::uint64_t r : rays) sum += r;
  return sum;
}

}  // namespace bounce::gi
