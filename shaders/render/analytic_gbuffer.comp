#version 460
#extension GL_GOOGLE_include_directive : require
// render.analytic_gbuffer: casts one primary ray per pixel into the analytic
// scene and writes the G-buffer. Background pixels get viewZ = 0.
#include "render/analytic_scene.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 1, r32f) writeonly uniform image2D gOut_ViewZ;
layout(set = 0, binding = 2, rgba16f) writeonly uniform image2D gOut_NormalRoughness;
layout(set = 0, binding = 3, rgba8) writeonly uniform image2D gOut_BaseColorMetallic;

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= uint(params.cameraPosition.w) || pixel.y >= uint(params.cameraRight.w)) return;
  vec3 origin = params.cameraPosition.xyz;
  vec3 direction = analyticCameraRay(pixel);
  AnalyticHit hit = traceAnalyticScene(origin, direction, 0.0f);
  if (hit.t >= kNoHit) {
    imageStore(gOut_ViewZ, ivec2(pixel), vec4(0.0f));
    imageStore(gOut_NormalRoughness, ivec2(pixel), vec4(0.0f));
    imageStore(gOut_BaseColorMetallic, ivec2(pixel), vec4(0.0f));
    return;
  }
  float viewZ = hit.t * dot(direction, params.cameraForward.xyz);
  imageStore(gOut_ViewZ, ivec2(pixel), vec4(viewZ));
  imageStore(gOut_NormalRoughness, ivec2(pixel), vec4(hit.normal, hit.roughness));
  imageStore(gOut_BaseColorMetallic, ivec2(pixel), vec4(hit.baseColor, hit.metallic));
}
