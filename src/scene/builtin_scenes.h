// Built-in procedural scenes: enough for the quick start, the tests and CI
// without any asset files. Every surface is a box, a quad or (the pillars) a
// cylinder, with exact normals, tangents (w = +1, glTF convention) and
// texture coordinates in metres; materials are plain factors, no textures.
// Solid objects and the walls of rooms are closed slabs whose normals point
// out of the solid, so the inside faces of a room point into the room and
// every wall is opaque from both sides (the sun cannot leak through).
//
// Units: metres; +Y up; the sun's illuminance E lights a facing Lambert
// surface of albedo a to radiance E * a / pi; a point or spot light of
// intensity I gives irradiance I / d^2 (spots shine down their node's -Z).
//
//   cornell            The Cornell box at 1/100 of its published millimetre
//                      size: a 5.55 m cube, open at the front (z = 0), back
//                      wall at z = -5.55, floor y = 0, ceiling y = 5.55, red
//                      wall x = -2.775 (left as the camera sees it), green
//                      wall x = +2.775. A tall box (1.65 x 3.30 x 1.65, turned
//                      +17 degrees about +Y) at the back left and a short
//                      cube (1.65, turned -17 degrees) at the front right.
//                      Light: a 1.30 x 1.05 m emissive quad 1 cm below the
//                      ceiling centre, radiance (17, 14.45, 10.2), plus a spot
//                      light 10 cm below it pointing down (outer cone 90
//                      degrees, so cos^2 falloff), intensity = the quad's
//                      radiance * area (the quad's intensity straight down),
//                      for renderers that light only with punctual lights.
//                      No sun. Camera at (0, 2.73, 8) looking down -Z, fovY
//                      39.3 degrees, as in the original photograph set-up.
//   pillars            The specular test scene: five gold pillars (F0 (1,
//                      0.78, 0.34), metallic, radius 0.3 m, 2.5 m tall, at z =
//                      0 and x = -3.2 .. 3.2 every 1.6 m) of roughness 0.2,
//                      0.4, 0.6, 0.8, 1.0 (left to right) on a glossy dark
//                      dielectric floor (roughness 0.15), in a closed hall
//                      x in [-7, 7], z in [-4, 9], y in [0, 5]. Lit only
//                      indirectly: a point light of intensity 1200 above
//                      the ceiling, at (0, 8, 3), shines through a 10 x 1 m
//                      slot in the ceiling (z in [2.5, 3.5]) onto the floor
//                      in front of the pillars (z in about [1.7, 4.3]); the
//                      ceiling hides the light from every pillar point, so
//                      the pillars see only that bright floor patch and what
//                      it lights. The lit patch is on screen, where
//                      screen-space GI can find it. No sun. Camera at (0, 1.6, 7.5) looking at the
//                      middle pillar, fovY 45.
//   sun-room           A closed room x in [-3, 3], z in [-4, 4], y in [0, 3]
//                      with one window in the +X wall (z in [-1.2, 1.2], y in
//                      [0.8, 2.4]); the sun (elevation 35, azimuth 105
//                      degrees, illuminance 10) shines through it onto the
//                      wooden floor around (0.8, 0, 0.6). Everything outside
//                      that patch (and the window) is lit only by bounce
//                      light. A table, a tall blue cabinet and a red ottoman.
//                      Camera in the corner at (-2.5, 1.65, 3.5) looking
//                      towards the window and the sun patch, fovY 55.
//   sun-room-animated  sun-room plus a 0.5 m yellow box at x = 0.8 that
//                      slides through the sun patch (z from -2.5 to 2.5 and
//                      back) while turning a full turn, a 6 s seamless loop:
//                      moving-object motion vectors and a moving shadow in
//                      the room's main source of bounce light.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "scene/scene.h"

namespace bounce::scene {

// The names makeBuiltinScene accepts, in a stable order.
std::vector<std::string> builtinSceneNames();

bool isBuiltinScene(std::string_view name);

// The scene shown when the user names none.
const char* defaultBuiltinScene();

// Builds the named scene (validated). Throws SceneError listing the valid
// names when `name` is not one of them.
Scene makeBuiltinScene(std::string_view name);

}  // namespace bounce::scene
