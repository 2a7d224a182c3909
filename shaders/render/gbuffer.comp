#version 460
#extension GL_GOOGLE_include_directive : require
// render.gbuffer: one primary ray per pixel (through the pixel centre plus
// this frame's jitter) into the scene's BVH, writing everything a GI pass
// needs about the visible surface. Conventions: docs/conventions.md.
#include "render/scene_access.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 16, r32f) writeonly uniform image2D gOut_ViewZ;
layout(set = 0, binding = 17, rgba16f) writeonly uniform image2D gOut_NormalRoughness;
layout(set = 0, binding = 18, rgba16f) writeonly uniform image2D gOut_GeometricNormal;
layout(set = 0, binding = 19, rgba8) writeonly uniform image2D gOut_BaseColorMetallic;
layout(set = 0, binding = 20, rgba16f) writeonly uniform image2D gOut_Emissive;
layout(set = 0, binding = 21, rg16f) writeonly uniform image2D gOut_Motion;
layout(set = 0, binding = 22, r32ui) writeonly uniform uimage2D gOut_Ids;

vec3 cameraPosition(GpuCamera c) { return c.position.xyz; }

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
  imageStore(gOut_Motion, pixel, vec4(motion, 0.0f, 0.0f));
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

  GpuInstance instance = gIn_Instances.items[hit.instance];
  uvec4 triangle = gIn_BvhTriangles.items[hit.triangle];
  GpuMaterial material = gIn_Materials.items[triangle.w & 0x7fffffffu];
  vec2 bary = hit.barycentrics;

  vec3 p0 = gIn_BvhPositions.items[triangle.x].xyz;
  vec3 p1 = gIn_BvhPositions.items[triangle.y].xyz;
  vec3 p2 = gIn_BvhPositions.items[triangle.z].xyz;
  vec3 objectPosition = barycentricMix(p0, p1, p2, bary);
  vec3 position = transformPoint(instance.objectToWorld, objectPosition);

  // Geometric normal, facing the camera: surfaces are shaded on whichever
  // side the ray sees (single-sided culling would need closed meshes).
  vec3 worldEdge1 = transformVector(instance.objectToWorld, p1 - p0);
  vec3 worldEdge2 = transformVector(instance.objectToWorld, p2 - p0);
  vec3 areaNormal = cross(worldEdge1, worldEdge2);
  vec3 geometricNormal = normalize(areaNormal);
  bool backFace = dot(geometricNormal, direction) > 0.0f;
  if (backFace) geometricNormal = -geometricNormal;

  uvec4 a0 = gIn_VertexAttributes.items[triangle.x];
  uvec4 a1 = gIn_VertexAttributes.items[triangle.y];
  uvec4 a2 = gIn_VertexAttributes.items[triangle.z];
  vec2 uv0 = vec2(uintBitsToFloat(a0.z), uintBitsToFloat(a0.w));
  vec2 uv1 = vec2(uintBitsToFloat(a1.z), uintBitsToFloat(a1.w));
  vec2 uv2 = vec2(uintBitsToFloat(a2.z), uintBitsToFloat(a2.w));
  vec2 uv = barycentricMix(uv0, uv1, uv2, bary);

  // Texture level from a ray cone (Akenine-Moller et al., Ray Tracing Gems
  // ch. 20): the cone's width at the hit, stretched by the viewing angle,
  // mapped to uv units by the triangle's uv-to-world area ratio.
  float worldArea = length(areaNormal);
  vec2 du1 = uv1 - uv0, du2 = uv2 - uv0;
  float uvArea = abs(du1.x * du2.y - du1.y * du2.x);
  float coneWidth = hit.t * gIn_Frame.frame.jitter.z;
  float cosine = max(abs(dot(geometricNormal, direction)), 1e-3f);
  float uvFootprint = 0.5f * log2(max(uvArea, 1e-20f) / max(worldArea, 1e-20f)) + log2(coneWidth / cosine);

  vec4 baseColor = material.baseColorFactor;
  if (material.textures.x != kNoTexture) baseColor *= sampleAtlas(material.textures.x, uv, uvFootprint);
  float metallic = material.factors.x;
  float roughness = material.factors.y;
  if (material.textures.y != kNoTexture) {
    vec4 mr = sampleAtlas(material.textures.y, uv, uvFootprint);
    roughness *= mr.y;
    metallic *= mr.z;
  }
  vec3 emissive = material.emissive.xyz;
  if (material.textures.w != kNoTexture) emissive *= sampleAtlas(material.textures.w, uv, uvFootprint).xyz;

  vec3 objectNormal = barycentricMix(unpackNormalOct32(a0.x), unpackNormalOct32(a1.x), unpackNormalOct32(a2.x), bary);
  vec3 normal = normalize(transformVector(instance.normalToWorld, objectNormal));
  if (backFace) normal = -normal;
  if (material.textures.z != kNoTexture) {
    uint packedTangent = a0.y;  // handedness is per triangle in practice; take the first vertex's
    vec3 objectTangent =
        barycentricMix(unpackNormalOct32(a0.y), unpackNormalOct32(a1.y), unpackNormalOct32(a2.y), bary);
    float handedness = (packedTangent & 1u) != 0u ? -1.0f : 1.0f;
    vec3 tangent = transformVector(instance.objectToWorld, objectTangent);
    tangent = tangent - normal * dot(normal, tangent);
    if (dot(tangent, tangent) > 1e-12f) {
      tangent = normalize(tangent);
      vec3 bitangent = cross(normal, tangent) * handedness * (backFace ? -1.0f : 1.0f);
      vec3 t = sampleAtlas(material.textures.z, uv, uvFootprint).xyz * 2.0f - 1.0f;
      t.xy *= material.factors.z;
      vec3 mapped = tangent * t.x + bitangent * t.y + normal * max(t.z, 0.0f);
      if (dot(mapped, mapped) > 1e-12f) normal = normalize(mapped);
    }
  }
  // A shading normal facing away from the camera makes black pixels; bend it
  // back to just above the view horizon.
  float facing = dot(normal, -direction);
  if (facing < 1e-3f) normal = normalize(normal + direction * (facing - 1e-3f));

  vec3 previousPosition = transformPoint(instance.previousObjectToWorld, objectPosition);
  vec2 currentPixel = projectToPixel(gIn_Frame.frame.camera, position, size).xy;
  vec3 previousPixel = projectToPixel(gIn_Frame.frame.previousCamera, previousPosition, size);
  vec2 motion = previousPixel.z > 0.0f ? previousPixel.xy - currentPixel : vec2(0.0f);

  float viewZ = dot(position - origin, gIn_Frame.frame.camera.forward.xyz);
  imageStore(gOut_ViewZ, pixel, vec4(viewZ, 0.0f, 0.0f, 0.0f));
  imageStore(gOut_NormalRoughness, pixel, vec4(normal, clamp(roughness, 0.0f, 1.0f)));
  imageStore(gOut_GeometricNormal, pixel, vec4(geometricNormal, 0.0f));
  imageStore(gOut_BaseColorMetallic, pixel, vec4(clamp(baseColor.xyz, 0.0f, 1.0f), clamp(metallic, 0.0f, 1.0f)));
  imageStore(gOut_Emissive, pixel, vec4(emissive, 0.0f));
  imageStore(gOut_Motion, pixel, vec4(motion, 0.0f, 0.0f));
  imageStore(gOut_Ids, pixel, uvec4((instance.ids.x << 16) | (triangle.w & 0xffffu)));
}
