#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "app/commands.h"
#include "app/option_checks.h"
#include "scene/builtin_scenes.h"
#include "scene/gltf_import.h"
#include "util/parse_number.h"
#include "util/printable.h"

namespace bounce::app {

scene::Scene loadSceneArgument(const std::string& argument, const scene::GltfImportOptions& importOptions) {
  if (argument.empty()) return scene::makeBuiltinScene(scene::defaultBuiltinScene());
  if (scene::isBuiltinScene(argument)) return scene::makeBuiltinScene(argument);
  const std::filesystem::path path(argument);
  const std::string extension = path.extension().string();
  if (extension != ".gltf" && extension != ".glb") {
    std::string names;
    for (const std::string& name : scene::builtinSceneNames()) names += (names.empty() ? "" : ", ") + name;
    throw UsageError("scene '" + argument + "' is neither a built-in scene (" + names + ") nor a .gltf/.glb file");
  }
  scene::Scene scene = scene::loadGltf(path, importOptions);
  scene::adoptDirectionalLightAsSun(scene);
  return scene;
}

namespace {

// Comma-separated finite numbers, exactly `count` of them, each in [min, max].
std::vector<float> parseNumbers(const std::string& text, std::size_t count, float min, float max,
                                const std::string& what) {
  std::vector<float> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    // "1, 0.5, 0" as well as "1,0.5,0".
    const std::size_t first = item.find_first_not_of(' '), last = item.find_last_not_of(' ');
    item = first == std::string::npos ? std::string() : item.substr(first, last - first + 1);
    const std::optional<double> number = util::parseFiniteNumber(item);
    if (!number) throw UsageError(what + ": '" + item + "' is not a number");
    if (*number < double(min) || *number > double(max)) {
      char range[64];
      std::snprintf(range, sizeof range, "[%g, %g]", double(min), double(max));
      throw UsageError(what + ": " + item + " is outside " + range);
    }
    values.push_back(float(*number));
  }
  if (values.size() != count)
    throw UsageError(what + ": wants " + std::to_string(count) + (count == 1 ? " number" : " numbers") + ", got " +
                     std::to_string(values.size()));
  return values;
}

}  // namespace

void applyMaterialChange(scene::Scene& scene, const std::string& change, const std::string& flag) {
  const std::string what = flag + " " + change;
  const std::size_t colon = change.rfind(':');
  const std::size_t equals = change.find('=', colon == std::string::npos ? 0 : colon);
  if (colon == std::string::npos || equals == std::string::npos || colon == 0)
    throw UsageError(what + ": expected NAME:KEY=VALUE, e.g. 'oak floor:roughness=0.1'");
  const std::string name = change.substr(0, colon);
  const std::string key = change.substr(colon + 1, equals - colon - 1);
  const std::string value = change.substr(equals + 1);
  // glTF does not make names unique, and exporters repeat one when they
  // split a material per primitive, so a name can stand for several
  // materials. Every material of the name is changed, and a warning says
  // how many and which: the user names what they see as one material, and
  // changing one of its copies (as happened, without a word) draws a
  // picture nobody asked for; refusing would leave no way to change them
  // at all, since --material has no other way to name a material.
  std::vector<std::size_t> matching;
  for (std::size_t i = 0; i < scene.materials.size(); ++i)
    if (scene.materials[i].name == name) matching.push_back(i);
  if (matching.empty()) {
    std::string names;
    for (const scene::Material& m : scene.materials) names += (names.empty() ? "'" : ", '") + m.name + "'";
    throw UsageError(what + ": the scene has no material '" + name + "' (it has " + names + ")");
  }
  for (const std::size_t index : matching) {
    scene::Material& material = scene.materials[index];
    if (key == "roughness") {
      material.roughnessFactor = parseNumbers(value, 1, 0.0f, 1.0f, what)[0];
    } else if (key == "metallic") {
      material.metallicFactor = parseNumbers(value, 1, 0.0f, 1.0f, what)[0];
    } else if (key == "base_color") {
      const std::vector<float> rgb = parseNumbers(value, 3, 0.0f, 1.0f, what);
      material.baseColorFactor = glm::vec4(rgb[0], rgb[1], rgb[2], material.baseColorFactor.w);
    } else if (key == "emission") {
      const std::vector<float> rgb = parseNumbers(value, 3, 0.0f, 1e20f, what);
      material.emissiveFactor = glm::vec3(rgb[0], rgb[1], rgb[2]);
    } else {
      throw UsageError(what + ": unknown key '" + key + "' (roughness, metallic, base_color, emission)");
    }
  }
  if (matching.size() > 1) {
    std::string indices;
    for (std::size_t i = 0; i < matching.size(); ++i)
      indices += (i == 0 ? "" : i + 1 == matching.size() ? " and " : ", ") + std::to_string(matching[i]);
    std::fprintf(stderr, "bounce: warning: %s\n",
                 util::printable(what + ": " + std::to_string(matching.size()) + " materials are named '" + name +
                                 "' (materials " + indices + "); all of them were changed")
                     .c_str());
  }
}

std::vector<std::filesystem::path> inputFiles(const scene::Scene& scene, const SceneOptions& options,
                                              const GiOptions* gi) {
  std::vector<std::filesystem::path> files = scene.files;
  std::error_code error;
  // --camera is a preset's name or a keyframe file; only a file is an input.
  if (!options.camera.empty() && std::filesystem::exists(options.camera, error)) files.push_back(options.camera);
  if (!options.env.empty()) files.push_back(options.env);
  if (gi && !gi->settingsFile.empty()) files.push_back(gi->settingsFile);
  return files;
}

