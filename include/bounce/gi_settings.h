// Every setting of the GI library, in one plain struct with documented
// defaults. Each field also has a key (gi.diffuse.spatial_radius, ...) under
// which `bounce` takes it on the command line (--gi.diffuse.spatial_radius 24)
// or from a JSON file ({"diffuse": {"spatial_radius": 24}}); see
// src/gi/settings.cpp for the table of keys and docs/gi-settings.md for all
// of them with their ranges.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace bounce::gi {

// How a sample's radiance becomes a scalar weight (the target function p-hat
// is this times the cosine at the shaded point).
enum class TargetFunction : std::uint32_t {
  Luminance = 0,    // Rec. 709 luminance
  ColorLength = 1,  // length of the RGB vector (the seed's choice)
};

// How the resolve tests whether a sample is visible from the pixel that
// evaluates it. World rays need a scene bridge (ContextDesc::sceneBridge);
// with the bridge "none" every choice is Screen.
enum class Visibility : std::uint32_t {
  Screen = 0,  // a march through this frame's depth buffer alone (thickness guessed)
  World = 1,   // an any-hit ray through the scene bridge for every sample
  Hybrid = 2,  // the march; a world ray where it cannot decide (left the screen, passed behind a surface)
};

struct DiffuseSettings {
  bool enabled = true;

  // --- sample gathering (half resolution): candidates per pixel and source
  std::uint32_t screenCandidates = 6;       // random pixels of the previous composited frame
  std::uint32_t brightCandidates = 2;       // picks among the brightest pixels of that frame
  std::uint32_t environmentCandidates = 2;  // uniform hemisphere directions into the environment (no bridge)
  // With a scene bridge that traces, environment candidates give way to
  // rays: cosine-distributed directions marched through the depth buffer
  // first and continued through the bridge where the screen cannot decide;
  // what they hit is shaded by the bridge (direct light, emission) and the
  // radiance cache, or read from the last frame where it was on screen; a
  // ray that truly misses sees the environment.
  std::uint32_t rayCandidates = 2;
  std::uint32_t rayScreenSteps = 8;  // depth-buffer march steps before a ray goes to the bridge (0: world at once)
  std::uint32_t brightPixels = 64;          // the reduction pyramid stops at about this many pixels
  float environmentMip = 1.0f;              // prefiltered environment level the samples read
  TargetFunction target = TargetFunction::Luminance;

  // --- temporal reuse (half resolution)
  std::uint32_t temporalMaxM = 20;       // history counts as at most this many frames of samples
  float temporalDepthTolerance = 0.05f;  // reprojected depth may differ by this fraction of viewZ
  float temporalNormalToleranceDegrees = 25.0f;

  // --- spatial reuse (half resolution): two passes
  float spatialRadius = 16.0f;  // first pass: disk radius in half-resolution pixels at the surface
  std::uint32_t spatialSamples = 5;
  float spatial2Radius = 6.0f;  // second pass
  std::uint32_t spatial2Samples = 5;
  float spatialNormalToleranceDegrees = 25.0f;  // neighbours whose normal differs more are rejected
  float spatialPlaneTolerance = 0.05f;  // ... and those farther from the tangent plane than this fraction of viewZ
  bool jacobian = true;                 // ReSTIR GI's reconnection Jacobian for reused samples
  // Which reservoirs the next frame's temporal reuse starts from: false,
  // those after temporal reuse (as the ReSTIR GI paper does); true, those
  // after the second spatial pass (the Jitter gi pass's feedback point). Measured on a
  // floor lit by a wall, the spatial feedback darkens indirect diffuse by a
  // quarter at M cap 20 (docs/gi.md), so it is off by default.
  bool spatialFeedback = false;

