// bounce view: the interactive viewer. A window showing the GI frame of a
// scene (the frame renderer's G-buffer and direct light, the GI library's
// composite over it) with a fly camera, live GI settings, live timings, a
// material editor, screenshots and a script mode for reproducible runs
// (viewer/script.h). docs/viewer.md has the keys.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bounce/gi.h"
#include "render/frame_renderer.h"
#include "scene/camera_path.h"
#include "scene/scene.h"
#include "viewer/panels.h"
#include "viewer/script.h"
#include "viewer/window.h"

namespace bounce::viewer {

struct ViewerOptions {
  WindowOptions window;                           // its size is the render size
  render::FrameRendererOptions renderer;          // width and height: the render size
  scene::CameraPose camera;                       // where the fly camera starts
  std::shared_ptr<const scene::CameraPath> path;  // what C (or a script's play) follows
  GiMode mode = GiMode::Hybrid;
  gi::Settings settings;
  gi::ContextDesc screenOnly, hybrid;  // the library's context in each mode (scene bridge none / bvh)
  std::vector<ScriptCommand> script;   // run in order; empty: interactive
  bool scripted = false;               // a script was given: it drives input, and its end closes the viewer
  std::string scriptName;              // the script file, as messages name it
  std::filesystem::path out = "out";   // screenshots go here
  std::filesystem::path record;        // non-empty: the session is written there as a script
  float exposure = 1.0f;
  float fps = 30.0f;  // scripted runs: the time a frame stands for (camera speed, animation)
};

// Runs until the window closes, Esc, or the script ends. Returns the exit
// code: 0, or 1 when the validation layer reported anything. Throws for
// what cannot start (no display, no device) and for a script command that
// fails ("SCRIPT:LINE: problem"); the GPU is idle before anything of the
// session is destroyed, whatever ends it.
int runViewer(const scene::Scene& scene, const ViewerOptions& options);

}  // namespace bounce::viewer