scene::Scene loadScene(const SceneOptions& options) {
  scene::Scene scene = loadSceneArgument(options.scene, {.allowOutsideAssets = options.allowOutsideAssets});
  for (const std::string& change : options.materials) applyMaterialChange(scene, change);
  return scene;
}

void addAllowOutsideAssetsFlag(CLI::App& command, bool& allowOutsideAssets) {
  command.add_flag("--allow-outside-assets", allowOutsideAssets,
                   "Let a glTF file's buffer and image URIs name files outside its folder (absolute paths, '..', "
                   "symlinks leading out); refused by default, so a downloaded scene cannot read other files");
}

void addOverwriteFlag(CLI::App& command, bool& overwrite) {
  command.add_flag("--overwrite", overwrite,
                   "Replace files in OUT that no Bounce run wrote (by default such a file stops the run before it "
                   "starts; files an earlier run wrote, listed in OUT/.bounce-written, are always replaced)");
}

void addSceneOptions(CLI::App& command, SceneOptions& options) {
  std::string names;
  for (const std::string& n : scene::builtinSceneNames()) names += (names.empty() ? "" : ", ") + n;
  command.add_option(
      "scene", options.scene,
      "Built-in scene (" + names + "; default " + scene::defaultBuiltinScene() + ") or a .gltf/.glb file");
  command.add_option("--camera", options.camera,
                     "Camera path: orbit, dolly, fly, static, gltf (the first glTF camera), gltf:N (the N-th, from 0), "
                     "gltf:NAME (by node or camera name), or a JSON keyframe file (default: the scene's first glTF "
                     "camera, else its suggested view)");
  command.add_option("--width", options.width, "Image width in pixels")
      ->check(CLI::Range(1u, 16384u))
      ->capture_default_str();
  command.add_option("--height", options.height, "Image height in pixels")
      ->check(CLI::Range(1u, 16384u))
      ->capture_default_str();
  command.add_option("--fps", options.fps, "Frames per second of scene time (animation and camera)")
      ->check(finiteRange(0.001, 10000.0));
  command.add_option("--env", options.env, "Equirectangular environment map (.exr/.hdr); default: procedural sky");
  command
      .add_option("--env-intensity", options.envIntensity,
                  "Multiplier of the environment (at most 1e20, also times the sun's illuminance for the sky)")
      ->check(finiteAtLeast(0.0));
  command.add_option("--env-rotation", options.envRotation, "Rotation of the environment map about +Y, degrees")
      ->check(finiteNumber());
  command.add_option("--sun-elevation", options.sunElevation, "Sun elevation above the horizon, degrees")
      ->check(finiteRange(-90.0, 90.0));
  command.add_option("--sun-azimuth", options.sunAzimuth, "Sun azimuth from +Z towards +X, degrees")
      ->check(finiteNumber());
  command.add_flag("--no-sun", options.noSun,
                   "No sunlight (e.g. when the --env map already shows its sun, which would then count twice)");
  addAllowOutsideAssetsFlag(command, options.allowOutsideAssets);
  command.add_option("--material", options.materials,
                     "Change a material's factor before rendering, NAME:KEY=VALUE (repeatable): roughness=R, "
                     "metallic=M (0..1), base_color=R,G,B (0..1), emission=R,G,B (radiance); a texture still "
                     "multiplies the factor, e.g. --material 'oak floor:roughness=0.1'");
}

std::unique_ptr<scene::CameraPath> cameraPathOf(const scene::Scene& scene, const SceneOptions& options) {
  return options.camera.empty() ? scene::defaultCameraPath(scene) : scene::makeCameraPath(options.camera, scene);
}

std::vector<scene::CameraFrame> checkedCameraFrames(const scene::CameraPath& path, std::uint32_t firstFrame,
                                                    std::uint32_t count, const SceneOptions& options) {
  std::vector<scene::CameraFrame> frames = scene::sampleCameraFrames(path, firstFrame, count, options.fps);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    try {
      render::checkCamera(frames[i].pose);
    } catch (const std::exception& problem) {
      const std::uint64_t frame = firstFrame + i;
      char time[32];
      std::snprintf(time, sizeof time, "%g", double(float(frame) / options.fps));
      const std::string scene = options.scene.empty() ? scene::defaultBuiltinScene() : options.scene;
      const std::string path = options.camera.empty() ? scene + "'s camera" : "--camera " + options.camera;
      throw std::runtime_error(path + ": frame " + std::to_string(frame) + " (at " + time + " s): " + problem.what());
    }
  }
  return frames;
}

render::FrameRendererOptions frameRendererOptions(const scene::Scene& scene, const SceneOptions& options) {
  render::FrameRendererOptions rendererOptions;
  rendererOptions.width = options.width;
  rendererOptions.height = options.height;
  render::EnvironmentDesc& environment = rendererOptions.environment;
  environment.map = options.env;
  environment.intensity = options.envIntensity;
  environment.rotationDegrees = options.envRotation;
  environment.sun = scene.sun;
  environment.hasSun = scene.hasSun;
  if (options.sunElevation) {
    environment.sun.elevationDegrees = *options.sunElevation;
    environment.hasSun = true;
  }
  if (options.sunAzimuth) environment.sun.azimuthDegrees = *options.sunAzimuth;
  if (options.noSun) {
    if (options.sunElevation || options.sunAzimuth)
      throw UsageError("--no-sun contradicts --sun-elevation/--sun-azimuth");
    environment.hasSun = false;
  }
  // Refused here, before anything is rendered, with the option's name.
  if (const std::string problem = render::environmentIntensityProblem(environment); !problem.empty()) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", double(environment.intensity));
    throw UsageError(std::string("--env-intensity ") + value + " " + problem);
  }
  return rendererOptions;
}

}  // namespace bounce::app
