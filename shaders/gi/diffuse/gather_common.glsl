// What gi.diffuse.gather and gi.diffuse.world_candidates share: the
// candidates' densities (the weights of gather.comp's header) and the
// streaming of a ray candidate once it is known what the ray met. The
// including shader declares gPrev_Composite, gPrev_Surface and
// gIn_Brightest and includes gi/diffuse/previous_screen.glsl first.
#ifndef BOUNCE_GI_DIFFUSE_GATHER_COMMON_GLSL
#define BOUNCE_GI_DIFFUSE_GATHER_COMMON_GLSL

const float kMaxFootprintStretch = 5.0f;

// A candidate point on last frame's surfaces: the surface at `pixel`, the
// radiance it sent, and its area density relative to one uniformly chosen
// pixel (p-hat / (count * this * distance^2 / cos) is its weight).
struct ScreenPoint {
  bool valid;
  vec3 position;
  vec3 normal;
  vec3 radiance;
  float areaPdf;  // per unit area, for one uniformly random pixel
};

ScreenPoint screenPoint(ivec2 pixel) {
  ScreenPoint point;
  point.valid = false;
  Surface surface = historySurfaceAt(pixel, imageLoad(gPrev_Surface, pixel).xy);
  if (surface.viewZ <= 0.0f) return point;
  ScreenView view = gIn_Frame.frame.previousView;
  vec3 toSurface = normalize(surface.position - viewPosition(view));
  vec3 forward = -vec3(view.viewToWorld[2].x, view.viewToWorld[2].y, view.viewToWorld[2].z);
  // Seen at grazing angles a pixel covers a large area, rarely sampled and
  // then weighted heavily; counting it as no more than kMaxFootprintStretch
  // head-on pixels bounds those weights (light from surfaces the camera sees
  // almost edge-on is slightly undercounted).
  float footprint = pixelFootprintArea(view, surface.viewZ, dot(toSurface, forward),
                                       max(abs(dot(surface.normal, toSurface)), 1.0f / kMaxFootprintStretch), fullSize());
  point.valid = true;
  point.position = surface.position;
  point.normal = surface.normal;
  point.radiance = sanitizeRadiance(imageLoad(gPrev_Composite, pixel).xyz);
  point.areaPdf = 1.0f / (fullSize().x * fullSize().y * footprint);
  return point;
}

// Area density to solid angle at x; 0 where the point cannot light x. The
// distance is taken as at least minimumDistance: the inverse-square
// singularity of area sampling would otherwise make points right next to x
// (in creases) rare fireflies, which the feedback through the composite
// would spread; light from the nearest millimetres is slightly undercounted.
float toSolidAngle(float areaPdf, vec3 pointPosition, vec3 pointNormal, vec3 x, float minimumDistance) {
  vec3 d = x - pointPosition;
  float distance2 = dot(d, d);
  float cosine = dot(pointNormal, d) * inversesqrt(max(distance2, 1e-20f));
  return cosine > 0.0f ? areaPdf * max(distance2, minimumDistance * minimumDistance) / cosine : 0.0f;
}

// The point techniques' share of a point's density at x: screen candidates,
// and bright candidates where the pixel is on the list (`listed`).
float pointTechniques(float screenPdf, bool listed) {
  DiffuseConstants d = gIn_DiffuseConstants.diffuse;
  ivec2 brightSize = ivec2(d.brightLevelSize);
  float brightPerScreen = fullSize().x * fullSize().y / float(brightSize.x * brightSize.y);
  return float(d.screenCandidates) * screenPdf +
         (listed ? float(d.brightCandidates) * screenPdf * brightPerScreen : 0.0f);
}

// Whether `source` is the pixel the bright list holds for its tile.
bool listedBright(ivec2 source) {
  DiffuseConstants d = gIn_DiffuseConstants.diffuse;
  if (d.brightCandidates == 0u) return false;
  ivec2 brightSize = ivec2(d.brightLevelSize);
  vec4 entry = imageLoad(gIn_Brightest, min(source >> int(d.brightLevel), brightSize - 1));
  return entry.w > 0.0f && ivec2(entry.yz) == source;
}

// The density of ray candidates at direction `direction` from x, per unit solid angle.
float rayTechnique(vec3 normal, vec3 direction) {
  return float(gIn_DiffuseConstants.diffuse.rayCandidates) * max(dot(normal, direction), 0.0f) * kInvPi;
}

// Below this distance from x the inverse-square law of area sampling is
// clamped (toSolidAngle says why).
float nearFieldDistance(Surface x) { return 1e-2f * x.viewZ; }

// Streams one ray candidate of x into r, drawn with density `pdf` (per
// unit solid angle): where last frame's pixel `shown` (x >= 0) showed what
// the ray met, its point and radiance, and the point techniques count too;
// otherwise (position, normal, radiance, flags) as the ray found them.
void streamRayCandidate(INOUT(Reservoir) r, Surface x, float pdf, ivec2 shown, vec3 position, vec3 normal,
                        vec3 radiance, uint flags, float nearField, float choice) {
  float techniques = pdf;
  if (shown.x >= 0) {
    ScreenPoint point = screenPoint(shown);
    if (!point.valid) return;
    position = point.position;
    normal = point.normal;
    radiance = point.radiance;
    techniques += pointTechniques(toSolidAngle(point.areaPdf, point.position, point.normal, x.position, nearField),
                                  listedBright(shown));
  }
  Reservoir candidate = emptyReservoir();
  candidate.position = position;
  candidate.normal = normal;
  candidate.radiance = radiance;
  candidate.flags = flags | kReservoirHasSample;
  float pHat = targetPdf(candidate, x.position, x.normal, gIn_DiffuseConstants.diffuse.targetFunction);
  if (pHat <= 0.0f) return;
  reservoirStream(r, position, normal, radiance, flags, pHat / techniques, 0.0f, choice);
}

#endif
