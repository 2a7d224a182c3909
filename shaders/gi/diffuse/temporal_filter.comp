#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.temporal_filter: blends this frame's indirect diffuse with its
// reprojected history. The history is read bilinearly at the motion
// vector's end, each of the four taps only if it saw the same surface
// (depth and normal). Its luminance is clamped to the pixel's fast history
// (an average of about kFastFrames frames) +- gamma * sigma, sigma the
// pixel's temporal deviation over the long history (luminance moments kept
// with the history, as SVGF does; gamma is the Jitter gi pass's
// variance_clipping_gamma_DIF): where light changes, the fast history
// moves within a few frames and drags the long one along. The clamp is
// centred on the fast history, not on the current 3x3 neighbourhood
// (Salvi's variance clipping), because resolved ReSTIR is heavy-tailed: a
// neighbourhood that one bright reservoir lights is bright and uniform,
// its mean far above the truth and its deviation small, so clipping to it
// only ever pulled the history up (measured: +30 to +70 % on sun-room).
// The blend weight is 1 / history length, the length capped at
// gi.diffuse.temporal_filter_frames and reset to 1 where the history is lost
// (disocclusion, camera cut, motion that is not finite). Alpha of the output
// holds the history length. The filtered image and the moments are next
// frame's history, so they are stored finite (sanitizeRadiance, finiteOr).
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "gi/diffuse/diffuse_common.glsl"
#include "shared/color.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4) uniform sampler2D gIn_Motion;
layout(set = 0, binding = 5, rgba16f) readonly uniform image2D gIn_Diffuse;
layout(set = 0, binding = 6, rg32ui) readonly uniform uimage2D gPrev_Surface;
layout(set = 0, binding = 7, rgba32f) readonly uniform image2D gPrev_Filtered;
layout(set = 0, binding = 8, rgba32f) readonly uniform image2D gPrev_Moments;
layout(set = 0, binding = 9, rgba32f) writeonly uniform image2D gOut_Filtered;
layout(set = 0, binding = 10, rgba32f) writeonly uniform image2D gOut_Moments;
#define LIGHT_CHANGE_BINDING 11
#include "gi/light_change/light_change.glsl"

#include "gi/motion.glsl"
#include "gi/temporal_history.glsl"

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  Surface x = gbufferSurface(pixel);
  if (x.viewZ <= 0.0f) {
    imageStore(gOut_Filtered, pixel, vec4(0.0f));
    imageStore(gOut_Moments, pixel, vec4(0.0f));
    return;
  }
  vec3 current = imageLoad(gIn_Diffuse, pixel).xyz;
  float currentLuminance = luminance(current);

  DiffuseConstants d = gIn_DiffuseConstants.diffuse;
  History history;
  history.found = false;
  vec2 motion = historyUsable() ? motionAt(pixel) : vec2(0.0f);
  if (historyUsable() && usableMotion(motion)) {
    float expectedViewZ = projectToScreen(gIn_Frame.frame.previousView, x.position, fullSize()).z;
    if (expectedViewZ > 0.0f)
      history = fetchHistory(0u, vec2(pixel) + motion,
                             ExpectedSurface(x.position, x.normal, expectedViewZ, d.temporalDepthTolerance,
                                             d.temporalCosNormalTolerance, kAnyMaterial));
  }
  float historyLength = history.found ? historyAfterLightChange(history.frames) : 0.0f;
  float frames = min(historyLength + 1.0f, d.temporalFilterFrames);
  float blend = 1.0f / frames;
  vec3 moments = vec3(currentLuminance, currentLuminance * currentLuminance, currentLuminance);
  vec3 previous = vec3(0.0f);
  if (historyLength > 0.0f) {
    moments = history.moments;
    previous = clampToFastHistory(history.radiance, moments, vec2(currentLuminance, currentLuminance * currentLuminance),
                                  blend, d.varianceClippingGamma);
  }
  vec3 filtered = mix(previous, current, blend);
  imageStore(gOut_Filtered, pixel, vec4(sanitizeRadiance(filtered), frames));
  imageStore(gOut_Moments, pixel, storedMoments(finiteOr(moments, vec3(0.0f)), 0.0f));
}
