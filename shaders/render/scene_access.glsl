// The scene as the frame renderer's passes see it: frame constants,
// materials, instances, vertex attributes and textures, plus the BVH with
// its alpha test. Included by every pass that traces rays into the scene, so
// the bindings and the alpha-test rule are written once.
//
// Bindings 0-5 are taken here and the BVH's follow from 6
// (BVH_FIRST_BINDING); a pass's own bindings start at 16.
#ifndef BOUNCE_RENDER_SCENE_ACCESS_GLSL
#define BOUNCE_RENDER_SCENE_ACCESS_GLSL

#include "render/frame_types.glsl"
#include "shared/packing.glsl"

layout(set = 0, binding = 0, std140) uniform FrameBlock { FrameConstants frame; } gIn_Frame;
layout(set = 0, binding = 1, std430) readonly buffer Materials { GpuMaterial items[]; } gIn_Materials;
layout(set = 0, binding = 2, std430) readonly buffer Instances { GpuInstance items[]; } gIn_Instances;
// Per vertex: x = octahedral normal, y = octahedral tangent whose lowest bit
// is the bitangent sign (1 = negative), z/w = texcoord as float bits.
layout(set = 0, binding = 3, std430) readonly buffer VertexAttributes { uvec4 items[]; } gIn_VertexAttributes;
#define TEXTURE_ATLAS_BINDING 4
#include "render/texture_atlas.glsl"

bool sceneAlphaTest(uint instance, uint triangle, vec2 barycentrics);
#define BVH_FIRST_BINDING 6
#define BVH_ALPHA_TEST(instance, triangle, barycentrics) sceneAlphaTest(instance, triangle, barycentrics)
#include "render/bvh_trace.glsl"

vec2 vertexTexcoord(uint vertex) {
  uvec4 a = gIn_VertexAttributes.items[vertex];
  return vec2(uintBitsToFloat(a.z), uintBitsToFloat(a.w));
}

vec3 barycentricMix(vec3 a, vec3 b, vec3 c, vec2 bary) { return a * (1.0f - bary.x - bary.y) + b * bary.x + c * bary.y; }
vec2 barycentricMix(vec2 a, vec2 b, vec2 c, vec2 bary) { return a * (1.0f - bary.x - bary.y) + b * bary.x + c * bary.y; }

uint triangleMaterial(uint triangle) { return gIn_BvhTriangles.items[triangle].w & 0x7fffffffu; }

// Alpha-masked triangles are transparent where base-colour alpha is below the
// cutoff. Sampled at mip 0: shadow and primary rays must agree on the
// silhouette, and any-hit rays have no footprint to choose a level from.
bool sceneAlphaTest(uint instance, uint triangle, vec2 barycentrics) {
  GpuMaterial material = gIn_Materials.items[triangleMaterial(triangle)];
  if (material.emissive.w < 0.0f) return true;
  float alpha = material.baseColorFactor.w;
  if (material.textures.x != kNoTexture) {
    uvec4 t = gIn_BvhTriangles.items[triangle];
    vec2 uv = barycentricMix(vertexTexcoord(t.x), vertexTexcoord(t.y), vertexTexcoord(t.z), barycentrics);
    alpha *= sampleAtlas(material.textures.x, uv, -100.0f).w;
  }
  return alpha >= material.emissive.w;
}

#endif
