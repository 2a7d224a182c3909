// A ray through this frame's depth buffer, hierarchically (Hi-Z): the
// min-max depth pyramid of gi.depth_pyramid / gi.depth_pyramid_reduce
// (src/gi/depth_pyramid.h), level k covering 2^k x 2^k pixels (the last
// cell of a row or column reaching to the screen's edge), read with
// texelFetch (hizLevel): level 0 is the march depth itself
// (gIn_DepthPyramidLevel0, a sampled r32f image), levels 1 and up the mips
// of gIn_DepthPyramid (a sampled rg32f image, mip k - 1 for level k). Each
// texel holds the nearest surface's viewZ (0: only background below) and
// the farthest (0: some background below).
//
// The including shader includes gi/gi_common.glsl first (gIn_Frame: the
// camera and render size) and defines HIZ_BINDING: this file declares
// gIn_DepthPyramid at it and gIn_DepthPyramidLevel0 at HIZ_LEVEL0_BINDING;
// the host binds both with DepthPyramid::binds() and declares them with
// depthPyramidDecls().
//
// The ray is followed in screen space, where its pixel position and
// 1 / viewZ change linearly, cell by cell (McGuire and Mara 2014, Uludag
// 2014, FidelityFX SSSR; here with min-max tiles, so that rays towards the
// camera and the sky work too): a cell the ray stays in front of (its
// farthest point nearer than the cell's nearest sample, and no sky in it)
// is stepped over, and the next is looked up one level coarser; any other
// is looked into one level finer, down to single pixels. A pixel's surface
// is known at its sample only; across the pixel it is taken as the plane
// through the sample and its neighbours' (hizSurface): pixels flat at
// their sample's depth would make a staircase of a surface receding along
// the ray, which grazing rays run into (the reflections of a glossy floor
// would hit the floor itself). Surfaces are `thickness` times their viewZ
// thick (as in gi/screen_trace.glsl). In a pixel the ray
//   - stays in front of the sample or of the plane: on to the next pixel;
//   - is behind the plane by more than the thickness throughout: it passed
//     behind a surface of unknown thickness, and screen space cannot say
//     what is there (kHizUndecided);
//   - else reaches the surface: a hit (kHizHit), where the ray meets the plane;
//   - meets a background pixel: it reached the sky as far as the screen
//     shows (kHizSky; an off-screen or hidden surface may still be in the way).
// A ray also ends undecided when it leaves the screen, comes closer to the
// camera plane than kHizNearest of its start's viewZ, or runs out of steps.
//
// The ray starts on a surface (a little off it, as rayOrigin() places it):
// its own pixel is not a hit, but a ray leaving that pixel behind its slab
// went through the surface, and ends undecided at once. Until the ray has
// been in front of a whole pixel it is still leaving its own surface, and
// reaching into a surface is not a hit (one right beside the origin, within
// its thickness, is passed through: the ray usually ends undecided behind it).
#ifndef BOUNCE_GI_HIZ_TRACE_GLSL
#define BOUNCE_GI_HIZ_TRACE_GLSL

#if !defined(HIZ_BINDING) || !defined(HIZ_LEVEL0_BINDING)
#error "define HIZ_BINDING and HIZ_LEVEL0_BINDING (the bindings of gIn_DepthPyramid and gIn_DepthPyramidLevel0) first"
#endif

layout(set = 0, binding = HIZ_BINDING) uniform sampler2D gIn_DepthPyramid;
layout(set = 0, binding = HIZ_LEVEL0_BINDING) uniform sampler2D gIn_DepthPyramidLevel0;

// Level `level`'s texel `cell`: (nearest, farthest) viewZ of the pixels it
// covers; level 0 from the march depth, (viewZ, viewZ) or (0, 0).
vec2 hizLevel(ivec2 cell, int level) {
  if (level > 0) return texelFetch(gIn_DepthPyramid, cell, level - 1).xy;
  float viewZ = texelFetch(gIn_DepthPyramidLevel0, cell, 0).x;
  return vec2(isFinite(viewZ) && viewZ > 0.0f ? viewZ : 0.0f);
}

const uint kHizHit = 0u;        // met a depth-buffer surface: the one at `texel`
const uint kHizSky = 1u;        // met a background pixel (`texel`): open on screen, not proven open in the world
const uint kHizUndecided = 2u;  // screen space cannot tell (see above); `lastFree` is how far it vouches

