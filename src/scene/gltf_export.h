// glTF 2.0 export of the scene model (scene.h), so that a scene edited in
// Bounce (its materials, say) can be saved and loaded again, by Bounce or
// by any glTF tool, looking the same.
//
// What is written: every mesh (positions, normals, tangents, texcoord set 0,
// 32-bit indices), every material with all its factors (and
// KHR_materials_emissive_strength when the emission needs it), every texture
// as a PNG of its exact texels, the node hierarchy with its local
// transforms, the displayed scene's roots, node animations, perspective
// cameras and the KHR_lights_punctual lights that nodes hold.
//
// What glTF cannot hold directly travels as standard glTF too:
//   - the sun becomes a directional light on a node named "sun" (its -Z
//     pointing along the sunlight), which loading in Bounce adopts as the
//     sun again (scene::adoptDirectionalLightAsSun); a scene without sun
//     gets one of intensity 0 there, which lights nothing and keeps the sky
//     black, as the scene had it;
//   - a built-in scene's suggested camera becomes a camera node named
//     "suggested view" when the scene has no camera of its own, so the
//     default view is the same.
// Scene meshes are glTF primitives; the meshes a node lists become one glTF
// mesh (the importer's order and count come back when, as in imported and
// built-in scenes, a node's meshes are consecutive and no other node lists
// some of them; otherwise a node's list is written as an extra glTF mesh).
// Meshes without a triangle are left out, as the importer leaves them out.
#pragma once

#include <filesystem>

#include "scene/scene.h"

namespace bounce::scene {

// What writeGltf does where a file it would write exists: Replace it (a
// regular file; a symbolic link is never replaced), or Refuse before any
// file is written (the viewer's save-gltf, which never writes over a file).
enum class ExistingFiles { Replace, Refuse };

// Writes `scene` to `file`: a .glb (everything in one file) when its
// extension is ".glb"; for ".gltf", the JSON with "<stem>.bin" (the buffer)
// and "<stem>.texture<N>.png" (texture N) beside it. Each file is written
// beside its place and renamed into it, so a failed write leaves no half
// file. Throws SceneError "<file>: <reason>" for another extension, a
// folder that does not exist or cannot be written, a file to write that is
// one of the scene's own source files (scene.source, or a buffer or image
// it reads), which an export must never overwrite, a symbolic link where a
// file goes, and, with ExistingFiles::Refuse, any of the files that exists
// (the .bin and textures as much as the .gltf: they are someone's too).
void writeGltf(const Scene& scene, const std::filesystem::path& file,
               ExistingFiles existing = ExistingFiles::Replace);

}  // namespace bounce::scene