  // --- resolve (full resolution) with deferred screen-space visibility
  std::uint32_t resolveReservoirs = 4;  // neighbouring half-resolution reservoirs each pixel evaluates (1..4)
  std::uint32_t visibilitySteps = 12;   // ray-march steps from the pixel to each sample (0 = no visibility test)
  Visibility visibility = Visibility::Hybrid;
  // Hybrid visibility: true, the resolve also marches from each
  // full-resolution pixel to each sample it evaluates (four a pixel);
  // false, it trusts gi.diffuse.sample_visibility's world ray, which tested
  // each reservoir's sample once from the reservoir's own surface, and the
  // four pixels that use it share the verdict. Measured on the H100 at
  // 1080p: the diffuse resolve 0.71-0.73 -> 0.32 ms, and HDR-FLIP at
  // 640x360 no worse on any of the five scenes (docs/benchmarks.md).
  bool perPixelVisibility = false;
  // Screen visibility (screen-only mode): false, the resolve marches from
  // each pixel to each sample; true, gi.diffuse.sample_march marches each
  // reservoir's sample once from its own surface at half resolution
  // (0.52-0.60 -> 0.26-0.27 + 0.04 ms), and the resolve shares the
  // verdict. Off by default: not measured on the GPU's scenes yet, and on
  // lavapipe it brightened open cornell's screen-only light, already over
  // the reference, from 1.158 to 1.178 of it.
  bool screenVisibilityPerReservoir = false;
  // Temporal and spatial reuse test a reused sample's visibility from the
  // reusing pixel with an any-hit ray through the bridge, so that reuse
  // adds no bias from occlusion (ReSTIR GI's unbiased reuse; costs a ray
  // per reused neighbour). Needs a bridge that traces.
  bool reuseVisibility = false;
  // Spatial reuse counts a neighbour towards normalising a sky sample only
  // if an any-hit ray through the bridge finds the sky open from it: sky
  // visibility differs most across the reuse disk (a window), and counting
  // neighbours that cannot see the sky through it darkens sky light (sun-room
  // 320x180: 0.61 -> 0.71 of the reference). Costs up to one ray per
  // neighbour for reservoirs holding a sky sample. Needs a bridge that traces.
  bool skyReuseVisibility = true;
  // Of those neighbours, one spatial pass tests at most this many with a ray
  // (rays into the open are the longest a frame casts); the others count
  // with the share of the tested ones' confidence that saw the sample. That
  // estimate of the normalisation is noisy, and its noise brightens sky
  // light (sun-room, 96x54: +18 % over no spatial reuse testing 1 a pass,
  // +7 % testing 2, +1 % testing all), so the default tests every one (a
  // pass merges at most 16).
  std::uint32_t skyReuseRays = 16;
  float visibilityThickness = 0.03f;  // surfaces are this fraction of their viewZ thick

  // --- temporal filter (full resolution)
  float varianceClippingGamma = 1.5f;       // history clamped to the fast history +- gamma * temporal sigma
  std::uint32_t temporalFilterFrames = 64;  // the longest history the filter accumulates
};

// How the specular branch draws its one ray per pixel and frame.
enum class SpecularSampling : std::uint32_t {
  // GGX visible normals around the pixel's normal and view (the Jitter gi pass's specular ReSTIR); the
  // target function is the real BRDF times cos times the radiance.
  Vndf = 0,
  // Uniform over a cone around the lobe's dominant direction, with the
  // view-independent target p-hat = radiance (Zyanide's uniform-lobe reservoirs): the stored
  // reservoirs survive a change of view; the resolve resamples them with the
  // real BRDF (the disposable reservoir). Samples that leave the lobe of the
  // surface reusing them are rejected.
  Uniform = 1,
};

// Which history the specular temporal filter reprojects.
enum class SpecularReprojection : std::uint32_t {
  Surface = 0,  // the surface's motion (right for rough surfaces)
  Virtual = 1,  // the reflected image's motion, from the hit distance (right for mirrors)
  Dual = 2,     // both, blended by roughness and by how well each agrees with this frame
};

// The specular branch (the Jitter gi pass's specular ReSTIR and Zyanide's uniform-lobe reservoirs; docs/gi.md,
// "Indirect specular").
struct SpecularSettings {
  bool enabled = true;