struct HizRay {
  uint outcome;
  ivec2 texel;     // the pixel where the trace ended: hit, sky, or where it passed behind a surface; -1 off screen
  float distance;  // world distance from the origin to lastFree
  vec3 lastFree;   // the hit point; the point where the ray entered the sky pixel or stopped deciding
};

// How far past a cell's edge (in pixels along the ray's major axis) the
// next cell is looked up: well above float rounding of positions up to
// 16384 pixels, well below anything a pixel decision depends on.
const float kHizNudge = 1.0f / 64.0f;
// A ray coming closer to the camera plane than this fraction of its start's
// viewZ has left what the screen shows (it is about to pass the camera).
const float kHizNearest = 1e-3f;
// A ray farther than this multiple of its start's viewZ is as good as at
// infinity: behind every surface. Keeps 1 / viewZ away from 0.
const float kHizFarthest = 1e6f;
const float kHizNever = 1e30f;

// A view-space point in homogeneous pixel coordinates: (x z, y z, z) with
// z = viewZ and (x, y) the continuous pixel position minus the frame's
// jitter, so that pixel (i, j), whose sample lies at its centre plus the
// jitter (docs/conventions.md), covers [i, i + 1) x [j, j + 1). Linear, so
// a direction maps the same way.
vec3 hizHomogeneous(ScreenView view, vec3 local, vec2 size) {
  float z = -local.z;
  return vec3(0.5f * size.x * (local.x / view.projection.x + z) - view.projection.z * z,
              0.5f * size.y * (z - local.y / view.projection.y) - view.projection.w * z, z);
}

// Where p + s * d leaves [low, high) along one axis (kHizNever if it does not move).
float hizAxisExit(float p, float d, float low, float high) {
  return d > 0.0f ? (high - p) / d : d < 0.0f ? (low - p) / d : kHizNever;
}

// The cell of `level` holding the screen point p (the last row and column's
// cells reach to the screen's edge).
ivec2 hizCell(vec2 p, int level, ivec2 levelSize) {
  return clamp(ivec2(floor(p / float(1 << level))), ivec2(0), levelSize - 1);
}

// Where p0 + s * d leaves a cell of `level`.
float hizCellExit(vec2 p0, vec2 d, ivec2 cell, int level, ivec2 levelSize, vec2 size) {
  float cellSize = float(1 << level);
  vec2 low = vec2(cell) * cellSize;
  vec2 high = mix(low + cellSize, size, equal(cell, levelSize - 1));
  return min(hizAxisExit(p0.x, d.x, low.x, high.x), hizAxisExit(p0.y, d.y, low.y, high.y));
}

// 1 / viewZ of a pixel's surface; 0 for background and beyond the screen.
float hizInverseDepth(ivec2 pixel, ivec2 pixels) {
  if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(pixel, pixels))) return 0.0f;
  float viewZ = hizLevel(pixel, 0).x;
  return viewZ > 0.0f ? 1.0f / viewZ : 0.0f;
}

// How 1 / viewZ (`w` at the pixel's sample) changes per pixel along `step`
// across a pixel's surface. On a plane 1 / viewZ is linear in screen space:
// where the neighbours on both sides agree (to a quarter), their mean; else
// the side where the surface continues more smoothly, if it is within a
// quarter of `w` (the other side is an edge); else (a surface one pixel
// wide, background around) 0.
float hizSurfaceSlope(float w, ivec2 pixel, ivec2 step, ivec2 pixels) {
  float before = hizInverseDepth(pixel - step, pixels);
  float after = hizInverseDepth(pixel + step, pixels);
  float fromBefore = before > 0.0f ? w - before : kHizNever;
  float fromAfter = after > 0.0f ? after - w : kHizNever;
  if (before > 0.0f && after > 0.0f &&
      abs(fromBefore - fromAfter) <= 0.25f * max(abs(fromBefore), abs(fromAfter)))
    return 0.5f * (fromBefore + fromAfter);
  float slope = abs(fromBefore) < abs(fromAfter) ? fromBefore : fromAfter;
  return abs(slope) < 0.25f * w ? slope : 0.0f;
}

