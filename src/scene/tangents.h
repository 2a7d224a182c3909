// Normal and tangent generation for triangle meshes: what the glTF importer
// does when a file leaves them out, and what built-in scenes use so that their
// meshes look exactly like imported ones.
//
// Tangent convention (glTF): tangent.xyz points along increasing u, and
// bitangent = cross(normal, tangent.xyz) * tangent.w points along increasing
// v *of the image seen upright*, i.e. along decreasing glTF v, since glTF puts
// v = 0 at the top row. That is the "+Y up" of glTF normal maps, and what
// MikkTSpace tangents exported by Blender and others give.
#pragma once

#include <cstddef>

#include "scene/scene.h"

namespace bounce::scene {

// Replaces the mesh by an un-indexed copy (three vertices per triangle) whose
// normals are the geometric normals of the triangles (counter-clockwise
// front), as glTF asks for meshes without normals. Texture coordinates and
// tangents, where present, are copied along. A degenerate triangle gets +Z.
void generateFlatNormals(Mesh& mesh);

// Fills mesh.tangents (one per vertex) from the derivatives of texcoords
// across each triangle, averaged (area weighted) over the triangles around a
// vertex and orthonormalised against the normal; w = handedness (+1 or -1).
// A vertex shared by triangles of opposite handedness (a mirrored UV seam) is
// split in two, as MikkTSpace does, so both sides shade correctly; this may
// append vertices and rewrite indices. Where texcoords are missing or
// degenerate the tangent is a stable arbitrary unit vector perpendicular to
// the normal, with w = +1. Never NaN, even for NaN input (which validate()
// then refuses). Requires mesh.normals to hold one normal per vertex.
void generateTangents(Mesh& mesh);

// Makes every normal unit length. Normals that are zero, tiny or not finite
// are replaced by the area-weighted normal of the triangles around the vertex
// (+Z when there is none). Returns how many normals had to be replaced or
// rescaled by more than a rounding error.
std::size_t normalizeNormals(Mesh& mesh);

// Makes given tangents unit length and perpendicular to their normals, with
// w exactly +1 or -1; a tangent that is zero, not finite or parallel to its
// normal becomes the stable arbitrary tangent. Returns how many were replaced.
std::size_t orthonormalizeTangents(Mesh& mesh);

}  // namespace bounce::scene
