// The scene as the frame renderer's passes see it: frame constants,
// materials, instances, vertex attributes and textures, plus the BVH with
// its alpha test. Included by every pass that traces rays into the scene, so
// the bindings and the alpha-test rule are written once.
//
// Bindings SCENE_FIRST_BINDING + 0..5 are taken here and the BVH's follow
// from + 6 (BVH_FIRST_BINDING); a pass's own bindings start at 16. A shader
// that has bindings of its own there (the GI library's, through the scene
// bridge, shaders/render/scene_bridge/) defines SCENE_FIRST_BINDING
// (default 0), SCENE_FRAME, the name of the frame block (default
// gIn_Frame), and SCENE_FRAME_STORAGE (default CONSTANT_BLOCK) before
// including this file.
#ifndef BOUNCE_RENDER_SCENE_ACCESS_GLSL
#define BOUNCE_RENDER_SCENE_ACCESS_GLSL

#ifndef SCENE_FIRST_BINDING
#define SCENE_FIRST_BINDING 0
#endif
#ifndef SCENE_FRAME
#define SCENE_FRAME gIn_Frame
#endif
// How the frame block is stored: the pass's constant block, or (the bridge)
// a storage buffer, which needs no declared layout on the host.
#ifndef SCENE_FRAME_STORAGE
#define SCENE_FRAME_STORAGE CONSTANT_BLOCK
#endif

#include "gpu/constant_block.glsl"
#include "render/frame_types.glsl"
#include "shared/packing.glsl"

layout(set = 0, binding = SCENE_FIRST_BINDING + 0, std140) SCENE_FRAME_STORAGE SceneFrameBlock { FrameConstants frame; } SCENE_FRAME;
layout(set = 0, binding = SCENE_FIRST_BINDING + 1, std430) readonly buffer Materials { GpuMaterial items[]; } gIn_Materials;
layout(set = 0, binding = SCENE_FIRST_BINDING + 2, std430) readonly buffer Instances { GpuInstance items[]; } gIn_Instances;
// Per vertex: x = octahedral normal, y = octahedral tangent whose lowest bit
// is the bitangent sign (1 = negative), z/w = texcoord as float bits.
layout(set = 0, binding = SCENE_FIRST_BINDING + 3, std430) readonly buffer VertexAttributes { uvec4 items[]; } gIn_VertexAttributes;
#define TEXTURE_ATLAS_BINDING (SCENE_FIRST_BINDING + 4)
#include "render/texture_atlas.glsl"

bool sceneAlphaTest(uint instance, uint triangle, vec2 barycentrics);
#define BVH_FIRST_BINDING (SCENE_FIRST_BINDING + 6)
#define BVH_ALPHA_TEST(instance, triangle, barycentrics) sceneAlphaTest(instance, triangle, barycentrics)
#include "render/bvh_trace.glsl"

vec2 vertexTexcoord(uint vertex) {
  uvec4 a = gIn_VertexAttributes.items[vertex];
  return vec2(uintBitsToFloat(a.z), uintBitsToFloat(a.w));
}

vec3 barycentricMix(vec3 a, vec3 b, vec3 c, vec2 bary) { return a * (1.0f - bary.x - bary.y) + b * bary.x + c * bary.y; }
vec2 barycentricMix(vec2 a, vec2 b, vec2 c, vec2 bary) { return a * (1.0f - bary.x - bary.y) + b * bary.x + c * bary.y; }

uint triangleMaterial(uint triangle) { return bvhTriangle(triangle).w & 0x7fffffffu; }

// Alpha-masked triangles are transparent where base-colour alpha is below the
// cutoff. Sampled at mip 0: shadow and primary rays must agree on the
// silhouette, and any-hit rays have no footprint to choose a level from.
bool sceneAlphaTest(uint instance, uint triangle, vec2 barycentrics) {
  GpuMaterial material = gIn_Materials.items[triangleMaterial(triangle)];
  if (material.emissive.w < 0.0f) return true;
  float alpha = material.baseColorFactor.w;
  if (material.textures.x != kNoTexture) {
    uvec4 t = bvhTriangle(triangle);
    vec2 uv = barycentricMix(vertexTexcoord(t.x), vertexTexcoord(t.y), vertexTexcoord(t.z), barycentrics);
    alpha *= sampleAtlas(material.textures.x, uv, -100.0f).w;
  }
  return alpha >= material.emissive.w;
}

// Everything about a surface a ray hit: position, normals (the shading one
// normal-mapped and facing the ray's origin), and material with textures
// filtered at the level of a ray cone `coneWidth` wide at the hit.
struct SceneSurface {
  vec3 position;
  vec3 objectPosition;  // for the previous frame's transform (motion vectors)
  vec3 geometricNormal;
  vec3 normal;
  vec3 baseColor;
  float metallic;
  float roughness;
  vec3 emissive;
  uint instance;
  uint material;
};

SceneSurface resolveSurface(BvhHit hit, vec3 direction, float coneWidth) {
  GpuInstance instance = gIn_Instances.items[hit.instance];
  uvec4 triangle = bvhTriangle(hit.triangle);
  GpuMaterial material = gIn_Materials.items[triangle.w & 0x7fffffffu];
  vec2 bary = hit.barycentrics;

  vec3 p0 = bvhVertexPosition(triangle.x);
  vec3 p1 = bvhVertexPosition(triangle.y);
  vec3 p2 = bvhVertexPosition(triangle.z);
  vec3 objectPosition = barycentricMix(p0, p1, p2, bary);
  vec3 position = transformPoint(instance.objectToWorld, objectPosition);

  // Geometric normal, facing the ray's origin: surfaces are shaded on
  // whichever side the ray sees (single-sided culling would need closed meshes).
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
  // A single-sided emitter (glTF doubleSided false) emits from its front
  // face only; surfaces are otherwise shaded on either side.
  if (backFace && material.factors.w < 0.5f) emissive = vec3(0.0f);

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
  // A shading normal facing away from the ray makes black pixels; bend it
  // back to just above the ray's horizon.
  float facing = dot(normal, -direction);
  if (facing < 1e-3f) normal = normalize(normal + direction * (facing - 1e-3f));


  SceneSurface surface;
  surface.position = position;
  surface.objectPosition = objectPosition;
  surface.geometricNormal = geometricNormal;
  surface.normal = normal;
  surface.baseColor = clamp(baseColor.xyz, 0.0f, 1.0f);
  surface.metallic = clamp(metallic, 0.0f, 1.0f);
  surface.roughness = clamp(roughness, 0.0f, 1.0f);
  surface.emissive = emissive;
  surface.instance = hit.instance;
  surface.material = triangle.w & 0x7fffffffu;
  return surface;
}

#endif
