// Screen-only mode's one policy for rays screen space cannot decide (no
// scene bridge traces them), the same for both branches (docs/gi.md,
// "Screen-only mode"):
//   - a ray that met a background pixel sees the environment along it;
//   - a ray that passed behind a surface on screen is blocked by it (below:
//     surfaces are solid), and sees what last frame showed there;
//   - a ray that leaves the screen before deciding, away from the camera,
//     sees what the screen shows where it leaves: the surfaces beyond the
//     edge are taken to be lit as those at it. This frame's tile there
//     (gi.screen_tiles, 16x16 pixels) gives the mean direct light of its
//     surface pixels, for the share of the tile they cover, and the
//     environment along the ray for the share that shows the sky;
//   - a ray that turns towards the camera sees what surrounds the camera as
//     the screen's outermost ring shows it (gi.screen_border): its mean
//     direct light, and the environment as often as the ring shows the sky.
// Direct light only: the unseen surfaces' own bounce light is not guessed.
// Guessed from the screen's (indirect) light, it fed back into itself frame
// after frame and doubled sun-room's, whose unseen walls are dark; without
// the direct light at the screen's edge, pillars, lit by a strip of light
// that runs on behind the camera, kept a tenth of its indirect light.
// Before, the specular branch gave every such ray the open sky (5.7x the
// reference's reflections on Sponza) and the diffuse branch nothing.
//
// The including shader defines SCREEN_TILES_BINDING, the binding of
// gIn_ScreenTiles (gIn_ScreenBorder the next; the host binds
// ScreenTiles::binds() and declares screenTilesDecls()).
#ifndef BOUNCE_GI_SCREEN_ONLY_POLICY_GLSL
#define BOUNCE_GI_SCREEN_ONLY_POLICY_GLSL

#ifndef SCREEN_TILES_BINDING
#error "define SCREEN_TILES_BINDING (the binding of gIn_ScreenTiles) first"
#endif

#include "gi/screen_exit.glsl"

layout(set = 0, binding = SCREEN_TILES_BINDING, rgba32f) readonly uniform image2D gIn_ScreenTiles;
layout(set = 0, binding = SCREEN_TILES_BINDING + 1, rgba32f) readonly uniform image2D gIn_ScreenBorder;

// Whether a ray passed a surface on screen or only went behind it, screen
// space cannot say; the policy takes surfaces as solid (this thickness, a
// fraction of viewZ, passed to the marches): a ray that goes behind one is
// blocked by it. The surface is on screen, where the screen's own samples
// count its light; taken as unseen surroundings as well, the light of every
// surface a coarse march jumps would count twice (sun-room's indirect
// diffuse came out 4x the truth).
const float kSolidSurfaces = 1e30f;

const int kScreenTileSize = 16;

// What a ray that left the screen at pixel `exit` (`towardsCamera`: nearer
// the camera plane there than where it started) sees; `environment`: the
// environment along it.
vec3 beyondTheScreen(ivec2 exit, vec3 environment, bool towardsCamera) {
  if (towardsCamera) {
    vec4 border = imageLoad(gIn_ScreenBorder, ivec2(0));
    float sky = isFinite(border.a) ? clamp(border.a, 0.0f, 1.0f) : 1.0f;
    return mix(sanitizeRadiance(border.rgb), environment, sky);
  }
  ivec2 tile = exit / kScreenTileSize;
  vec4 surfaces = imageLoad(gIn_ScreenTiles, tile);
  ivec2 pixels = min(ivec2(kScreenTileSize), ivec2(fullSize()) - tile * kScreenTileSize);
  float share = isFinite(surfaces.a) ? clamp(surfaces.a / float(pixels.x * pixels.y), 0.0f, 1.0f) : 0.0f;
  return mix(environment, sanitizeRadiance(surfaces.rgb), share);
}

#endif
