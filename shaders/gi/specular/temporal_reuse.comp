#version 460
#extension GL_GOOGLE_include_directive : require
// gi.specular.temporal_reuse: merges each pixel's fresh reservoir with the
// one its surface had last frame, found through the motion vector and
// accepted only on the same surface (depth and normal). Unlike the diffuse
// branch the history is this pass's own output, before spatial reuse (the
// Jitter gi pass's feedback point), and short: M is capped at gi.specular.temporal_max_m
// (4), so a reflection follows a moving camera within a few frames. The
// history's sample is re-weighed by its target at this frame's surface and
// view (VNDF sampling: the BRDF changes with the view; uniform sampling:
// the target ignores the view, and a sample that left this frame's cone is
// rejected). A reused sample that last frame's screen shows takes the
// radiance it sends now. Surfaces smoother than
// gi.specular.reuse_min_roughness keep their fresh reservoir alone (Zyanide's uniform-lobe reservoirs).
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"

layout(set = 0, binding = 4) uniform sampler2D gIn_BaseColorMetallic;
#define SPECULAR_READS_MATERIAL
#include "gi/specular/specular_common.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 5) uniform sampler2D gIn_Motion;
layout(set = 0, binding = 6, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 7, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 8, rgba32ui) readonly uniform uimage2D gIn_Reservoir1;
layout(set = 0, binding = 9, rgba32ui) readonly uniform uimage2D gPrev_Reservoir0;
layout(set = 0, binding = 10, rgba32ui) readonly uniform uimage2D gPrev_Reservoir1;
layout(set = 0, binding = 11, rgba32ui) writeonly uniform uimage2D gOut_Reservoir0;
layout(set = 0, binding = 12, rgba32ui) writeonly uniform uimage2D gOut_Reservoir1;
layout(set = 0, binding = 13, rgba16f) readonly uniform image2D gPrev_Composite;
#define LIGHT_CHANGE_BINDING 14
#include "gi/light_change/light_change.glsl"

#include "gi/motion.glsl"
#include "gi/previous_screen.glsl"

const uint kSaltSpecularTemporal = 0x7374u + 1u;

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideHalf(halfPixel)) return;
  uvec4 first = imageLoad(gIn_Reservoir0, halfPixel);
  uvec4 second = imageLoad(gIn_Reservoir1, halfPixel);
  ivec2 pixel = reservoirSurfacePixel(halfPixel);
  float roughness;
  Surface x = gbufferSurfaceRoughness(pixel, roughness);
  vec2 motion = x.viewZ > 0.0f && historyUsable() ? motionAt(pixel) : vec2(0.0f);
  if (x.viewZ > 0.0f && historyUsable() && usableMotion(motion)) {
    GlossySurface s = pixelGlossySurface(x, roughness, pixel);
    SpecularConstants c = gIn_SpecularConstants.specular;
    vec2 previousPosition = vec2(pixel) + 0.5f + motion;
    ivec2 previousHalf = ivec2(floor(previousPosition * 0.5f));
    ivec2 previousPixel = reservoirSurfacePixel(previousHalf);
    float expectedViewZ = projectToScreen(gIn_Frame.frame.previousView, x.position, fullSize()).z;
    if (specularReuses(s) && insideHalf(previousHalf) && expectedViewZ > 0.0f) {
      Surface previous = historySurfaceAt(previousPixel, imageLoad(gPrev_Surface, previousPixel).xy);
      if (similarSurface(expectedViewZ, x.normal, previous.viewZ, previous.normal, c.temporalDepthTolerance,
                         c.temporalCosNormalTolerance)) {
        uint rng = giSeed(uvec2(halfPixel), kSaltSpecularTemporal);
        Reservoir fresh = unpackReservoir(first, second);
        Reservoir history =
            unpackReservoir(imageLoad(gPrev_Reservoir0, previousHalf), imageLoad(gPrev_Reservoir1, previousHalf));
        history.M = uint(historyAfterLightChange(float(min(history.M, c.temporalMaxM))));
        if (reservoirHasSample(history) && !reservoirIsEnvironment(history)) {
          ivec2 shown = previousPixelShowing(history.position, history.normal);
          if (shown.x >= 0) history.radiance = sanitizeRadiance(imageLoad(gPrev_Composite, shown).xyz);
        }
        Reservoir merged = emptyReservoir();
        reservoirStream(merged, fresh.position, fresh.normal, fresh.radiance, fresh.flags,
                        specularTargetPdf(fresh, s, c.sampling, c.lobeFraction) * fresh.W * fresh.M, fresh.M,
                        rngUniform(rng));
        reservoirStream(merged, history.position, history.normal, history.radiance, history.flags,
                        specularTargetPdf(history, s, c.sampling, c.lobeFraction) * history.W * history.M, history.M,
                        rngUniform(rng));
        reservoirFinalize(merged, specularTargetPdf(merged, s, c.sampling, c.lobeFraction), merged.M);
        packReservoir(merged, first, second);
      }
    }
  }
  imageStore(gOut_Reservoir0, halfPixel, first);
  imageStore(gOut_Reservoir1, halfPixel, second);
}