  // --- sample generation and trace (half resolution): one ray per pixel
  SpecularSampling sampling = SpecularSampling::Vndf;
  // Uniform sampling: the cone holds this fraction of the lobe's microfacet normals.
  float lobeFraction = 0.9f;
  // Below this perceptual roughness no reservoir is reused (Zyanide's uniform-lobe reservoirs): a
  // near-mirror's lobe is too narrow for another pixel's or frame's sample
  // to land in it; each pixel keeps its own ray.
  float reuseMinRoughness = 0.25f;
  // At and above this perceptual roughness a pixel casts no ray of its own:
  // its fresh sample is the diffuse branch's final sample of the frame at
  // the same surface, weighed by that reservoir's unbiased contribution
  // weight (Bevy Solari's rule for rough lobes). A rough lobe is nearly as
  // wide as the cosine lobe the diffuse samples follow, and the diffuse
  // target covers every direction the specular one does, so the estimate
  // stays unbiased; what it saves is the ray, and with a scene bridge the
  // world ray after it. Above 1 every pixel traces; the same without the
  // diffuse branch (disabled, or the engine gives its own diffuse signal).
  // Off by default: the diffuse branch's own darkening (known-issues.md)
  // comes with its samples, measured at 0.5 as 7 % less indirect specular
  // on Sponza for 0.70 ms less (docs/benchmarks.md).
  float diffuseSampleRoughness = 2.0f;
  // At and above this perceptual roughness the hits of a pixel's world ray
  // take their direct light from the radiance cache's cell, where it knows
  // it, instead of a shadow ray of their own (gi.cache.direct_light; as the
  // diffuse ray candidates do): a rough lobe blurs what it reflects over
  // more than a cell. Above 1: every hit casts its shadow rays.
  float cachedDirectRoughness = 2.0f;
  std::uint32_t traceSteps = 64;     // depth-buffer march steps before a ray goes to the bridge (0: at once)
  float traceThickness = 0.03f;      // depth-buffer surfaces are this fraction of their viewZ thick

  // --- temporal reuse (half resolution), fed back before spatial reuse
  std::uint32_t temporalMaxM = 4;  // the Jitter gi pass: reflections must react fast
  float temporalDepthTolerance = 0.05f;
  float temporalNormalToleranceDegrees = 25.0f;

  // --- spatial reuse (half resolution): neighbours within the lobe's footprint
  std::uint32_t spatialSamples = 4;
  float spatialMaxRadius = 16.0f;  // half-resolution pixels, for the roughest lobes
  float spatialNormalToleranceDegrees = 25.0f;
  float spatialPlaneTolerance = 0.05f;
  bool jacobian = true;

  // --- resolve (full resolution): reservoirs evaluated per pixel, by roughness
  std::uint32_t resolveMaxSamples = 4;  // for surfaces at least resolve_full_roughness rough
  float resolveFullRoughness = 0.5f;    // from 1 reservoir at roughness 0 up to the maximum here (linear)
  float resolveMaxRadius = 6.0f;        // full-resolution pixels, for the roughest lobes

  // --- temporal filter (full resolution)
  SpecularReprojection reprojection = SpecularReprojection::Dual;
  float varianceClippingGamma = 1.5f;
  std::uint32_t temporalFilterFrames = 32;  // the longest history (rough surfaces; smooth ones less)
};

