#version 460
#extension GL_GOOGLE_include_directive : require
// gi.specular.temporal_filter: blends this frame's indirect specular with
// its history, fetched twice (the Jitter gi pass's dual-source reprojection):
//   surface  through the motion vectors, where the surface itself was: right
//            for rough surfaces, whose reflection sticks to the surface;
//   virtual  where the reflected image was: the hit seen in the mirror lies
//            hit distance beyond the surface along the view ray (a virtual
//            point behind a flat reflector), and last frame's camera saw
//            that point at another pixel of the same reflector. Right for
//            mirrors, whose reflections swim over the surface as the camera moves.
// The Jitter gi pass blends the two by local statistics alone and reports mixed results
// at medium roughness. Here each source's weight is a prior from roughness
// (virtual for smooth, surface for rough; NRD's virtual-history amount)
// times its agreement with this frame: a Gaussian in how many local standard
// deviations (3x3 of this frame's resolve) its luminance lies from the local
// mean, so the source that reprojected the wrong reflection loses. A
// virtual tap counts only on the reflector's plane. The blended history is
// clamped to the fast history as the diffuse filter does
// (gi/temporal_history.glsl), and smooth surfaces keep a shorter history
// (a quarter of gi.specular.temporal_filter_frames for a mirror), since
// their reflections move most. gOut_Reprojection shows which source won.
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "gi/specular/specular_common.glsl"
#include "shared/color.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4) uniform sampler2D gIn_Motion;
layout(set = 0, binding = 5, rgba16f) readonly uniform image2D gIn_Specular;
layout(set = 0, binding = 6, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 7, rgba32f) readonly uniform image2D gPrev_Filtered;
layout(set = 0, binding = 8, rgba32f) readonly uniform image2D gPrev_Moments;
layout(set = 0, binding = 9, rgba32f) writeonly uniform image2D gOut_Filtered;
layout(set = 0, binding = 10, rgba32f) writeonly uniform image2D gOut_Moments;
layout(set = 0, binding = 11, rgba16f) writeonly uniform image2D gOut_Reprojection;
#define LIGHT_CHANGE_BINDING 12
#include "gi/light_change/light_change.glsl"

#include "gi/motion.glsl"
#include "gi/temporal_history.glsl"

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  float roughness;
  Surface x = gbufferSurfaceRoughness(pixel, roughness);
  if (x.viewZ <= 0.0f) {
    imageStore(gOut_Filtered, pixel, vec4(0.0f));
    imageStore(gOut_Moments, pixel, vec4(0.0f));
    imageStore(gOut_Reprojection, pixel, vec4(0.0f));
    return;
  }
  SpecularConstants c = gIn_SpecularConstants.specular;
  vec4 resolved = imageLoad(gIn_Specular, pixel);
  vec3 current = vec3(resolved);
  float currentLuminance = luminance(current);

  History surface;
  surface.found = false;
  History virtualHistory;
  virtualHistory.found = false;
  vec2 motion = historyUsable() ? motionAt(pixel) : vec2(0.0f);
  if (historyUsable() && usableMotion(motion)) {
    float expectedViewZ = projectToScreen(gIn_Frame.frame.previousView, x.position, fullSize()).z;
    if (c.reprojection != kReprojectionVirtual && expectedViewZ > 0.0f)
      surface = fetchHistory(0u, vec2(pixel) + motion, ExpectedSurface(x.position, x.normal, expectedViewZ,
                                                                   c.temporalDepthTolerance,
                                                                   c.temporalCosNormalTolerance, kAnyMaterial));
    if (c.reprojection != kReprojectionSurface)
      virtualHistory = fetchVirtualHistory(0u, x, virtualReprojection(x, resolved.w, 0.0f, 1.0f),
                                           c.temporalDepthTolerance, c.temporalCosNormalTolerance, kAnyMaterial);
  }

  // This frame's local statistics, which judge the two sources.
  float mean = currentLuminance, deviation = 0.0f;
  if (surface.found && virtualHistory.found) {
    float sum = 0.0f;
    float sumSquares = 0.0f;
    float count = 0.0f;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 tap = pixel + ivec2(dx, dy);
        if (!insideFull(tap) || gbufferDepth(tap) <= 0.0f) continue;
        float l = luminance(vec3(imageLoad(gIn_Specular, tap)));
        sum += l;
        sumSquares += l * l;
        count += 1.0f;
      }
    mean = sum / count;
    deviation = sqrt(max(sumSquares / count - mean * mean, 0.0f));
  }
  float virtualWeight;
  History history = blendReflectionHistories(surface, virtualHistory, roughness, mean, deviation, virtualWeight);

  float longest = c.temporalFilterFrames * mix(0.25f, 1.0f, smoothstep(0.0f, 0.5f, roughness));
  float historyLength = history.found ? historyAfterLightChange(history.frames) : 0.0f;
  float frames = min(historyLength + 1.0f, max(longest, 1.0f));
  float blend = 1.0f / frames;
  vec3 moments = vec3(currentLuminance, currentLuminance * currentLuminance, currentLuminance);
  vec3 previous = vec3(0.0f);
  if (historyLength > 0.0f) {
    moments = history.moments;
    previous = clampToFastHistory(history.radiance, moments, vec2(currentLuminance, currentLuminance * currentLuminance),
                                  blend, c.varianceClippingGamma);
  }
  vec3 filtered = mix(previous, current, blend);
  imageStore(gOut_Filtered, pixel, vec4(sanitizeRadiance(filtered), frames));
  imageStore(gOut_Moments, pixel, storedMoments(finiteOr(moments, vec3(0.0f)), 0.0f));
  // r: the surface history was used, g: the virtual one, b: history length / the longest.
  imageStore(gOut_Reprojection, pixel,
             vec4(surface.found ? 1.0f - virtualWeight : 0.0f, virtualWeight, frames / max(longest, 1.0f), 1.0f));
}
