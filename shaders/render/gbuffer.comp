#version 460
#extension GL_GOOGLE_include_directive : require
// render.gbuffer: one primary ray per pixel (through the pixel centre plus
// this frame's jitter) into the scene's BVH, writing everything a GI pass
// needs about the visible surface. Conventions: docs/conventions.md.
// Everything it stores is finite (docs/conventions.md, "Non-finite values").
#include "render/scene_access.glsl"
#include "shared/finite.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 16, r32f) writeonly uniform image2D gOut_ViewZ;
layout(set = 0, binding = 17, rgba16f) writeonly uniform image2D gOut_NormalRoughness;
layout(set = 0, binding = 18, rgba16f) writeonly uniform image2D gOut_GeometricNormal;
layout(set = 0, binding = 19, rgba8) writeonly uniform image2D gOut_BaseColorMetallic;
layout(set = 0, binding = 20, rgba16f) writeonly uniform image2D gOut_Emissive;
layout(set = 0, binding = 21, rg16f) writeonly uniform image2D gOut_Motion;
layout(set = 0, binding = 22, r32ui) writeonly uniform uimage2D gOut_Ids;

vec3 cameraPosition(GpuCamera c) { return c.position.xyz; }

// Motion as rg16f can hold it: beyond kMaxHalf pixels (a point right at the
// previous camera's plane) a half float would round to +inf, and motion that
// could not be computed points that far off screen too: both find no history.
vec2 storableMotion(vec2 motion) {
  return clamp(finiteOr(motion, vec2(kMaxHalf)), vec2(-kMaxHalf), vec2(kMaxHalf));
}

void writeBackground(ivec2 pixel, vec3 direction) {
  // The sky is infinitely far: only camera rotation moves it.
  vec2 size = gIn_Frame.frame.imageSize.xy;
  vec3 current = projectToPixel(gIn_Frame.frame.camera, cameraPosition(gIn_Frame.frame.camera) + direction, size);
  vec3 previous = projectToPixel(gIn_Frame.frame.previousCamera, cameraPosition(gIn_Frame.frame.previousCamera) + direction, size);
  vec2 motion = previous.z > 0.0f ? previous.xy - current.xy : vec2(0.0f);
  imageStore(gOut_ViewZ, pixel, vec4(0.0f));
  imageStore(gOut_NormalRoughness, pixel, vec4(0.0f));
  imageStore(gOut_GeometricNormal, pixel, vec4(0.0f));
  imageStore(gOut_BaseColorMetallic, pixel, vec4(0.0f));
  imageStore(gOut_Emissive, pixel, vec4(0.0f));
  imageStore(gOut_Motion, pixel, vec4(storableMotion(motion), 0.0f, 0.0f));
  imageStore(gOut_Ids, pixel, uvec4(0xffffffffu));
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  vec2 size = gIn_Frame.frame.imageSize.xy;
  if (pixel.x >= int(size.x) || pixel.y >= int(size.y)) return;

  vec3 origin = cameraPosition(gIn_Frame.frame.camera);
  vec3 direction = cameraRayDirection(gIn_Frame.frame.camera, vec2(pixel) + 0.5f + gIn_Frame.frame.jitter.xy, size);
  BvhHit hit = bvhTraceClosest(origin, direction, 0.0f, 1e30f);
  if (!(hit.t < 1e30f)) {
    writeBackground(pixel, direction);
    return;
  }

  SceneSurface surface = resolveSurface(hit, direction, hit.t * gIn_Frame.frame.jitter.z);
  GpuInstance instance = gIn_Instances.items[hit.instance];
  vec3 previousPosition = transformPoint(instance.previousObjectToWorld, surface.objectPosition);
  vec2 currentPixel = projectToPixel(gIn_Frame.frame.camera, surface.position, size).xy;
  vec3 previousPixel = projectToPixel(gIn_Frame.frame.previousCamera, previousPosition, size);
  vec2 motion = previousPixel.z > 0.0f ? previousPixel.xy - currentPixel : vec2(0.0f);

  float viewZ = dot(surface.position - origin, gIn_Frame.frame.camera.forward.xyz);
  // A hit whose shading came out non-finite (a degenerate triangle or
  // tangent frame) is stored as background: a pixel that shows the sky is
  // wrong, a G-buffer that holds NaN poisons every pass that reads it.
  if (!isFinite(viewZ) || !isFinite(vec4(surface.normal, surface.roughness)) || !isFinite(surface.geometricNormal) ||
      !isFinite(vec4(surface.baseColor, surface.metallic))) {
    writeBackground(pixel, direction);
    return;
  }
  imageStore(gOut_ViewZ, pixel, vec4(viewZ, 0.0f, 0.0f, 0.0f));
  imageStore(gOut_NormalRoughness, pixel, vec4(surface.normal, surface.roughness));
  imageStore(gOut_GeometricNormal, pixel, vec4(surface.geometricNormal, 0.0f));
  imageStore(gOut_BaseColorMetallic, pixel, vec4(surface.baseColor, surface.metallic));
  imageStore(gOut_Emissive, pixel, vec4(sanitizeRadiance(surface.emissive), 0.0f));
  imageStore(gOut_Motion, pixel, vec4(storableMotion(motion), 0.0f, 0.0f));
  imageStore(gOut_Ids, pixel, uvec4((instance.ids.x << 16) | (surface.material & 0xffffu)));
}