// The denoiser (docs/gi.md, "The denoiser"; after NVIDIA's REBLUR, as the
// REBLUR analysis reads it): temporal accumulation, history fix, blur, post-blur and temporal
// stabilisation of each branch's resolved signal, in place of the
// branches' own temporal filters.
struct DenoiseSettings {
  bool enabled = true;
  std::uint32_t maxAccumulatedFrames = 30;  // the longest history (REBLUR's default)
  std::uint32_t historyFixFrames = 3;       // shorter histories are rebuilt from a wide neighbourhood
  // Radii and strides in pixels of a 1080-row frame, scaled with the render height.
  float diffusePrePassRadius = 30.0f;       // pre-pass: the widest radius (REBLUR's; 0: no pre-pass)
  float specularPrePassRadius = 50.0f;      // the same for specular (REBLUR's)
  float historyFixStride = 14.0f;           // pixels between history fix's taps (REBLUR: 14)
  float blurRadius = 30.0f;                 // pixels, at the first frame of a history (REBLUR's max radius)
  float minBlurRadius = 1.0f;               // pixels, however long the history
  float postBlurRadiusScale = 0.5f;         // post-blur's radius as a fraction of blur's
  float planeDistanceSensitivity = 0.02f;   // a tap this fraction of viewZ off the pixel's plane weighs 0
  float lobeAngleFraction = 0.15f;          // the normal weight's cone for a long history (REBLUR's; squared)
  float roughnessFraction = 0.15f;          // the roughness weight's reach in fractions of the roughness
  std::uint32_t stabilizationFrames = 8;    // temporal stabilisation's longest history (0: off)
  float disocclusionThreshold = 0.01f;      // last frame's depth may differ by this fraction of the frustum (REBLUR's)
  // Temporal passes: a reprojected normal may turn this far; a reprojected
  // depth (stabilisation's, the reflection's virtual history) may differ by
  // this fraction of viewZ.
  float normalToleranceDegrees = 25.0f;
  float depthTolerance = 0.05f;
  float clampSigma = 1.5f;                  // history clamping to the fast history and the neighbourhood, in sigmas
  bool antiFirefly = true;                  // history fix brings outliers down to their neighbours' mean + 2 sigma
  // The engine's noisy signals (FrameInputs::noisy) are checkerboarded,
  // REBLUR's checkerboard mode: each holds every other pixel of a row,
  // packed to ceil(width / 2) x height, pixel (x, y) at (x / 2, y) where
  // (x + y + frameIndex) is odd for signals of kind Diffuse, even for
  // Specular (shaders/shared/checkerboard.glsl); the pre-pass fills the
  // rest. The branches' own signals are full resolution whatever it says.
  bool checkerboard = false;
};

// What the engine's motion vectors are in (the library's own convention:
// pixels, previous position = current + motion).
enum class MotionUnits : std::uint32_t {
  Pixels = 0,  // pixels of the render size
  Uv = 1,      // fractions of the render size ([0,1] across the frame)
};

// How the library reads the engine's inputs (docs/integration.md, "Inputs").
struct InputSettings {
  MotionUnits motionUnits = MotionUnits::Pixels;
  // Multiply the motion after its units: -1 flips an axis (y up, or
  // motion stored as current - previous).
  float motionScaleX = 1.0f;
  float motionScaleY = 1.0f;
};

// The world-space radiance cache (docs/gi.md, "The radiance cache"): what
// world rays of the scene bridge find off screen is lit by it, so light
// bounces more than once without rays that recurse. Used only with a scene
// bridge that traces.
struct CacheSettings {
  bool enabled = true;
  std::uint32_t memoryMib = 72;  // device memory for the cells at most (capacity: a power of two)
  float cellSize = 0.04f;        // a cell's edge as a fraction of its distance to the camera (rounded to 2^k)
  std::uint32_t updateRays = 65536;   // closest-hit rays per frame of the update paths, at most
  std::uint32_t updateBounces = 3;    // surfaces each update path bounces off at most (1..4)
  std::uint32_t historySamples = 64;  // a cell's value averages at most this many samples
  std::uint32_t maxAge = 64;          // cells nobody used for this many frames are evicted
  std::uint32_t injectStride = 4;     // the screen fills cells from one pixel of every stride x stride block
  // Cells also hold the direct light at their point (one shadow ray a cell
  // and frame), and diffuse world hits take theirs from the cell instead of
  // a shadow ray each (docs/gi.md, "The radiance cache").
  bool directLight = true;
};

