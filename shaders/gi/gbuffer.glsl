// This frame's surfaces as every GI pass reads them from the engine's
// G-buffer: the one place that decides which pixels have one
// (usableViewZ / usableNormalRoughness in gi/gi_common.glsl). The including
// shader declares gIn_ViewZ (r32f) and gIn_NormalRoughness (rgba16f) and
// includes gi/gi_common.glsl first.
#ifndef BOUNCE_GI_GBUFFER_GLSL
#define BOUNCE_GI_GBUFFER_GLSL

// The surface a pixel shows; viewZ 0 (no surface) for background and for a
// pixel whose depth, normal or roughness cannot be used. The normal is read
// only where there is a depth, so a background pixel costs one fetch.
Surface gbufferSurface(ivec2 pixel) {
  float viewZ = usableViewZ(imageLoad(gIn_ViewZ, pixel).x);
  vec4 normalRoughness = viewZ > 0.0f ? imageLoad(gIn_NormalRoughness, pixel) : vec4(0.0f);
  if (viewZ <= 0.0f || !usableNormalRoughness(normalRoughness))
    return surfaceAt(gIn_Frame.frame.view, pixel, 0.0f, vec3(0.0f, 0.0f, 1.0f));
  return surfaceAt(gIn_Frame.frame.view, pixel, viewZ, normalize(normalRoughness.xyz));
}

// A pixel's depth alone, for tests that need no normal (visibility marches,
// neighbourhood statistics): 0 for background and non-finite depths.
float gbufferDepth(ivec2 pixel) { return usableViewZ(imageLoad(gIn_ViewZ, pixel).x); }

#endif
