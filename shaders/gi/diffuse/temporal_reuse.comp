#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.temporal_reuse: merges each pixel's fresh reservoir with the
// one its surface had last frame (the output of last frame's second spatial
// pass), found through the motion vector and accepted only if the surface
// there is the same one (depth and normal). The history's sample is
// re-weighed by its p-hat at this frame's surface; its M is capped so old
// samples cannot crowd out new light. On a camera cut, the first frame, or
// a disocclusion (or motion that is not finite), the fresh reservoir passes
// through. A reused sample whose surface last frame's screen shows takes
// the radiance it sends now (last frame's composite there), as ReSTIR DI
// evaluates its lights anew: a stored radiance would hold back every
// change of light, and every bounce the feedback adds, for as long as the
// sample lives. After a change of light (gi.light_change) the history's M
// shrinks further: samples drawn for the old light cannot find the new.
// The pass whose counters its world rays add to (gi/world_ray_count.glsl).
#define WORLD_RAY_PASS kWorldRayPassTemporalReuse
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "gi/diffuse/diffuse_common.glsl"
#include "gi/diffuse/reuse_visibility.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4) uniform sampler2D gIn_Motion;
layout(set = 0, binding = 5, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 6, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 7, rgba32ui) readonly uniform uimage2D gIn_Reservoir1;
layout(set = 0, binding = 8, rgba32ui) readonly uniform uimage2D gPrev_Reservoir0;
layout(set = 0, binding = 9, rgba32ui) readonly uniform uimage2D gPrev_Reservoir1;
layout(set = 0, binding = 10, rgba32ui) writeonly uniform uimage2D gOut_Reservoir0;
layout(set = 0, binding = 11, rgba32ui) writeonly uniform uimage2D gOut_Reservoir1;
layout(set = 0, binding = 12, rgba16f) readonly uniform image2D gPrev_Composite;
#define LIGHT_CHANGE_BINDING 13
#include "gi/light_change/light_change.glsl"

#include "gi/motion.glsl"
#include "gi/diffuse/previous_screen.glsl"

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideHalf(halfPixel)) return;
  uvec4 first = imageLoad(gIn_Reservoir0, halfPixel);
  uvec4 second = imageLoad(gIn_Reservoir1, halfPixel);
  ivec2 pixel = reservoirSurfacePixel(halfPixel);
  Surface x = gbufferSurface(pixel);
  vec2 motion = x.viewZ > 0.0f && historyUsable() ? motionAt(pixel) : vec2(0.0f);
  if (x.viewZ > 0.0f && historyUsable() && usableMotion(motion)) {
    // Where this surface was last frame, and the reservoir that covered it.
    vec2 previousPosition = vec2(pixel) + 0.5f + motion;
    ivec2 previousHalf = ivec2(floor(previousPosition * 0.5f));
    ivec2 previousPixel = reservoirSurfacePixel(previousHalf);
    float expectedViewZ = projectToScreen(gIn_Frame.frame.previousView, x.position, fullSize()).z;
    if (insideHalf(previousHalf) && expectedViewZ > 0.0f) {
      Surface previous = historySurfaceAt(previousPixel, imageLoad(gPrev_Surface, previousPixel).xy);
      DiffuseConstants d = gIn_DiffuseConstants.diffuse;
      if (similarSurface(expectedViewZ, x.normal, previous.viewZ, previous.normal, d.temporalDepthTolerance,
                         d.temporalCosNormalTolerance)) {
        uint target = d.targetFunction;
        uint rng = giSeed(uvec2(halfPixel), kSaltSpatial + 1u);
        Reservoir fresh = unpackReservoir(first, second);
        Reservoir history = unpackReservoir(imageLoad(gPrev_Reservoir0, previousHalf), imageLoad(gPrev_Reservoir1, previousHalf));
        history.M = uint(historyAfterLightChange(float(min(history.M, d.temporalMaxM))));
        if (reservoirHasSample(history) && !reservoirIsEnvironment(history)) {
          ivec2 shown = previousPixelOf(history.position, history.normal);
          if (shown.x >= 0) history.radiance = sanitizeRadiance(imageLoad(gPrev_Composite, shown).xyz);
        }
        Reservoir merged = emptyReservoir();
        reservoirStream(merged, fresh.position, fresh.normal, fresh.radiance, fresh.flags,
                        targetPdf(fresh, x.position, x.normal, target) * fresh.W * fresh.M, fresh.M, rngUniform(rng));
        reservoirStream(merged, history.position, history.normal, history.radiance, history.flags,
                        targetPdf(history, x.position, x.normal, target) * history.W * history.M *
                            reuseVisibility(history, x),
                        history.M, rngUniform(rng));
        reservoirFinalize(merged, targetPdf(merged, x.position, x.normal, target), merged.M);
        packReservoir(merged, first, second);
      }
    }
  }
  imageStore(gOut_Reservoir0, halfPixel, first);
  imageStore(gOut_Reservoir1, halfPixel, second);
}
