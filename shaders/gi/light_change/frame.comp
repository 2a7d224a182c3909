#version 460
#extension GL_GOOGLE_include_directive : require
// gi.light_change.frame: the share of the frame's direct light that
// changed since last frame (the tiles' summed block changes over their
// summed light), or the share the engine declares it changed
// (FrameInputs::lightChange) where that is larger: a lamp no pixel shows
// (off screen, or smaller than a pixel of a small frame) changes the
// indirect light with no trace in the frame's direct light. From the
// larger of this frame's and last frame's share, the share of their
// history every temporal history keeps this frame
// (gi/light_change/light_change.glsl). Last frame's counts too: the
// screen's samples see a change one frame late, through last frame's
// composite. And the most frames a screen history may hold: where a
// change restarted them, it grows back kHistoryRegrowth a frame. One
// workgroup; each invocation sums a fixed set of tiles, then the workgroup
// sums them (gi/workgroup_sum.glsl): the same bits every run.
#include "gi/gi_common.glsl"
#include "gi/light_change/light_change.glsl"

layout(local_size_x = 256) in;

layout(set = 0, binding = 1, rgba32f) readonly uniform image2D gIn_Tiles;
layout(set = 0, binding = 2, rgba32f) readonly uniform image2D gPrev_LightChange;
layout(set = 0, binding = 3, rgba32f) writeonly uniform image2D gOut_LightChange;

const uint kInvocations = 256u;
#define WORKGROUP_SUM_LANES kInvocations
#include "gi/workgroup_sum.glsl"

void main() {
  uint lane = gl_LocalInvocationIndex;
  ivec2 tiles = (ivec2(fullSize()) + 15) / 16;
  uint count = uint(tiles.x * tiles.y);
  vec4 own = vec4(0.0f);
  for (uint i = lane; i < count; i += kInvocations)
    own += imageLoad(gIn_Tiles, ivec2(int(i) % tiles.x, int(i) / tiles.x));
  vec4 total = workgroupSum(own);
  if (lane != 0u) return;
  float seen = total.y > 0.0f ? clamp(total.x / total.y, 0.0f, 1.0f) : 0.0f;
  float change = max(seen, gIn_Frame.frame.declaredLightChange);
  vec4 last = historyUsable() ? imageLoad(gPrev_LightChange, ivec2(0)) : vec4(0.0f, 0.0f, 1.0f, kHistoryUnheld);
  float kept = historyShareKept(max(change, last.x));
  float hold = min(last.w + kHistoryRegrowth, kHistoryUnheld) * kept;
  imageStore(gOut_LightChange, ivec2(0), vec4(change, last.x, kept, hold));
}
