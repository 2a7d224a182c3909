#version 460
#extension GL_GOOGLE_include_directive : require
// gi.denoise.validation (captured frames only): the denoiser's validation
// view (NRD's validation layer): one image of 4 x 2 panels, each the whole
// frame shrunk into it. Top: viewZ (log scale), normals, motion (0.5 grey
// = still, 1 pixel = 1/32 of the range), the specular virtual history's
// share (black: surface motion only, cyan: reflection motion only);
// bottom: the diffuse and specular history lengths (black 0 to white
// max_accumulated_frames, via red and yellow) and the denoised diffuse and
// specular light (tonemapped) with the pixels whose history was lost this
// frame (disocclusion, a cut) in red. "Diffuse" and "specular" are the
// first signal of each kind the denoiser ran this frame (the library's
// two, unless the engine declared others first); a panel of a kind none
// ran is black.
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#define DENOISE_VIEW_PASS
#include "gi/denoise/denoise_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4) uniform sampler2D gIn_Motion;
layout(set = 0, binding = 5, rgba16f) readonly uniform image2D gIn_DiffuseHistory;
layout(set = 0, binding = 6, rgba16f) readonly uniform image2D gIn_SpecularHistory;
layout(set = 0, binding = 7, rgba16f) readonly uniform image2D gIn_SpecularMoments;
layout(set = 0, binding = 8, rgba16f) readonly uniform image2D gIn_Diffuse;
layout(set = 0, binding = 9, rgba16f) readonly uniform image2D gIn_Specular;
layout(set = 0, binding = 10, rgba16f) writeonly uniform image2D gOut_Validation;

#include "gi/motion.glsl"

// Which kinds have a signal in the panels.
layout(push_constant) uniform ValidationParams {
  uint diffuseShown;   // 1: the diffuse panels show a signal
  uint specularShown;  // 1: the specular panels do
} gShown;

bool signalOn(uint kind) { return (kind == kSignalKindDiffuse ? gShown.diffuseShown : gShown.specularShown) != 0u; }

// Black, red, yellow, white as t goes 0..1.
vec3 heat(float t) {
  t = clamp(t, 0.0f, 1.0f) * 3.0f;
  return clamp(vec3(t, t - 1.0f, t - 2.0f), vec3(0.0f), vec3(1.0f));
}

vec3 panel(uint which, ivec2 source) {
  DenoiseConstants d = gIn_DenoiseConstants.denoise;
  float viewZ = gbufferDepth(source);
  if (which == 0u) return vec3(viewZ > 0.0f ? clamp(1.0f - log2(1.0f + viewZ) / 8.0f, 0.0f, 1.0f) : 0.0f);
  if (which == 1u) return viewZ > 0.0f ? gbufferSurface(source).normal * 0.5f + 0.5f : vec3(0.0f);
  if (which == 2u) {
    vec2 motion = motionAt(source);
    return usableMotion(motion) ? vec3(clamp(vec2(0.5f) + motion / 32.0f, 0.0f, 1.0f), 0.5f) : vec3(1.0f, 0.0f, 1.0f);
  }
  if (which == 3u)
    return signalOn(kSignalKindSpecular) && viewZ > 0.0f
               ? vec3(0.0f, 1.0f, 1.0f) * clamp(imageLoad(gIn_SpecularMoments, source).w, 0.0f, 1.0f)
               : vec3(0.0f);
  if (which == 4u)
    return signalOn(kSignalKindDiffuse) ? heat(imageLoad(gIn_DiffuseHistory, source).w / d.maxAccumulatedFrames)
                                    : vec3(0.0f);
  if (which == 5u)
    return signalOn(kSignalKindSpecular) ? heat(imageLoad(gIn_SpecularHistory, source).w / d.maxAccumulatedFrames)
                                     : vec3(0.0f);
  bool diffuse = which == 6u;
  if (!signalOn(diffuse ? kSignalKindDiffuse : kSignalKindSpecular) || viewZ <= 0.0f) return vec3(0.0f);
  float frames = diffuse ? imageLoad(gIn_DiffuseHistory, source).w : imageLoad(gIn_SpecularHistory, source).w;
  if (frames <= 1.0f) return vec3(1.0f, 0.0f, 0.0f);
  vec3 light = max(diffuse ? imageLoad(gIn_Diffuse, source).xyz : imageLoad(gIn_Specular, source).xyz, vec3(0.0f));
  return light / (1.0f + light);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  ivec2 size = ivec2(fullSize());
  ivec2 panelSize = max(size / ivec2(4, 2), ivec2(1));
  ivec2 cell = min(pixel / panelSize, ivec2(3, 1));
  vec2 local = (vec2(pixel - cell * panelSize) + 0.5f) / vec2(panelSize);
  ivec2 source = clamp(ivec2(local * vec2(size)), ivec2(0), size - 1);
  imageStore(gOut_Validation, pixel, vec4(panel(uint(cell.x + 4 * cell.y), source), 1.0f));
}
