// glTF 2.0 import (.gltf with external or embedded buffers, and .glb) into the
// scene model of scene.h.
//
// What is read: the displayed scene (the file's default scene, else scene 0,
// else every parentless node) with its node hierarchy and transforms (matrices
// decomposed into translation, rotation, scale); triangle primitives (strips
// and fans become lists; points and lines are skipped with a warning);
// positions, normals, tangents and texcoord set 0 (missing normals become
// flat normals, missing tangents are generated); metallic-roughness materials
// with their five textures, alpha mode and KHR_materials_emissive_strength;
// textures decoded from PNG or JPEG to RGBA8 (only those materials use);
// KHR_lights_punctual lights; perspective cameras; node animations.
//
// What is refused, with a SceneError whose what() starts with the file path:
// anything malformed (JSON, JSON nested deeper than 64 levels, schema types,
// out-of-range indices or accessor ranges, missing files, buffer or image
// URIs outside the file's folder, NaN or infinite geometry, cycles in the
// node graph)
// and files that require an extension this importer does not implement.
// Everything else it cannot use (optional extensions, orthographic cameras,
// skins, morph targets, vertex colours, ...) is reported through
// GltfImportOptions::warn, one line per kind of problem.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "scene/scene.h"

namespace bounce::scene {

struct GltfImportOptions {
  // Receives one line per warning (without a trailing newline). Empty: print
  // "bounce: warning: <line>" to stderr.
  std::function<void(const std::string&)> warn;
  // Buffer and image files are read from the glTF file's folder only: a URI
  // that leads elsewhere (an absolute path, ".." above the folder, a symlink
  // pointing out of it) is refused, with the same message whether or not
  // the file it names exists. True reads such files (`--allow-outside-assets`).
  // A URI with a NUL byte is refused either way.
  bool allowOutsideAssets = false;
};

// Loads a .gltf or .glb file (recognised by its content, not its extension)
// and returns a scene that has passed validate(). Throws SceneError
// "<path>: <reason>".
Scene loadGltf(const std::filesystem::path& path, const GltfImportOptions& options = {});

}  // namespace bounce::scene
