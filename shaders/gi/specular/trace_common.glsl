// What gi.specular.trace and gi.specular.world_trace share: a ray's
// candidate from what it hits, and the pixel's fresh reservoir made from
// it. The including shader declares gPrev_Composite, gPrev_Surface,
// gIn_Environment and gOut_Reservoir0/1, and includes gi/previous_screen.glsl,
// the radiance cache, gi/scene_bridge.glsl and gi/world_rays.glsl first.
#ifndef BOUNCE_GI_SPECULAR_TRACE_COMMON_GLSL
#define BOUNCE_GI_SPECULAR_TRACE_COMMON_GLSL

void store(ivec2 halfPixel, Reservoir r) {
  uvec4 first, second;
  packReservoir(r, first, second);
  imageStore(gOut_Reservoir0, halfPixel, first);
  imageStore(gOut_Reservoir1, halfPixel, second);
}

// Last frame's radiance from the surface at (position, normal), if last
// frame showed it and what it showed is what the surface sends back along
// the ray (`direction`): last frame's camera saw it from elsewhere, and a
// glossy surface's light depends on the side it is seen from (a glint of
// the sun on polished metal seen by the camera would be reflected as if the
// metal sent it everywhere). Where the scene bridge cannot trace, what the
// screen shows is all there is and is taken whatever the side.
bool previousRadiance(vec3 position, vec3 normal, float roughness, vec3 direction, out vec3 radiance) {
  radiance = vec3(0.0f);
  if (gIn_SpecularConstants.specular.hasPreviousFrame == 0u) return false;
  vec3 seen = normalize(viewPosition(gIn_Frame.frame.previousView) - position);
  if (kSceneBridgeTraces && !reflectsAlikeTowards(seen, -direction, roughness)) return false;
  ivec2 shown = previousPixelShowing(position, normal);
  if (shown.x < 0) return false;
  radiance = sanitizeRadiance(imageLoad(gPrev_Composite, shown).xyz);
  return true;
}

// The candidate of a ray through the scene bridge from the start: its hit,
// lit by last frame's screen where that showed it alike, else by the bridge
// and the radiance cache (with `directFromCache`, the direct light too where
// the hit's cell knows it: no shadow ray); a true miss sees the sharp
// environment.
Reservoir worldCandidate(vec3 origin, vec3 direction, vec3 normal, bool directFromCache) {
  Reservoir candidate = emptyReservoir();
  candidate.flags = kReservoirHasSample;
  SceneHit hit = worldTraceClosest(origin, direction, kWorldRaysSpecular);
  if (hit.hit) {
    candidate.position = hit.position;
    candidate.normal = hit.normal;
    if (!previousRadiance(hit.position, hit.normal, hit.roughness, direction, candidate.radiance))
      candidate.radiance = offscreenHitRadiance(hit, direction, directFromCache);
  } else {
    candidate.position = direction;
    candidate.normal = normal;
    candidate.flags |= kReservoirEnvironment;
    candidate.radiance = sanitizeRadiance(environmentRadianceLod(gIn_Environment, direction, 0.0f));
  }
  return candidate;
}

// The fresh reservoir r (M = 1) with the ray's candidate, if it found one,
// weighed by the target of its sampling over its pdf; stored at halfPixel.
void storeCandidate(ivec2 halfPixel, Reservoir r, bool found, Reservoir candidate, GlossySurface s, float pdf) {
  if (found) {
    SpecularConstants c = gIn_SpecularConstants.specular;
    float target = specularTargetPdf(candidate, s, c.sampling, c.lobeFraction);
    reservoirStream(r, candidate.position, candidate.normal, candidate.radiance, candidate.flags, target / pdf, 0.0f,
                    0.0f);
    reservoirFinalize(r, target, 1.0f);
  }
  store(halfPixel, r);
}

#endif
