// How much of its history each temporal history keeps this frame, after a
// change of light (gi.light_change.frame): the reservoirs' M, the
// denoiser's and the branches' filters' history lengths, the radiance
// cache's sample counts. Light that changed makes every history's old
// frames wrong in proportion; without this each would follow the change
// only at 1 / its length a frame, and the loop of histories (the cache, the
// filters, the composite the next gather reads) far slower still.
#ifndef BOUNCE_GI_LIGHT_CHANGE_GLSL
#define BOUNCE_GI_LIGHT_CHANGE_GLSL

// A share of the direct light changing below this is taken for noise (a
// moving highlight, reprojection at edges): histories keep everything.
const float kLightChangeNoise = 0.01f;
// From this share on, every history starts over.
const float kLightChangeRestart = 0.25f;
// After a history restarts for a change of light, the screen's histories
// may hold at most this many frames more each frame, so they keep up while
// the light that bounces more than once is still arriving (one bounce more
// a frame: each frame's estimate is above the last, and a history of all
// of them would lag); a history that did not restart is not held back.
const float kHistoryRegrowth = 0.5f;
// The hold on a history that nothing restarted: longer than any.
const float kHistoryUnheld = 65536.0f;

// The share of history kept for a change of `change` of the light.
float historyShareKept(float change) {
  return clamp(1.0f - (change - kLightChangeNoise) / (kLightChangeRestart - kLightChangeNoise), 0.0f, 1.0f);
}

#ifdef LIGHT_CHANGE_BINDING
// This frame's verdict (gi.light_change): x the share of the light that
// changed, y last frame's share, z the share of history kept, w the most
// frames a screen history may hold (kHistoryRegrowth).
layout(set = 0, binding = LIGHT_CHANGE_BINDING, rgba32f) readonly uniform image2D gIn_LightChange;
float historyKept() { return imageLoad(gIn_LightChange, ivec2(0)).z; }
// The most frames a history may hold this frame.
float historyHold() { return imageLoad(gIn_LightChange, ivec2(0)).w; }
// A screen history of `frames` frames (or M samples a frame) after the change.
float historyAfterLightChange(float frames) {
  vec4 verdict = imageLoad(gIn_LightChange, ivec2(0));
  return min(frames * verdict.z, verdict.w);
}
#endif

#endif
