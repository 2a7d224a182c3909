// bounce view --script FILE: a reproducible run of the viewer, one command a
// line, run in order, each at the start of a frame ('#' starts a comment):
//
//   wait N                  render N frames before the next command
//   key KEY N               hold KEY (w a s d q e, shift) for N frames
//   look DX DY              turn the camera as a mouse drag of DX, DY pixels would
//   camera PX PY PZ TX TY TZ  place the camera at P looking at T (a cut)
//   pose PX PY PZ TX TY TZ  the camera moves there (no cut: what --record writes a frame)
//   play N                  follow the camera path (--camera) for N frames from where it is
//   click X Y               a left click on pixel (X, Y) of the frame: picks
//                           the material seen there for the editor
//   set KEY VALUE           a GI setting, as --gi.KEY VALUE (restarts the GI)
//   gi MODE                 off, screen-only or hybrid
//   material FIELD VALUE..  edit the picked material: base_color R G B,
//                           roughness V, metallic V, emission R G B, emission_strength V
//   screenshot NAME         the frame as OUT/NAME.png and OUT/NAME.exr (HDR)
//   frames on|off           record every frame as OUT/recording-N/frameNNNN.png
//   stages NAME             every stage of the next frame to OUT/NAME-stages/
//   window NAME             the next frame as the window shows it (frame and panels) as OUT/NAME.png
//   timings LABEL           print the median costs since the last 'timings' (GPU: the frame's
//                           passes, the GI library's, the viewer's own; CPU time a frame)
//   panels on|off           show or hide the panels (the window shows the frame alone)
//   split MODE              the right half: none, gi-off, other (the GI with other
//                           settings: the defaults, or other-settings') or reference
//                           (progressive path tracing)
//   other-settings FILE     the split's other settings from a JSON settings file
//   measure                 print the GI frame's relMSE and HDR-FLIP against the reference
//   stage NAME              show that image (a stage's, as --dump-stages names it; final: the frame)
//   inspect X Y             print every image's value at pixel (X, Y)
//   save-gltf NAME          the scene with the edited materials as OUT/NAME (.gltf or .glb)
//   quit                    close the viewer (the end of the file does too)
//
// The same actions the window's keys, mouse and panels take: a script is a
// user's session written down.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace bounce::viewer {

struct ScriptCommand {
  enum class Kind {
    Wait,
    Key,
    Look,
    Camera,
    Pose,
    Play,
    Click,
    Set,
    Gi,
    Material,
    Screenshot,
    Stages,
    Window,
    Split,
    OtherSettings,
    Panels,
    Timings,
    Frames,
    Measure,
    Stage,
    Inspect,
    SaveGltf,
    Quit
  };
  Kind kind = Kind::Wait;
  int line = 0;  // in the file, for messages
  std::vector<std::string>
      words;                    // the arguments as written (Set, Gi, Material, Screenshot, Stages, Window, Key's name)
  std::vector<double> numbers;  // the numeric arguments (Wait, Key's frames, Look, Camera, Click, Material's values)
};

// Parses a script's text; `source` names it in errors. Throws
// std::runtime_error "SOURCE:LINE: PROBLEM" for an unknown command, a wrong
// number of arguments, a number that is not one (or not finite, or out of
// range: frames 1..100000, pixels >= 0), an unknown key or material field,
// a screenshot name that is not a plain file name (no folders, no '..'), a
// camera so far from the origin that the viewer's 32-bit floats would turn
// or lose its view, or a line holding a NUL byte (shown as \x00). Control
// bytes of the words quoted are shown as \xNN.
std::vector<ScriptCommand> parseScript(std::string_view text, const std::string& source);
// The largest script read: about an hour of a session recorded at 60
// frames a second (a pose and a wait a frame), and at most a few hundred MB
// of parsed commands however short its lines.
inline constexpr std::uintmax_t kMaxScriptBytes = 16u << 20;

// Reads and parses a file; a missing or unreadable file, one that is not a
// regular file (a FIFO, a device, a folder) or one over kMaxScriptBytes is
// an error naming it.
std::vector<ScriptCommand> loadScript(const std::filesystem::path& file);

// The keys `key` takes, as their names in scripts.
bool isScriptKey(std::string_view name);

}  // namespace bounce::viewer