// A pixel's surface: known at its sample (its centre, jitter taken out),
// taken across the pixel as the plane through the sample and its smoother
// neighbours. Pixels flat at their sample's depth would make a staircase of
// a surface receding along a ray (a floor seen from above), which grazing
// rays run into: the reflections of a glossy floor would hit the floor itself.
struct HizSurface {
  vec2 samplePoint;
  float w;      // 1 / viewZ at the sample
  vec2 slope;   // of 1 / viewZ, per pixel
};

HizSurface hizSurface(ivec2 pixel, float viewZ, ivec2 pixels) {
  HizSurface surface;
  surface.samplePoint = vec2(pixel) + 0.5f;
  surface.w = 1.0f / viewZ;
  surface.slope = vec2(hizSurfaceSlope(surface.w, pixel, ivec2(1, 0), pixels),
                       hizSurfaceSlope(surface.w, pixel, ivec2(0, 1), pixels));
  return surface;
}

// The ray in screen space: p0 + s * d, s in pixels along the major axis;
// z of p and d is 1 / viewZ. `tPerS` turns s into world distance:
// t = s * tPerS / (1 / viewZ at s).
struct HizScreenRay {
  vec3 p0;
  vec3 d;
  float tPerS;
};

// The ray's 1 / viewZ at s, times `scale`, minus the surface's there: > 0
// in front of the surface, < 0 behind it (scale 1) or behind its slab
// (scale 1 + thickness). Linear in s, as both are.
float hizGap(HizScreenRay r, HizSurface surface, float s, float scale) {
  return (r.p0.z + r.d.z * s) * scale - surface.w - dot(surface.slope, r.p0.xy + r.d.xy * s - surface.samplePoint);
}

HizRay hizEnd(uint outcome, HizScreenRay r, float s, vec3 origin, vec3 direction, vec2 size) {
  HizRay ray;
  ray.outcome = outcome;
  // The pixel ahead of s, as the march looked it up.
  vec2 p = r.p0.xy + r.d.xy * (s + kHizNudge);
  ray.texel = all(greaterThanEqual(p, vec2(0.0f))) && all(lessThan(p, size)) ? ivec2(floor(p)) : ivec2(-1);
  ray.distance = s * r.tPerS / (r.p0.z + r.d.z * s);
  ray.lastFree = origin + direction * ray.distance;
  return ray;
}

