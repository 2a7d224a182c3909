#include <filesystem>
#include <stdexcept>

#include "app/commands.h"
#include "scene/builtin_scenes.h"
#include "scene/gltf_import.h"

namespace bounce::app {

scene::Scene loadSceneArgument(const std::string& argument) {
  if (argument.empty()) return scene::makeBuiltinScene(scene::defaultBuiltinScene());
  if (scene::isBuiltinScene(argument)) return scene::makeBuiltinScene(argument);
  const std::filesystem::path path(argument);
  const std::string extension = path.extension().string();
  if (extension != ".gltf" && extension != ".glb") {
    std::string names;
    for (const std::string& name : scene::builtinSceneNames()) names += (names.empty() ? "" : ", ") + name;
    throw std::runtime_error("scene '" + argument + "' is neither a built-in scene (" + names +
                             ") nor a .gltf/.glb file");
  }
  scene::Scene scene = scene::loadGltf(path);
  scene::adoptDirectionalLightAsSun(scene);
  return scene;
}

}  // namespace bounce::app
