// Camera paths: where the camera is at every moment of a render, and where it
// jumps (a cut), so that the renderer can reset temporal GI history exactly
// on the frames that need it.
//
// Specs accepted by makeCameraPath (the `--camera` of `bounce render`):
//
//   static  the scene's suggested camera (Scene::suggestedCamera, or a view
//           framing the scene's bounds when it has none); never moves.
//   orbit   one revolution in 8 s around the vertical axis through the centre
//           of the scene's bounds, at the starting camera's height and
//           horizontal distance, starting at its angle, looking at the bounds'
//           centre at the starting target's height. When the starting camera
//           is inside the bounds (an interior), the circle shrinks to stay
//           inside them. Loops seamlessly.
//   dolly   straight towards the starting camera's target, half the way in
//           4 s and back in 4 s with a cosine ease; loops seamlessly.
//   fly     a smooth closed curve (periodic Catmull-Rom through six points on
//           an ellipse over the middle of the bounds, at 65-78 % of their
//           height), looking 1 s ahead along the curve and down towards the
//           middle; 16 s per loop, seamless.
//   gltf    the first camera of the displayed glTF scene (depth-first from
//           the roots): its node's world transform at each time (animated
//           when its node or an ancestor is) and its vertical field of view.
//   gltf:N  the N-th camera (from 0) in that same depth-first order.
//   gltf:NAME  the first camera whose node or glTF camera is called NAME.
//   anything else: a JSON keyframe file (see parseCameraKeyframes).
//
// Presets start from the suggested camera and derive their size from the
// scene's bounds at time 0.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace bounce::scene {

struct CameraFrame {
  CameraPose pose;
  bool cut = false;  // the camera jumped: the GI history must be reset this frame
};

class CameraPath {
 public:
  virtual ~CameraPath() = default;

  // The pose at `time` seconds. Presets repeat with period duration();
  // keyframes hold their first pose before the first key and their last pose
  // after the last; a glTF camera follows its animations, which loop.
  virtual CameraPose pose(float time) const = 0;

  // Which continuous piece of the path `time` falls in. Two times with the
  // same segment are joined by continuous motion; a change between two
  // frames is a cut. A cut is a property of an interval, not of an instant,
  // which is why frames get their flags from sampleCameraPath.
  virtual int segment(float /*time*/) const { return 0; }

  // Length of the path in seconds (one loop for the looping presets); 0 for
  // a camera that never moves.
  virtual float duration() const = 0;
};

// The preset names makeCameraPath accepts: orbit, dolly, fly, static, gltf
// (and gltf:N, gltf:NAME for a camera other than a glTF file's first).
std::vector<std::string> cameraPathPresets();

// A preset by name, else the JSON keyframe file `spec` names. Throws
// SceneError for "gltf" on a scene without a camera, for "gltf:N" or
// "gltf:NAME" naming no camera (listing the scene's cameras by number and
// name), for a spec that is neither a preset nor an existing file (listing
// the presets), and for any problem in the file.
std::unique_ptr<CameraPath> makeCameraPath(std::string_view spec, const Scene& scene);

// What `bounce render` uses when the user names no path: the scene's first
// glTF camera if it has one, else the static suggested camera.
std::unique_ptr<CameraPath> defaultCameraPath(const Scene& scene);

// Keyframes as JSON text; `source` names the text in error messages (the
// file name). The format:
//
//   {"keyframes": [
//     {"time": 0, "position": [x, y, z], "target": [x, y, z], "fovY": 45},
//     {"time": 2.5, "position": [...], "target": [...], "up": [0, 1, 0]},
//     {"time": 4, "position": [...], "target": [...], "cut": true}, ...]}
//
// time (seconds), position and target are required; fovY (degrees, in
// (0, 180)) defaults to the previous keyframe's (45 for the first); up
// defaults to +Y; cut defaults to false. Times strictly increase. Position
// and target are interpolated by a Catmull-Rom spline over the key times
// (cubic Hermite with finite-difference tangents, one-sided at the ends of a
// segment), so the camera passes through every key exactly at its time with
// continuous velocity; fovY and up are interpolated linearly. A keyframe with
// "cut": true starts a new segment: the previous segment holds its last key
// until the cut key's time and nothing is interpolated across it; the first
// frame at or after that time is flagged as a cut. Unknown fields are
// refused (a misspelt "fov" would otherwise be silently ignored), and so is
// a key given twice in one object, JSON nested deeper than 16 levels, and a
// file of more than 100,000 keyframes (counted while it is read). Errors
// throw SceneError "<source>: keyframe <i>: <problem>" (just "<source>:
// <problem>" for problems of the whole document).
std::unique_ptr<CameraPath> parseCameraKeyframes(const std::string& json, const std::string& source);

// parseCameraKeyframes on the file's contents, named by its path.
std::unique_ptr<CameraPath> loadCameraKeyframes(const std::filesystem::path& file);

// The frames of a render: frame i at time i / fps. Frame 0 is a cut (there is
// no history yet), and so is every frame whose segment differs from the
// previous frame's. Throws std::invalid_argument for frameCount < 0 or a fps
// that is not a positive finite number.
std::vector<CameraFrame> sampleCameraPath(const CameraPath& path, int frameCount, float fps);

// Frames first .. first + count - 1 of the same render, flagged exactly as
// sampleCameraPath flags them, without sampling the frames before `first`
// (bounce reference renders one frame of a long path). Throws
// std::invalid_argument for a fps that is not a positive finite number.
std::vector<CameraFrame> sampleCameraFrames(const CameraPath& path, std::uint32_t first, std::uint32_t count,
                                            float fps);

}  // namespace bounce::scene
