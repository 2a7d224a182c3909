// This frame's surfaces as every GI pass reads them from the engine's
// G-buffer: the one place that decodes the engine's formats and decides
// which pixels have a surface (usableViewZ / usableNormalRoughness in
// gi/gi_common.glsl, which the including shader includes first). Its two
// bindings, with gIn_Frame, are the group every pass that looks at this
// frame's surfaces binds (src/gi/frame_inputs.h); they are sampled images
// read with texelFetch, so any format of their family works (R16F or R32F
// depth; rgba16f or rgb10_a2 normals, as gIn_Frame.frame.normalEncoding says).
#ifndef BOUNCE_GI_GBUFFER_GLSL
#define BOUNCE_GI_GBUFFER_GLSL

layout(set = 0, binding = 1) uniform sampler2D gIn_ViewZ;
layout(set = 0, binding = 2) uniform sampler2D gIn_NormalRoughness;

// The depth as stored: may be anything, NaN included (usableViewZ decides).
float gbufferRawViewZ(ivec2 pixel) { return texelFetch(gIn_ViewZ, pixel, 0).x; }

// World normal (not yet normalised) and perceptual roughness, whatever the encoding.
vec4 gbufferNormalRoughness(ivec2 pixel) {
  vec4 stored = texelFetch(gIn_NormalRoughness, pixel, 0);
  if (gIn_Frame.frame.normalEncoding == kNormalEncodingOctahedral)
    return vec4(decodeOctahedral(vec2(stored.x, stored.y) * 2.0f - 1.0f), stored.z);
  return stored;
}

// The surface a pixel shows; viewZ 0 (no surface) for background and for a
// pixel whose depth, normal or roughness cannot be used. The normal is read
// only where there is a depth, so a background pixel costs one fetch.
// `roughness`: the surface's perceptual roughness in [0, 1] (1 without a surface).
Surface gbufferSurfaceRoughness(ivec2 pixel, out float roughness) {
  roughness = 1.0f;
  float viewZ = usableViewZ(gbufferRawViewZ(pixel));
  vec4 normalRoughness = viewZ > 0.0f ? gbufferNormalRoughness(pixel) : vec4(0.0f);
  if (viewZ <= 0.0f || !usableNormalRoughness(normalRoughness))
    return surfaceAt(gIn_Frame.frame.view, pixel, 0.0f, vec3(0.0f, 0.0f, 1.0f));
  roughness = clamp(normalRoughness.w, 0.0f, 1.0f);
  return surfaceAt(gIn_Frame.frame.view, pixel, viewZ, normalize(normalRoughness.xyz));
}

Surface gbufferSurface(ivec2 pixel) {
  float roughness;
  return gbufferSurfaceRoughness(pixel, roughness);
}

// A pixel's depth alone, for tests that need no normal (visibility marches,
// neighbourhood statistics): 0 for background and non-finite depths.
float gbufferDepth(ivec2 pixel) { return usableViewZ(gbufferRawViewZ(pixel)); }

#endif
