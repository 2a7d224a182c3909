// bounce view: the interactive viewer (src/viewer/, docs/viewer.md) for a
// built-in scene or a glTF file, with the same scene, camera and GI options
// as bounce render; --script runs it unattended (a list of input events and
// waits, ending in screenshots).
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "app/commands.h"
#include "app/option_checks.h"
#include "app/output_files.h"
#include "viewer/viewer.h"

namespace bounce::app {

CLI::App* addViewCommand(CLI::App& app, ViewOptions& options) {
  CLI::App* command = app.add_subcommand(
      "view",
      "Interactive viewer: the GI frame of a scene in a window, fly camera, live settings and timings, "
      "material editor (keys: docs/viewer.md, or H in the window)");
  addGpuOptions(*command, options.gpu);
  addSceneOptions(*command, options.view);
  addGiOptions(*command, options.gi, false);
  command->add_option("--script", options.script,
                      "Run this script of input events and waits instead of reading the keyboard and mouse, then "
                      "quit (commands: docs/viewer.md)");
  command->add_flag("--headless", options.headless,
                    "No window (a machine without a display; needs --script): the panels are drawn into an image "
                    "that is never presented, e.g. to measure the viewer's own cost (script command timings)");
  command->add_option("--record", options.record,
                      "Write the session as a script to this file (camera poses, settings, clicks, material edits, "
                      "screenshots), so that --script replays it; an existing file is not overwritten");
  command->add_option("--out", options.out, "Folder for screenshots (created if missing)");
  command->add_option("--exposure", options.exposure, "Exposure multiplier before tonemapping")
      ->check(finitePositive());
  return command;
}

int runView(const ViewOptions& options) {
  // Before the window opens: a bad script or output folder fails now.
  if (options.headless && options.script.empty())
    throw UsageError("--headless needs --script FILE: without a window there is no keyboard or mouse");
  std::vector<viewer::ScriptCommand> script;
  if (!options.script.empty()) script = viewer::loadScript(options.script);
  checkWritableDirectory(options.out, "--out");
  if (!options.record.empty()) {
    std::error_code error;
    if (std::filesystem::exists(options.record, error))
      throw UsageError("--record " + options.record +
                               ": the file exists; not overwritten (choose another name)");
  }
  // Settings that contradict each other are a command-line mistake: found before the scene loads.
  const gi::Settings settings = giSettings(options.gi);
  const SceneOptions& shot = options.view;
  const scene::Scene scene = loadScene(shot);
  std::unique_ptr<scene::CameraPath> path = cameraPathOf(scene, shot);
  const std::vector<scene::CameraFrame> first = checkedCameraFrames(*path, 0, 1, shot);

  viewer::ViewerOptions viewerOptions;
  viewerOptions.window = {.width = shot.width,
                          .height = shot.height,
                          .title = "bounce view - " + scene.name,
                          .validation = options.gpu.validate,
                          .deviceIndex = options.gpu.device,
                          .headless = options.headless};
  viewerOptions.renderer = frameRendererOptions(scene, shot);
  viewerOptions.camera = first[0].pose;
  viewerOptions.path = std::shared_ptr<const scene::CameraPath>(path.release());
  viewerOptions.record = options.record;
  // --gi off starts with GI off; the window can still switch it on, with
  // both branches.
  const bool gi = giEnabled(options.gi);
  GiOptions branches = options.gi;
  if (!gi) branches.mode = GiOptions{}.mode;
  viewerOptions.mode = !gi                                ? viewer::GiMode::Off
                       : options.gi.sceneBridge == "none" ? viewer::GiMode::ScreenOnly
                                                          : viewer::GiMode::Hybrid;
  viewerOptions.settings = settings;
  GiOptions screenOnly = branches, hybrid = branches;
  screenOnly.sceneBridge = "none";
  hybrid.sceneBridge = "bvh";
  viewerOptions.screenOnly = giContextDesc(shot.width, shot.height, screenOnly);
  viewerOptions.hybrid = giContextDesc(shot.width, shot.height, hybrid);
  viewerOptions.script = std::move(script);
  viewerOptions.scripted = !options.script.empty();
  viewerOptions.scriptName = options.script;
  viewerOptions.out = options.out;
  viewerOptions.exposure = options.exposure;
  viewerOptions.fps = shot.fps;
  return viewer::runViewer(scene, viewerOptions);
}

}  // namespace bounce::app
