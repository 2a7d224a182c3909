// A reflection ray marched through this frame's depth buffer (gIn_MarchDepth,
// which the including shader declares after gi/gi_common.glsl) in even steps
// of screen space: clipped to the screen first, so every step moves about
// the same number of pixels whatever the ray's length. What it can say:
// it hit a depth-buffer surface (a step falls behind one by less than its
// thickness right after a step in front of it), it met a sky pixel (only
// proof that the screen shows sky there), or it is undecided (left the
// screen or the view, passed behind a surface farther than its thickness,
// or ran out of steps): the caller's world ray decides then.
#ifndef BOUNCE_GI_SPECULAR_SCREEN_MARCH_GLSL
#define BOUNCE_GI_SPECULAR_SCREEN_MARCH_GLSL

const uint kMarchHit = 0u;
const uint kMarchSky = 1u;
const uint kMarchUndecided = 2u;

struct MarchResult {
  uint outcome;
  ivec2 texel;  // the surface hit
};

// How far the ray may go (world units) before its view-space z leaves the
// near side of the camera: points behind the camera do not project.
float marchLength(vec3 startView, vec3 directionView, float viewZ) {
  const float kFarthest = 64.0f;  // multiples of the pixel's viewZ
  float length = kFarthest * viewZ;
  if (directionView.z > 0.0f) length = min(length, (-startView.z - 0.01f) / directionView.z);
  return max(length, 0.0f);
}

MarchResult screenMarch(vec3 origin, vec3 direction, float viewZ, float thickness, uint steps, float jitter) {
  MarchResult result;
  result.outcome = kMarchUndecided;
  result.texel = ivec2(0);
  ScreenView view = gIn_Frame.frame.view;
  vec3 startView = toViewSpace(view, origin);
  vec3 directionView = toViewSpace(view, origin + direction) - startView;
  float length = marchLength(startView, directionView, viewZ);
  if (length <= 0.0f || steps == 0u) return result;
  vec3 a = projectViewPoint(view, startView, fullSize());
  vec3 endView = startView + directionView * length;
  vec3 b = projectViewPoint(view, endView, fullSize());
  // Clip the segment to the screen in 2D (perspective: interpolate 1/z).
  vec2 delta = vec2(b) - vec2(a);
  float tEnd = 1.0f;
  for (int axis = 0; axis < 2; ++axis) {
    float d = delta[axis];
    float limit = d > 0.0f ? fullSize()[axis] - (a[axis]) : -a[axis];
    if (abs(d) > 1e-6f) tEnd = min(tEnd, max(limit / d, 0.0f));
  }
  bool clipped = tEnd < 1.0f;
  float inverseA = 1.0f / a.z;
  float inverseB = 1.0f / b.z;
  vec2 previous = vec2(a);
  for (uint i = 1u; i <= steps; ++i) {
    float t = tEnd * (float(i) - 1.0f + jitter) / float(steps);
    vec2 screen = vec2(a) + delta * t;
    float depth = 1.0f / mix(inverseA, inverseB, t);  // viewZ along the ray at this screen point
    ivec2 texel = ivec2(floor(screen));
    if (!insideFull(texel)) return result;
    if (texel == ivec2(floor(vec2(a)))) continue;  // the pixel the ray starts on
    float sceneViewZ = marchViewZ(texel);
    if (sceneViewZ <= 0.0f) {
      result.outcome = kMarchSky;
      return result;
    }
    float behind = depth - sceneViewZ;
    if (behind > 0.01f * sceneViewZ) {
      if (behind < thickness * sceneViewZ) {
        result.outcome = kMarchHit;
        result.texel = texel;
      }
      return result;
    }
  }
  // Walked the whole way in front of everything: left the screen (clipped) or the ray's range.
  return result;
}

#endif