// Traces origin + t * direction (any length) through the depth pyramid for
// at most maxSteps cell visits; `thickness`: of surfaces, a fraction of their viewZ.
HizRay hizTrace(vec3 originWorld, vec3 directionWorld, float thickness, uint maxSteps) {
  HizRay undecided;
  undecided.outcome = kHizUndecided;
  undecided.texel = ivec2(-1);
  undecided.distance = 0.0f;
  undecided.lastFree = isFinite(originWorld) ? originWorld : vec3(0.0f);
  float length2 = dot(directionWorld, directionWorld);
  if (!isFinite(originWorld) || !isFinite(directionWorld) || !isFinite(length2) || !(length2 > 1e-30f))
    return undecided;
  vec3 direction = directionWorld * inversesqrt(length2);
  ScreenView view = gIn_Frame.frame.view;
  vec2 size = fullSize();
  vec3 k0 = hizHomogeneous(view, toViewSpace(view, originWorld), size);
  vec4 localDirection = view.worldToView * vec4(direction, 0.0f);
  vec3 kd = hizHomogeneous(view, vec3(localDirection.x, localDirection.y, localDirection.z), size);
  if (!(k0.z > 0.0f)) return undecided;  // behind the camera
  HizScreenRay r;
  r.p0 = vec3(k0.x / k0.z, k0.y / k0.z, 1.0f / k0.z);
  if (!isFinite(r.p0) || any(lessThan(r.p0.xy, vec2(0.0f))) || any(greaterThanEqual(r.p0.xy, size)))
    return undecided;  // off screen: nothing known about where it starts
  // d(p, 1 / viewZ) / dt at the origin, times viewZ^2.
  vec3 d = vec3(kd.x * k0.z - k0.x * kd.z, kd.y * k0.z - k0.y * kd.z, -kd.z);
  float major = max(abs(d.x), abs(d.y));
  // Along the camera ray through its own pixel, the ray stays in that pixel.
  if (!isFinite(d) || !(major > 1e-6f * k0.z)) return undecided;
  r.d = d / major;
  r.tPerS = k0.z / major;

  float end = min(hizAxisExit(r.p0.x, r.d.x, 0.0f, size.x), hizAxisExit(r.p0.y, r.d.y, 0.0f, size.y));
  if (r.d.z < 0.0f) end = min(end, r.p0.z * (1.0f - 1.0f / kHizFarthest) / -r.d.z);
  if (r.d.z > 0.0f) end = min(end, r.p0.z * (1.0f / kHizNearest - 1.0f) / r.d.z);
  float slab = 1.0f + (isFinite(thickness) ? max(thickness, 0.0f) : 0.0f);
  ivec2 fullPixels = ivec2(size);
  int top = findMSB(max(fullPixels.x, fullPixels.y));
  // The origin's own pixel holds the surface the ray starts from: not a
  // hit, but a ray that leaves the pixel farther behind that surface than
  // its thickness went through it, and screen space vouches for nothing.
  ivec2 own = ivec2(floor(r.p0.xy));
  float s = min(hizCellExit(r.p0.xy, r.d.xy, own, 0, fullPixels, size), end);
  float ownViewZ = hizLevel(own, 0).x;
  if (maxSteps == 0u || (ownViewZ > 0.0f && hizGap(r, hizSurface(own, ownViewZ, fullPixels), s, slab) < 0.0f))
    return undecided;
  bool emerged = false;  // has been in front of a whole pixel: off its own surface
  int level = 0;
  for (uint i = 0u; i < maxSteps; ++i) {
    if (s >= end) return hizEnd(kHizUndecided, r, end, originWorld, direction, size);
    ivec2 levelSize = max(fullPixels >> level, ivec2(1));
    ivec2 cell = hizCell(r.p0.xy + r.d.xy * (s + kHizNudge), level, levelSize);
    float exit = min(max(hizCellExit(r.p0.xy, r.d.xy, cell, level, levelSize, size), s + kHizNudge), end);
    vec2 surfaces = hizLevel(cell, level);
    bool open = surfaces.y > 0.0f;  // no background pixel in the cell
    // In front of every sample of the cell (the ray's farthest point nearer
    // than the nearest sample): step over it.
    if (open && 1.0f / min(r.p0.z + r.d.z * s, r.p0.z + r.d.z * exit) < surfaces.x) {
      emerged = true;
      s = exit;
      level = min(level + 1, top);
      continue;
    }
    if (level > 0) {
      --level;
      continue;
    }
    if (!open) return hizEnd(kHizSky, r, s, originWorld, direction, size);
    HizSurface surface = hizSurface(cell, surfaces.x, fullPixels);
    float gapEntry = hizGap(r, surface, s, 1.0f);
    float gapExit = hizGap(r, surface, exit, 1.0f);
    if (gapEntry > 0.0f && gapExit > 0.0f) {  // in front of the surface across the pixel
      emerged = true;
      s = exit;
      level = min(1, top);
      continue;
    }
    // Entering behind the surface, the ray may have met it up to a pixel
    // before: a cell is stepped over when the ray is in front of its
    // samples, but a sloped surface reaches half a pixel nearer at its edge.
    float rate = (gapExit - gapEntry) / (exit - s);
    float metBefore = rate < 0.0f ? s - gapEntry / rate : -kHizNever;
    bool justBefore = gapEntry <= 0.0f && metBefore >= s - 1.0f;
    // Behind the surface by more than its thickness across the pixel.
    if (!justBefore && hizGap(r, surface, s, slab) < 0.0f && hizGap(r, surface, exit, slab) < 0.0f)
      return hizEnd(kHizUndecided, r, s, originWorld, direction, size);
    if (!emerged) {
      s = exit;
      continue;
    }
    // The ray reaches the surface in this pixel (or just before): where it
    // meets it, or its entry when it comes from behind it.
    float atSurface = gapEntry > 0.0f ? mix(s, exit, gapEntry / (gapEntry - gapExit))
                      : justBefore    ? max(metBefore, 0.0f)
                                      : s;
    HizRay ray = hizEnd(kHizHit, r, atSurface, originWorld, direction, size);
    ray.texel = cell;
    return ray;
  }
  return hizEnd(kHizUndecided, r, s, originWorld, direction, size);
}

#endif
