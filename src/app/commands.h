// The bounce subcommands. Each registers its options on the CLI and runs
// when chosen; run functions return the process exit code and throw on errors
// (main prints one line and exits non-zero).
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bounce/gi.h"
#include "bounce/gi_settings.h"
#include "gpu/context.h"
#include "render/frame_renderer.h"
#include "scene/camera_path.h"
#include "scene/gltf_import.h"
#include "scene/scene.h"

namespace bounce::app {

// The most frames of a camera path a command renders or picks from: over
// nine hours at 30 fps, and few enough that every frame's time is exact as a
// float and every frame's pose fits in memory.
constexpr std::uint32_t kMaxFrames = 1000000;

struct GpuOptions {
  std::optional<int> device;
  bool validate = false;
};
void addGpuOptions(CLI::App& command, GpuOptions& options);
std::unique_ptr<gpu::Context> openContext(const GpuOptions& options);
// 0 when validation is off or silent; otherwise prints how many messages
// there were and returns 1, so a validated run fails on any message.
int validationExitCode(const gpu::Context& context);
// Throws when the buffers and images made so far for a width x height frame
// do not fit the device's largest device-local heap: Vulkan may still hand
// out the memory (lavapipe does, lazily), and the frame would then crawl or
// be killed by the system long after the command started.
void checkDeviceMemoryFits(const gpu::Context& context, std::uint32_t width, std::uint32_t height);
// (Before anything of a frame is made, render::requireFrameMemory refuses a
// frame whose images alone do not fit; this then counts the scene too.)

// A SCENE argument: a built-in name, a .gltf/.glb path, or empty for the
// default built-in. A glTF directional light becomes the sun.
scene::Scene loadSceneArgument(const std::string& argument, const scene::GltfImportOptions& importOptions);
// --allow-outside-assets, for every command that takes a SCENE argument.
void addAllowOutsideAssetsFlag(CLI::App& command, bool& allowOutsideAssets);
// --overwrite, for every command that fills an output folder (OutputFolder,
// app/output_files.h).
void addOverwriteFlag(CLI::App& command, bool& overwrite);

// What a rendering command renders: the scene, the camera path, the image
// size and the lighting (sky or map, sun). Shared by render and reference.
struct SceneOptions {
  std::string scene;   // built-in name or .gltf/.glb path; empty = the default built-in
  std::string camera;  // preset name or JSON keyframe file; empty = the scene's own camera
  std::uint32_t width = 960;
  std::uint32_t height = 540;
  float fps = 30.0f;
  std::string env;  // equirect HDR/EXR; empty = procedural sky
  float envIntensity = 1.0f;
  float envRotation = 0.0f;
  std::optional<float> sunElevation;
  std::optional<float> sunAzimuth;
  bool noSun = false;
  bool allowOutsideAssets = false;  // glTF buffers and images may come from outside the file's folder
  std::vector<std::string> materials;  // --material NAME:KEY=VALUE, in order
};
void addSceneOptions(CLI::App& command, SceneOptions& options);
// The scene the options name, with their --material changes made.
scene::Scene loadScene(const SceneOptions& options);
// Changes a material's factors as "NAME:KEY=VALUE" says (KEY: roughness,
// metallic in [0, 1]; base_color R,G,B in [0, 1]; emission R,G,B >= 0), of
// every material of that name (glTF names need not be unique; a warning
// names them when there are several); throws naming the argument and the
// problem (an unknown material lists the scene's).
// `flag` names the option in messages.
void applyMaterialChange(scene::Scene& scene, const std::string& change, const std::string& flag = "--material");
// The camera path --camera names, or the scene's own (its first glTF
// camera, else its suggested view) when none is given.
std::unique_ptr<scene::CameraPath> cameraPathOf(const scene::Scene& scene, const SceneOptions& options);
struct GiOptions;
// Every file a command reads for its scene and settings: the scene's files
// (the glTF and each buffer and image it refers to), a camera keyframe
// file, the environment map, a GI settings file. No output may be one.
std::vector<std::filesystem::path> inputFiles(const scene::Scene& scene, const SceneOptions& options,
                                              const GiOptions* gi);
// Frames first .. first + count - 1 of `path` at --fps, the camera of every
// one checked before any is rendered (render::checkCamera): a path that
// passes through its target or looks along its up vector half-way fails
// now, not after minutes of frames. Throws naming the camera path, the
// frame, its time and the problem.
std::vector<scene::CameraFrame> checkedCameraFrames(const scene::CameraPath& path, std::uint32_t first,
                                                    std::uint32_t count, const SceneOptions& options);

// The renderer options (size, environment, sun) for a loaded scene as the
// flags say; throws for contradictory flags.
render::FrameRendererOptions frameRendererOptions(const scene::Scene& scene, const SceneOptions& options);

// The GI library on the command line: --gi diffuse|off, --gi-settings
// FILE.json, and one --gi.KEY VALUE flag per key of gi::settingKeys().
struct GiOptions {
  // Which GI branches run: a comma list of diffuse and specular (the GI
  // library composites the frame), or "off" (direct light only).
  std::string mode = "diffuse,specular";
  std::string settingsFile;
  std::vector<std::pair<std::string, std::string>> overrides;  // key, value, in command-line order
  std::uint32_t warmup = 16;  // frames rendered (and thrown away) at the first camera before the first output frame
  std::string sceneBridge = "bvh";  // how the GI sees beyond the screen: none or bvh (render/scene_bridge.h)
};
// `warmup`: whether the command offers --gi-warmup (bench has its own --warmup).
void addGiOptions(CLI::App& command, GiOptions& options, bool warmup = true);
// Only --gi-settings and the --gi.KEY flags (a command that decides itself
// what runs, as denoise does).
void addGiSettingsOptions(CLI::App& command, GiOptions& options);
bool giEnabled(const GiOptions& options);
// The branch names of a --gi value ("diffuse,specular" -> diffuse, specular).
std::vector<std::string> giBranches(const std::string& mode);
// With --gi off, warns (stderr) about the GI settings given, which nothing reads.
void warnIgnoredGiOptions(const GiOptions& options);
// The settings: `base` (the defaults unless a command starts elsewhere),
// then the file, then the flags; validated.
gi::Settings giSettings(const GiOptions& options, const gi::Settings& base = {});
// The scene bridge the options ask for (none: screen space only).
gi::SceneBridge giSceneBridge(const GiOptions& options);
// The GI library's context for frames up to width x height from the frame
// renderer (its frames in flight), with the scene bridge the options ask for.
gi::ContextDesc giContextDesc(std::uint32_t width, std::uint32_t height, const GiOptions& options);
// The library's message for the first --gi.KEY flag in argv whose key is not
// a setting (naming the closest keys), or "" when every one is known. CLI11
// alone would only say the argument was not expected.
std::string unknownGiSettingFlag(int argc, const char* const* argv);

struct InfoOptions {
  GpuOptions gpu;
};
CLI::App* addInfoCommand(CLI::App& app, InfoOptions& options);
int runInfo(const InfoOptions& options);

struct RenderOptions {
  GpuOptions gpu;
  SceneOptions view;
  GiOptions gi;
  std::uint32_t frames = 1;
  std::string out = "out";
  float exposure = 1.0f;
  std::vector<std::string> aovs;
  bool hdr = false;
  bool jitter = false;
  bool dumpStages = false;
  std::vector<std::uint32_t> dumpFrames;  // empty = the last frame
  std::vector<std::uint32_t> cutFrames;   // frames flagged as camera cuts besides the path's own
  bool overwrite = false;                 // replace files in OUT that no Bounce run wrote
  // Whether the command line set the size (--width or --height) and
  // --gi-warmup: on a CPU device, what it left unset is chosen smaller
  // (kCpuQuickStart, below).
  bool sizeGiven = false;
  bool warmupGiven = false;
};
// On a CPU device (lavapipe) a frame at the default size takes seconds: a
// render that names neither size nor warm-up gets kCpuQuickStart's instead,
// so that the README's first command shows a GI image within a minute on a
// 2-core machine without a GPU.
struct QuickStart {
  std::uint32_t width, height, warmup;
};
constexpr QuickStart kCpuQuickStart{480, 270, 8};
CLI::App* addRenderCommand(CLI::App& app, RenderOptions& options);
int runRender(const RenderOptions& options);

// bounce view: the interactive viewer (cmd_view.cpp, src/viewer/).
struct ViewOptions {
  GpuOptions gpu;
  SceneOptions view;
  GiOptions gi;
  std::string script;  // empty: interactive
  bool headless = false;  // no window (needs a script): the panels drawn into an image, never presented
  std::string record;     // non-empty: write the session there as a script
  std::string out = "out";
  float exposure = 1.0f;
};
CLI::App* addViewCommand(CLI::App& app, ViewOptions& options);
int runView(const ViewOptions& options);

struct ReferenceCommandOptions {
  GpuOptions gpu;
  SceneOptions view;
  std::uint32_t frame = 0;  // of the camera path
  std::uint32_t spp = 1024;
  std::optional<double> targetRelMse;  // stop once the halves agree this well
  std::uint32_t maxBounces = 24;
  std::uint32_t seed = 0;
  std::string lobes = "all";  // all, diffuse or specular: the material lobes paths follow
  std::string out = "reference.exr";
  float exposure = 1.0f;
  bool halves = false;
  bool dumpStages = false;
  bool overwrite = false;  // replace OUT.exr's files that no Bounce run wrote
};
CLI::App* addReferenceCommand(CLI::App& app, ReferenceCommandOptions& options);
int runReference(const ReferenceCommandOptions& options);

// bounce denoise: the GI library's denoiser on a path-traced sequence at a
// few samples per pixel (cmd_denoise.cpp).
struct DenoiseOptions {
  GpuOptions gpu;
  SceneOptions view;
  GiOptions gi;                      // --gi-settings and --gi.KEY only
  std::uint32_t frames = 32;         // of the camera path; the last is measured
  std::uint32_t spp = 1;             // path samples per pixel of every frame's noisy signals
  std::uint32_t referenceSpp = 512;  // samples of the last frame's converged reference
  std::uint32_t seed = 0;
  std::uint32_t maxBounces = 24;
  std::string out = "denoise";
  float exposure = 1.0f;
  bool dumpStages = false;
  bool checkerboard = false;  // hand the signals over checkerboarded (gi.denoise.checkerboard)
  bool overwrite = false;     // replace files in OUT that no Bounce run wrote
};
CLI::App* addDenoiseCommand(CLI::App& app, DenoiseOptions& options);
int runDenoise(const DenoiseOptions& options);

// bounce ghosting: how fast the GI's error on newly uncovered pixels returns
// to the level of the rest after a fast turn or a moving object
// (cmd_ghosting.cpp; docs/metrics.md).
struct GhostingOptions {
  GpuOptions gpu;
  SceneOptions view = {.width = 640, .height = 360};
  GiOptions gi = {.warmup = 32};
  // turn (the camera turns in one frame), object (a moving object uncovers),
  // light (--light-changes at the event frame), sun (the sun turns by
  // --sun-jump degrees) or cut (a cut in place)
  std::string event = "turn";
  std::vector<std::string> lightChanges;  // --light-change NAME:KEY=VALUE, made at the event frame
  std::optional<float> sunJump;           // --event sun: degrees the sun's azimuth turns at the event frame
  std::uint32_t eventFrame = 32;        // the (first) event frame; frames 0.. lead up to it, after gi.warmup
  std::optional<std::uint32_t> events;  // event frames from eventFrame on, pooled (default: turn 1, object 8)
  std::uint32_t after = 8;              // frames measured after the event
  std::uint32_t settle = 32;            // then this many more, and the regions measured once more (0: not)
  std::optional<std::uint32_t> nearby;  // radius of the nearby rest, pixels (default: height / 40, at least 2)
  std::optional<float> turnDegrees;     // the built-in turn's angle (default kDefaultTurnDegrees)
  std::uint32_t referenceSpp = 256;     // samples of each measured frame's reference
  std::uint32_t seed = 0;
  std::uint32_t maxBounces = 24;
  double within = 1.5;  // recovered: the uncovered region's error at most this times the rest's
  std::string out = "ghosting";
  float exposure = 1.0f;
  bool overwrite = false;  // replace files in OUT that no Bounce run wrote
};
inline constexpr float kDefaultTurnDegrees = 20.0f;
inline constexpr float kDefaultSunJumpDegrees = 30.0f;
CLI::App* addGhostingCommand(CLI::App& app, GhostingOptions& options);
int runGhosting(const GhostingOptions& options);

struct BenchOptions {
  GpuOptions gpu;
  std::string scene;  // as for render
  bool allowOutsideAssets = false;
  std::uint32_t width = 1920;
  std::uint32_t height = 1080;
  std::uint32_t frames = 200;
  std::uint32_t warmup = 20;
  std::uint32_t copyMegabytes = 256;
  // What the traffic floors are measured against when the copy pass does
  // not run (--copy-mb 0): the H100's copy bandwidth as this bench measured
  // it (docs/benchmarks.md).
  double bandwidthGbps = 3000.0;
  std::uint32_t rays = 1u << 20;  // incoherent rays per frame for render.bvh_trace_rays (0 = skip)
  // Where they start: surfaces (anywhere on the triangles), visible (the
  // surfaces the camera sees) or bounds (anywhere in the scene's box).
  std::string rayOrigins = "surfaces";
  std::string json;
  std::optional<float> sunElevation;
  std::optional<float> sunAzimuth;
  GiOptions gi;
};
CLI::App* addBenchCommand(CLI::App& app, BenchOptions& options);

struct BrdfVizOptions {
  std::string out = "brdf-viz";
  bool overwrite = false;  // replace files in OUT that no Bounce run wrote
  std::uint32_t size = 256;
  std::uint32_t frames = 48;
  float fps = 12.0f;
  std::vector<float> baseColor = {1.0f, 0.78f, 0.34f};  // gold
  float metallic = 1.0f;
  float roughness = 0.4f;     // of the view sweep
  float viewDegrees = 45.0f;  // of the roughness sweep
};
CLI::App* addBrdfVizCommand(CLI::App& app, BrdfVizOptions& options);
int runBrdfViz(const BrdfVizOptions& options);

struct CompareOptions {
  // Two images (reference, then test), or with `sequence` the frames: one
  // directory or several image files.
  std::vector<std::string> images;
  bool sequence = false;
  std::string flip = "auto";  // auto (HDR-FLIP for EXR/HDR inputs, LDR-FLIP for PNG/JPEG), ldr or hdr
  std::optional<float> ppd;   // pixels per degree; default that of the FLIP tool
  std::string errorMap;       // PNG of the FLIP map (magma); empty = none
  std::string json;           // every value as JSON; empty = none
  std::string regions;        // a label image (e.g. the G-buffer's ids.exr): the numbers per label too; empty = none
  std::optional<double> maxRelMse;
  std::optional<double> maxRmse;
  std::optional<double> minPsnr;
  std::optional<double> maxFlip;      // mean FLIP
  std::optional<double> maxTemporal;  // mean relative frame-to-frame change (with sequence)
};
CLI::App* addCompareCommand(CLI::App& app, CompareOptions& options);
int runCompare(const CompareOptions& options);
int runBench(const BenchOptions& options);

struct SheetOptions {
  std::vector<std::string> images;
  std::string out;
  std::optional<int> columns;       // default: all on one row, at most 8
  std::vector<std::string> labels;  // of the first row's cells
  int shrink = 1;
  float exposure = 1.0f;  // of EXR/HDR inputs
};
CLI::App* addSheetCommand(CLI::App& app, SheetOptions& options);
int runSheet(const SheetOptions& options);

}  // namespace bounce::app