struct Settings {
  DiffuseSettings diffuse;
  SpecularSettings specular;
  DenoiseSettings denoise;
  CacheSettings cache;
  InputSettings input;
  // false: no temporal and no spatial reuse (gathering, resolve and filters
  // stay): the baseline every reuse comparison is made against.
  bool restir = true;
  std::uint32_t seed = 0;  // another seed gives other (independent) noise
  // World rays per pixel and frame the library may cast through a scene
  // bridge that traces, at most (planWorldRays says how they are spent;
  // docs/gi-settings.md, "World rays"). Not counted against it: the radiance
  // cache's updates (cache.update_rays a frame, whatever the size) and the
  // bridge's own shadow rays at hits (as many as its lights).
  float worldRayBudget = 3.5f;
};

// How the library spends Settings::worldRayBudget, in rays per
// half-resolution reservoir (four pixels) and frame, at most, with a scene
// bridge that traces. What its settings ask for is fixed (sample
// visibility, specular continuation, the unbiased reuse option, world
// visibility at the resolve); what is left pays first for one ray
// candidate, then for testing sky samples in spatial reuse
// (diffuse.sky_reuse_rays in each pass, at most one per neighbour), then
// for the other ray candidates (diffuse.ray_candidates): each is cut to
// what the budget holds.
struct WorldRayPlan {
  std::uint32_t diffuseCandidates = 0;  // gi.diffuse.gather
  std::uint32_t skyReuseRays = 0;       // gi.diffuse.spatial_reuse, in each pass
  std::uint32_t spatialPasses = 0;      // spatial reuse passes that merge neighbours
  std::uint32_t reuseVisibility = 0;    // the unbiased option, temporal and spatial reuse together
  std::uint32_t sampleVisibility = 0;   // gi.diffuse.sample_visibility (hybrid visibility)
  std::uint32_t resolveVisibility = 0;  // gi.diffuse.resolve (world visibility): its reservoirs for each of 4 pixels
  std::uint32_t specular = 0;           // gi.specular.trace
  // Every ray above, per reservoir.
  std::uint32_t perReservoir() const;
};
// Throws std::invalid_argument when what the settings fix alone is more than
// the budget (naming the settings and the budget they would need).
WorldRayPlan planWorldRays(const Settings& settings);

// One settable field: its key (relative to "gi.", e.g. "diffuse.spatial_radius"),
// its type and range as text, its default and what it does.
struct SettingInfo {
  std::string key;
  std::string type;  // "bool", "enum: a|b", or "uint"/"float" and its range: "uint [0, 64]", "float (0, 1]"
  std::string defaultValue;
  std::string description;
};

// Every key, in the order of the structs above.
const std::vector<SettingInfo>& settingKeys();

// Sets one field from text ("24", "on", "off", "true", "luminance", ...).
// The key may also carry the command line's "gi." prefix.
// Throws std::invalid_argument naming the key, the value and what it takes
// (unknown key, not a number, out of range); the field is then left as it was.
// Only this key's own range is checked: call validate() once every setting is
// applied, for the checks that span keys (at least one kind of candidate).
void applySetting(Settings& settings, const std::string& key, const std::string& value);

// Applies a JSON file ({"restir": false, "diffuse": {"spatial_radius": 24}});
// nested objects and dotted keys ({"diffuse.spatial_radius": 24}) are the same
// key, and a {"gi": {...}} wrapper is allowed. Keys the file leaves out keep
// their value. Throws std::runtime_error starting with the file's path (no
// file, malformed JSON, unknown key, bad value, a key given twice), and then
// changes nothing.
void applySettingsFile(Settings& settings, const std::filesystem::path& file);

// The current value of a key as text, in a form applySetting takes back
// (bools as on/off, floats in as few digits as give the same float).
std::string settingValue(const Settings& settings, const std::string& key);

// Checks every field's range; throws std::invalid_argument naming the first
// bad key (settings built in code, not only parsed, pass through this).
void validate(const Settings& settings);
// validate(), and the check that depends on the scene bridge: with one that
// traces, ray candidates take the environment candidates' place, so the
// screen, bright and ray candidates (as many as the world-ray budget pays
// for) must not all be 0 while diffuse is on. A command line checks this
// before it loads a scene; the library checks it again when it is made.
void validate(const Settings& settings, bool bridgeTraces);

}  // namespace bounce::gi
