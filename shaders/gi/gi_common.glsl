// What every GI pass shares: the frame constants at binding 0 (gIn_Frame),
// surfaces of this frame and of the history, and randomness. Passes that
// look at this frame's surfaces include gi/gbuffer.glsl too (bindings 1 and
// 2); the three are the group every such pass binds (src/gi/frame_inputs.h).
#ifndef BOUNCE_GI_COMMON_GLSL
#define BOUNCE_GI_COMMON_GLSL

#include "gpu/constant_block.glsl"
#include "gi/gi_types.glsl"
#include "shared/finite.glsl"
#include "shared/packing.glsl"
#include "shared/rng.glsl"

layout(set = 0, binding = 0, std140) CONSTANT_BLOCK FrameBlock { GiFrameConstants frame; } gIn_Frame;

// Stable per-pass salts for rngSeed, so no two passes draw the same numbers.
const uint kSaltGather = 0x6761u;
const uint kSaltSpatial = 0x7370u;
const uint kSaltResolve = 0x7265u;

vec2 fullSize() { return gIn_Frame.frame.renderSize; }
vec2 halfSize() { return gIn_Frame.frame.halfSize; }
bool historyUsable() { return gIn_Frame.frame.noHistory == 0u; }

bool insideFull(ivec2 p) { return all(greaterThanEqual(p, ivec2(0))) && all(lessThan(p, ivec2(fullSize()))); }
bool insideHalf(ivec2 p) { return all(greaterThanEqual(p, ivec2(0))) && all(lessThan(p, ivec2(halfSize()))); }

// Entry `slot` of the `slotsPerPixel` a half-resolution pixel has in a
// buffer laid out pixel by pixel, row by row (the diffuse branch's pending
// rays and neighbour tests); slot / slotsPerPixel is the pixel's index
// (shared/packing.glsl's pixelToIndex over the half size).
uint halfPixelSlot(ivec2 halfPixel, uint slotsPerPixel, uint slot) {
  return pixelToIndex(uvec2(halfPixel), uint(halfSize().x)) * slotsPerPixel + slot;
}

// The full-resolution pixel whose surface a half-resolution reservoir belongs to.
ivec2 reservoirSurfacePixel(ivec2 halfPixel) { return halfPixel * 2; }

// What the passes accept from the engine (docs/gi.md, "Non-finite
// inputs"). Nothing an engine hands over is trusted to be finite: a depth
// that is not a finite positive number is background; a surface pixel whose
// normal or roughness is not finite, or whose normal has no direction, has
// no usable surface either and is treated like background: nothing is
// gathered for it or reused from it, and since its history surface is
// stored as background, the next frame sees a disocclusion there. Motion
// that is not finite finds no history (a disocclusion too). Radiance goes
// through sanitizeRadiance (shared/finite.glsl) as it is read.
float usableViewZ(float viewZ) { return isFinite(viewZ) && viewZ > 0.0f ? viewZ : 0.0f; }
bool usableNormalRoughness(vec4 normalRoughness) {
  vec3 normal = vec3(normalRoughness.x, normalRoughness.y, normalRoughness.z);
  return isFinite(normalRoughness) && dot(normal, normal) > 0.0f;
}
bool usableMotion(vec2 motion) { return isFinite(motion); }

// A surface of this frame or the previous one: where it is and which way it faces.
struct Surface {
  vec3 position;
  vec3 normal;
  float viewZ;  // 0: background, no surface
};

Surface surfaceAt(ScreenView view, ivec2 pixel, float viewZ, vec3 normal) {
  Surface s;
  s.viewZ = viewZ;
  s.normal = normal;
  s.position = viewZ > 0.0f ? reconstructPosition(view, vec2(pixel), viewZ, fullSize()) : vec3(0.0f);
  return s;
}

// The history surface format (gi.store_history): rg32ui, x = viewZ bits,
// y = octahedral normal and material id (shared/packing.glsl, packNormalMaterial).
Surface historySurfaceAt(ivec2 pixel, uvec2 packed) {
  return surfaceAt(gIn_Frame.frame.previousView, pixel, uintBitsToFloat(packed.x),
                   unpackNormalOfNormalMaterial(packed.y));
}

// Whether two surfaces are the same one seen twice: depths within a fraction
// of the view depth and normals within an angle.
bool similarSurface(float viewZ, vec3 normal, float otherViewZ, vec3 otherNormal, float depthTolerance,
                    float cosNormalTolerance) {
  return otherViewZ > 0.0f && abs(otherViewZ - viewZ) <= depthTolerance * viewZ &&
         dot(normal, otherNormal) >= cosNormalTolerance;
}

uint giSeed(uvec2 pixel, uint salt) {
  return rngSeed(pixel, gIn_Frame.frame.frameIndex, gIn_Frame.frame.seed ^ salt);
}

#endif
