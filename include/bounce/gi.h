// The Bounce GI library: screen-space ReSTIR global illumination for an
// engine's G-buffer, recorded into the engine's own command buffers on the
// engine's own Vulkan device. It sees images and camera matrices, never a
// scene. docs/integration.md walks through an integration step by step.
//
//   bounce::gi::GiContext gi(device, {.maxWidth = 1920, .maxHeight = 1080});
//   every frame, after the engine's G-buffer and direct light, in its command buffer:
//     gi.record(commandBuffer, inputs);
//     ... read gi.composite() (the frame, HDR) or gi.indirect(bounce::gi::kDiffuseSignal) ...
//
// The passes it records (docs/passes.md has each one's inputs and outputs):
//   gi.store_history                    this frame's depth and normals, for the next frame
//   gi.diffuse.bright_pixels            2x2 -> 1 reductions of the previous frame to its brightest pixels
//   gi.diffuse.gather                   half res: candidates from the previous frame, the brightest
//                                       pixels and the environment into one reservoir per pixel
//   gi.diffuse.temporal_reuse           half res: merge with last frame's reservoir (ReSTIR)
//   gi.diffuse.spatial_reuse            half res: merge with neighbours, twice (ReSTIR)
//   gi.diffuse.sample_visibility        half res, with a bridge that traces: drop samples hidden
//                                       from their reservoir's surface (one world ray each)
//   gi.diffuse.resolve                  full res: each pixel evaluates nearby reservoirs with
//                                       screen-space visibility -> indirect diffuse
//   gi.diffuse.temporal_filter          full res: reprojected history, clamped to the fast history
//   gi.specular.trace                   half res: one lobe-sampled ray per pixel, marched through the
//                                       depth buffer, then through the scene bridge
//   gi.specular.temporal_reuse          half res: merge with last frame's reservoir (M <= 4)
//   gi.specular.spatial_reuse           half res: merge with neighbours in the lobe's footprint
//   gi.specular.resolve                 full res: 1..8 reservoirs per pixel by roughness -> indirect specular
//   gi.specular.temporal_filter         full res: surface and reflection (virtual) motion, blended
//   gi.engine_signal.SIGNAL             full res, for a noisy signal the engine gives (FrameInputs::
//                                       noisy): taken in, non-finite values dropped
//   gi.denoise.*                        with Settings::denoise.enabled: the denoiser, per signal, in place
//                                       of the branches' temporal filters (docs/gi.md, "The denoiser")
//   gi.composite                        direct + albedo * indirect diffuse + specular reflectance *
//                                       indirect specular (+ emission)
// The composite is what the next frame's gathering samples, so light keeps
// bouncing from frame to frame.
//
// Errors: every call that can fail throws bounce::gi::Error (a
// std::runtime_error) whose message names the input or setting at fault;
// settings are checked as gi_settings.h says. A call that throws records
// nothing into the command buffer.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "bounce/gi_settings.h"
#include "bounce/version.h"

namespace bounce::gi {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The engine's Vulkan device. It must be Vulkan 1.3 with the features
// synchronization2 and maintenance4 enabled and the device extension
// VK_KHR_push_descriptor enabled (the library writes its descriptors into
// the command buffer: no pools, no per-frame allocations). The library
// keeps the handles; the engine keeps them alive and destroys them after
// the GiContext.
struct Device {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  // The family of the queues the command buffers given to record() are
  // submitted to; it must support compute.
  std::uint32_t queueFamily = 0;
  // VK_EXT_debug_utils is enabled on the instance: the library names its
  // images and pipelines and labels each pass in the command buffer (what
  // RenderDoc, Nsight and validation messages then show).
  bool debugUtils = false;
};

// One of the engine's images as it is when record() is called.
//   - `view` is a 2D view of mip 0 (of every mip for the environment).
//   - `layout`, `stage`, `access`: the layout the image is in and the stage
//     and access of the engine's last use of it before record() (e.g. a
//     compute shader's write: VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
//     VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT). The library's first barrier waits
//     for that use; an image the engine has not touched is UNDEFINED / NONE.
// The library reads inputs as sampled images (texelFetch), so they need
// VK_IMAGE_USAGE_SAMPLED_BIT; it never writes them.
struct ImageRef {
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint32_t mipLevels = 1;
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags2 stage = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 access = VK_ACCESS_2_NONE;
};

// A buffer of the engine's as it is when record() is called: `size` bytes
// from its start, and the stage and access of the engine's last write to it
// (the library's first read waits for that write). The library only reads
// it, in compute shaders: the engine's next write must wait for
// VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT reads.
struct BufferRef {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  VkPipelineStageFlags2 stage = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 access = VK_ACCESS_2_NONE;
};

// --- The scene bridge: how the library sees beyond the screen.
// The library's shaders that trace rays call a few functions
// (shaders/gi/scene_bridge.glsl lists them: closest hit, any hit, the direct
// light leaving a hit) that the engine implements in GLSL, in a file its
// build compiles the library's shaders with (CMake:
// bounce_embed_shaders(... SCENE_BRIDGE), cmake/EmbedShaders.cmake).
// The bridge "none" (the default) traces nothing: pure screen space.
// docs/integration.md, "A scene bridge", walks through writing one.
// Bridge data is read from storage buffers (constants too: a std140 block
// declared `readonly buffer`) and sampled images.
enum class SceneResourceKind { StorageBuffer, SampledImage };

// One resource the bridge's GLSL declares, by the name it has there.
struct SceneResourceDecl {
  std::string name;  // e.g. "gIn_BvhNodes"
  SceneResourceKind kind = SceneResourceKind::StorageBuffer;
  std::string purpose;
};

// One of the library's shaders compiled with the bridge (the table
// bounce_embed_shaders(... SCENE_BRIDGE) generates holds them): SPIR-V words, by the
// library's name for the shader ("gi/diffuse/gather") and by how its
// constant blocks are declared (the library picks the variant it runs).
struct ShaderCode {
  const char* name = nullptr;
  bool constantsInStorageBuffers = false;
  const std::uint32_t* words = nullptr;
  std::size_t wordCount = 0;
};

struct SceneBridge {
  std::string name = "none";  // shown in logs and errors: "bvh"
  // Every shader of the library compiled with the bridge; empty: the
  // library's own, which trace nothing.
  std::vector<ShaderCode> shaders;
  std::vector<SceneResourceDecl> resources;
};

// What a bridge resource is bound to this frame: a buffer (BufferRef) or a
// sampled image (ImageRef in GENERAL or SHADER_READ_ONLY_OPTIMAL layout,
// read in place, and a sampler).
struct SceneResource {
  std::string name;
  BufferRef buffer;
  ImageRef image;
  VkSampler sampler = VK_NULL_HANDLE;
};

// A camera as engines keep it: column-major 4x4 matrices (m[column * 4 +
// row], as glm and GLSL store them). Views are right-handed and look down -Z
// with +Y up; the projection must be a symmetric perspective (what
// glm::perspective makes, with or without Vulkan's flipped Y), with any
// sub-pixel jitter given apart, in pixels.
struct Camera {
  float worldToView[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  float viewToClip[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  float jitter[2] = {0.0f, 0.0f};  // the G-buffer's sample of pixel (i, j) lies at (i + 0.5, j + 0.5) + jitter
};

// --- The signals the denoiser denoises (docs/gi.md, "The denoiser").
// Each signal is a noisy image of demodulated light with a hit distance
// (FrameInputs::noisy says what it holds), denoised on its own history.
// The library's two branches produce the first two; an engine may declare
// more of its own (ContextDesc::signals: its ambient occlusion, a second
// diffuse layer, ...), which the library denoises and leaves for the engine
// to read (GiContext::indirect), without compositing them.
enum class SignalKind : std::uint32_t {
  // Light through a wide lobe (a Lambert lobe, occlusion): blurred across
  // the surface's plane within a cone of normals, reprojected with the
  // surface.
  Diffuse = 0,
  // Light through a GGX lobe: blurred within the lobe by roughness and by
  // how far the light came from (a contact reflection stays sharp), and
  // reprojected with the reflection as well (virtual motion).
  Specular = 1,
};
// A signal's index: kDiffuseSignal, kSpecularSignal, then the engine's
// ContextDesc::signals in order (2, 3, ...).
using SignalId = std::uint32_t;
constexpr SignalId kDiffuseSignal = 0;   // the diffuse branch's signal (or the engine's in its place)
constexpr SignalId kSpecularSignal = 1;  // the specular branch's
// At most this many signals in all (the library's two included).
constexpr std::size_t kMaxSignals = 32;

// A signal an engine declares: its name (1-32 of a-z, 0-9 and '_', not
// "diffuse" or "specular"; its passes are gi.denoise.NAME.*) and its kind.
struct SignalDesc {
  std::string name;
  SignalKind kind = SignalKind::Diffuse;
};

// What the engine hands the library each frame. The frame covers the
// rectangle [0, width) x [0, height) of every image (images may be larger:
// the render size can change from frame to frame up to the context's
// maximum; a change of size restarts the history, as a camera cut does).
//
// Accepted formats (docs/conventions.md has the conventions):
//   viewZ              R32_SFLOAT, R16_SFLOAT: positive distance along the view axis; 0 = background
//   normalRoughness    R16G16B16A16_SFLOAT: world shading normal xyz, perceptual roughness w;
//                      A2B10G10R10_UNORM_PACK32: octahedral normal in rg, stored as
//                      encodeOctahedral(n) * 0.5 + 0.5 (shaders/shared/packing.glsl), roughness in b
//   baseColorMetallic  R8G8B8A8_UNORM, R8G8B8A8_SRGB: base colour rgb (linear once read), metallic a
//   motion             R16G16_SFLOAT, R32G32_SFLOAT: times Settings::input.motionScale, the
//                      offset in pixels from this frame's pixel to where it was in the last one
//   direct             R16G16B16A16_SFLOAT, R32G32B32A32_SFLOAT: direct light, linear HDR;
//                      background pixels show the sky
//   emissive           optional (image VK_NULL_HANDLE: `direct` holds the emission), as `direct`
//   environment        R16G16B16A16_SFLOAT or R32G32B32A32_SFLOAT equirect with a prefiltered mip
//                      chain (mip k = GGX roughness k / (levels - 1)): EnvironmentPrefilter makes one
//   noisy[id]          optional, R16G16B16A16_SFLOAT or R32G32B32A32_SFLOAT: a noisy signal of the
//                      engine's own for the library's denoiser (below)
//   materialId         optional, R8_UINT, R16_UINT or R32_UINT: a material id per pixel, of which
//                      the low 8 bits count (below)
// A NaN or infinite value in any input is treated as invalid (no surface,
// no light, no history), never passed on (docs/reliability.md).
struct FrameInputs {
  ImageRef viewZ;
  ImageRef normalRoughness;
  ImageRef baseColorMetallic;
  ImageRef motion;
  ImageRef direct;
  ImageRef emissive;
  // Optional (VK_NULL_HANDLE: every pixel is one material). The denoiser's
  // temporal passes reuse no history across a change of material id
  // (REBLUR's material test): where the surface stays put but its material
  // changes (a decal appears, an editor swaps a material, two materials
  // meet on one plane) the pixel's history starts over instead of blending
  // the old material's light into the new one's.
  ImageRef materialId;
  ImageRef environment;
  VkSampler environmentSampler = VK_NULL_HANDLE;  // linear, repeating in u, clamped in v
  std::uint32_t width = 0;                        // the render size, at most the context's maximum
  std::uint32_t height = 0;
  Camera camera;
  Camera previousCamera;  // ignored on a cut
  std::uint64_t frameIndex = 0;
  bool cameraCut = false;  // nothing of earlier frames is reused
  // The share of the light (0 to 1) the engine knows it changed since its
  // last frame: a lamp switched on or off, dimmed or brightened. The
  // library sees a change of light in the direct light and emission the
  // frame shows (gi.light_change; docs/gi.md "When the light changes"),
  // and a lamp off screen or smaller than a pixel (a small frame) changes
  // the indirect light with no trace there: its histories would go on
  // holding the old light. The larger of the two counts, so an engine that
  // knows of a change says so here (0: it declares none). Outside [0, 1]
  // or NaN: record() throws Error.
  float lightChange = 0.0f;
  // Copy every pass's output of this frame for debugging; collect() returns
  // the copies once the frame has run.
  bool captureStages = false;
  // Every resource ContextDesc::sceneBridge declares, bound for this frame
  // (none for the bridge "none").
  std::vector<SceneResource> sceneResources;

  // --- The denoiser on the engine's own signals (docs/gi.md, "Denoising an
  // engine's own signals"), by SignalId: noisy[id] (entries past the end,
  // or with image VK_NULL_HANDLE, are not given). Needs
  // Settings::denoise.enabled (record() throws Error otherwise).
  //   noisy[kDiffuseSignal], noisy[kSpecularSignal]: an engine that has a
  //        noisy indirect diffuse or specular signal of its own (its path
  //        tracer's, its ray-traced reflections at one sample a pixel, ...)
  //        hands it over here, and the library denoises it in place of the
  //        branch that makes that signal: the branch records none of its
  //        passes this frame, and indirect(id) and composite() hold the
  //        engine's signal, denoised (and remodulated by the composite).
  //        Starting or stopping to give one of these restarts every history
  //        for that frame, as a camera cut does. When every enabled
  //        branch's signal comes from the engine, no branch runs and
  //        `environment` (and its sampler) may be left out.
  //   noisy[2...]: the signals of ContextDesc::signals, denoised into
  //        indirect(id) on the frames they are given (a frame without one
  //        leaves its result as it was; the next frame that gives it starts
  //        its history over). The composite does not read them.
  // Each image holds (R16G16B16A16_SFLOAT or R32G32B32A32_SFLOAT):
  //   rgb  demodulated radiance, linear HDR, as the library's own:
  //        diffuse the light arriving through a white Lambert lobe (the
  //        composite multiplies it by base colour (1 - metallic));
  //        specular the GGX lobe's reflected light divided by
  //        specularReflectance(F0, n.v, roughness) of shaders/shared/brdf.glsl
  //        (the composite multiplies it back); an engine's own signal
  //        whatever it denoises (occlusion in all three channels, ...)
  //   a    the distance in world units from the surface to where the light
  //        came from (the first hit of the ray or path; averaged over a
  //        pixel's samples), 0 where unknown; a ray that escaped to the
  //        sky: any distance beyond the scene. It sets how far the
  //        specular blur may reach (a contact reflection stays sharp).
  // Checkerboard mode (Settings::denoise.checkerboard, REBLUR's): an
  // engine that traces every other pixel hands each signal packed to
  // ceil(width / 2) x height, pixel (x, y) of the frame at (x / 2, y), for
  // the pixels where x + y + frameIndex is odd in signals of kind Diffuse
  // and even in signals of kind Specular (shaders/shared/checkerboard.glsl;
  // a diffuse and a specular signal together cover every pixel of a
  // frame). The denoiser fills the other pixels from their neighbours on
  // the same surface. The branches' signals stay full.
  // NaN and infinite radiance counts as no light, a non-finite or negative
  // distance as unknown.
  std::vector<ImageRef> noisy;
  // The names of noisy[kDiffuseSignal] and noisy[kSpecularSignal] before
  // signals went by id, kept for one release (deprecated): each is read as
  // that entry of `noisy`. Give a signal in one place only (the same image
  // in both is taken; two different ones are refused).
  ImageRef noisyDiffuse;
  ImageRef noisySpecular;
};

// What the library does with the engine's input images after its passes.
enum class InputState {
  // Transitioned back to the layout they had (ImageRef::layout), after a
  // barrier from the library's reads to the stage and access they had: the
  // engine can go on as if the library had not been there.
  Restore,
  // Left in VK_IMAGE_LAYOUT_GENERAL, last used by compute-shader sampled
  // reads; the engine barriers from there.
  LeaveGeneral,
};

struct ContextDesc {
  std::uint32_t maxWidth = 0;  // the largest render size; the library's images are this big
  std::uint32_t maxHeight = 0;
  // Frames the engine has in flight at most: record() of frame N may reuse
  // what frame N - framesInFlight used (timestamp queries, stage copies).
  std::uint32_t framesInFlight = 2;
  bool timestamps = true;  // time every pass (collect() returns the times)
  InputState inputState = InputState::Restore;
  SceneBridge sceneBridge;  // "none": screen space only
  // The engine's own signals for the denoiser, beyond the library's two:
  // SignalId 2, 3, ... in this order (FrameInputs::noisy, indirect()).
  // Needs Settings::denoise.enabled; each adds its histories to the
  // denoiser's memory (estimateMemoryBytes counts them).
  std::vector<SignalDesc> signals;
};

// How an image of the library is best looked at (bounce --dump-stages uses it).
enum class Visualization {
  Radiance,  // linear HDR: exposure + tonemap + sRGB
  Color,     // linear [0,1] colour: sRGB encode
  Signed,    // [-1,1] vectors: x * 0.5 + 0.5
  Range,     // scalar data: min..max to black..white
  Raw,       // stored values, clamped to [0,1]
  Motion,    // 2D vectors, scaled by the largest
  Ids,       // integer labels: a colour each
  Heat,      // positive scalars spanning decades: log scale, magma colours
};

// An image the library owns, in the state the last record() left it: layout
// GENERAL, last written by a compute shader (stage COMPUTE_SHADER, access
// SHADER_STORAGE_WRITE). The engine may read it (sample it, copy it) with a
// barrier from there; if it moves it to another layout it must move it back
// to GENERAL before the next record(), with a barrier whose destination is
// stage COMPUTE_SHADER, access kLibraryImageAccess (the library's passes
// read some of its images as sampled images).
inline constexpr VkAccessFlags2 kLibraryImageAccess =
    VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;

struct LibraryImage {
  std::string name;  // e.g. "gi.diffuse.reservoirs0"
  ImageRef image;
  Visualization visualization = Visualization::Raw;
  std::string purpose;
};

// Device memory of one unit of the library: "diffuse", "specular",
// "cache" (the radiance cache), "denoise", "frame" (what the frame level
// holds: histories of the surface and the composite, the depth pyramid,
// constants, ray counters), or "transient" (the memory the units'
// frame-local images share).
struct UnitMemory {
  std::string unit;
  std::uint64_t bytes = 0;
};

struct PassTiming {
  std::uint64_t frameIndex = 0;
  std::string pass;  // e.g. "gi.diffuse.resolve"
  double milliseconds = 0.0;
  // What its bindings cover, each once: the least the pass must move (its
  // traffic floor; bytes / the device's bandwidth is the shortest time it
  // can take). Images count the levels bound at their full size; storage
  // buffers count whole, apart, as some are sized for the worst case and
  // the pass touches less of them.
  std::uint64_t imageBytes = 0;
  std::uint64_t bufferBytes = 0;
};

// A copy of one image a pass wrote, taken right after that pass ran (so
// later passes that reuse the image do not hide it). Texels of mip 0,
// tightly packed rows, in `format`.
struct CapturedStage {
  std::uint64_t frameIndex = 0;
  std::string pass;     // e.g. "gi.diffuse.resolve"
  std::string binding;  // the shader's name for it, e.g. "gOut_Diffuse"
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  VkFormat format = VK_FORMAT_UNDEFINED;
  Visualization visualization = Visualization::Raw;
  std::vector<std::uint8_t> texels;
};

// What the world rays of a frame were for (docs/gi-settings.md, "World
// rays"): every ray the library casts through the scene bridge, and the
// shadow rays the bridge reports casting to light the library's hits.
enum class WorldRayPurpose : std::uint32_t {
  DiffuseCandidates,  // gi.diffuse.gather: closest-hit ray candidates
  SkyReuse,           // gi.diffuse.spatial_reuse: is the sky open from a neighbour?
  ReuseVisibility,    // temporal and spatial reuse with gi.diffuse.reuse_visibility
  SampleVisibility,   // gi.diffuse.sample_visibility: each reservoir's sample
  ResolveVisibility,  // gi.diffuse.resolve with gi.diffuse.visibility world
  Specular,           // gi.specular.trace: rays screen space cannot finish
  CacheUpdate,        // gi.cache.update
  HitShadows,         // the bridge's shadow rays lighting what rays hit
  Count
};
constexpr std::size_t kWorldRayPurposeCount = std::size_t(WorldRayPurpose::Count);
// "diffuse_candidates", "sky_reuse", ... (the JSON keys of bounce bench).
const char* worldRayPurposeName(WorldRayPurpose purpose);

// The passes that cast world rays (the counters of gi/world_ray_count.glsl).
constexpr std::size_t kWorldRayPassCount = 10;
// The pass's name as its timings carry it: "gi.diffuse.gather",
// "gi.diffuse.world_candidates", ... "gi.cache.update" (pass < kWorldRayPassCount).
const char* worldRayPassName(std::size_t pass);

// The world rays one frame cast, by purpose and by the pass that cast them
// (all 0 with the bridge "none"); both add up to the same total.
struct WorldRayCount {
  std::uint64_t frameIndex = 0;
  std::array<std::uint64_t, kWorldRayPurposeCount> rays{};
  std::array<std::uint64_t, kWorldRayPassCount> passRays{};  // by worldRayPassName's numbering
  // The entries of its world queue each pass took up (the pixels or tests
  // an earlier pass left it to trace; 0 for passes that trace without one).
  std::array<std::uint64_t, kWorldRayPassCount> passQueued{};
  std::uint64_t total() const;
};

struct FrameResults {
  std::vector<PassTiming> timings;       // in recorded order, frame by frame
  std::vector<CapturedStage> stages;
  std::vector<WorldRayCount> worldRays;  // one per frame collected
};

class GiContext {
 public:
  // Creates the library's images (pooled in a few allocations of device
  // memory), samplers and pipelines on the engine's device. Throws Error
  // when the device lacks what the library needs, when the size is 0 or
  // above 16384, and for settings gi_settings.h's validate() refuses.
  GiContext(const Device& device, const ContextDesc& desc, const Settings& settings = {});
  ~GiContext();
  GiContext(const GiContext&) = delete;
  GiContext& operator=(const GiContext&) = delete;

  // Records every pass of one frame into `commandBuffer`, which is in the
  // recording state and will be submitted to a queue of Device::queueFamily
  // after everything recorded before and before everything recorded after.
  // Transitions what it needs and leaves inputs as ContextDesc::inputState
  // says. Throws Error naming the input when an image is missing, too
  // small for the render size (a checkerboarded noisy signal: for half its
  // width), of a format not listed above, or a camera is
  // not finite or not a symmetric perspective, and for a noisy signal
  // given while the denoiser is off.
  void record(VkCommandBuffer commandBuffer, const FrameInputs& frame);

  // Timings and stage copies of the frames recorded so far whose command
  // buffers have completed: the engine passes the index of the last frame it
  // knows has finished on the GPU (after waiting on its fence). Throws Error
  // for a frame index never recorded.
  FrameResults collect(std::uint64_t completedFrameIndex);

  // A signal denoised, demodulated; alpha the history length in frames.
  // With the denoiser on (the default), its result, RGBA16F; with it off,
  // the branch's own temporal filter, RGBA32F (that filter's history does
  // not round its half stores). With FrameInputs::noisy[id] given, the
  // engine's signal denoised. See LibraryImage for its state.
  //   kDiffuseSignal   indirect diffuse: light arriving through a white
  //                    Lambert lobe; multiply by base colour (1 - metallic)
  //   kSpecularSignal  indirect specular: divided by shaders/shared/brdf.glsl's
  //                    specularReflectance(F0, n.v, roughness); multiply by it
  //   2, 3, ...        ContextDesc::signals, denoised (as of the last frame
  //                    that gave them; zero before the first)
  // Throws Error for an id the context does not have.
  ImageRef indirect(SignalId signal) const;
  // Every signal the context denoises, by SignalId: "diffuse" and
  // "specular" (their kinds), then ContextDesc::signals.
  std::vector<SignalDesc> signals() const;
  // indirect(kDiffuseSignal) and indirect(kSpecularSignal) by their names
  // before signals went by id, kept for one release (deprecated).
  ImageRef indirectDiffuse() const;
  ImageRef indirectSpecular() const;
  // The composited frame: linear HDR, RGBA16F.
  ImageRef composite() const;
  // Every image of the library, by name (history, reservoirs, intermediate
  // results), but the transient ones: images a unit writes and reads only
  // while it records share memory with other units' (docs/passes.md), so
  // after a frame they hold no stage of their own; captureStages copies
  // them right after each pass.
  std::vector<LibraryImage> images() const;

  // Device memory the library holds (its images and buffers), in bytes.
  std::uint64_t memoryBytes() const;
  // The same by unit (each image's and buffer's own bytes, named
  // gi.UNIT.*; the pools' unused tails, in memoryBytes(), are in none),
  // in the order diffuse, specular, cache, denoise, frame, then
  // "transient": the pool the units' transient images share (the most
  // one unit's take).
  std::vector<UnitMemory> memoryByUnit() const;
  // What memoryBytes() of a context made with `desc` and `settings` will be,
  // before making it (its images' and buffers' bytes; the few MiB the pools
  // round up to are not counted): to refuse a size the device cannot hold
  // before anything is allocated.
  static std::uint64_t estimateMemoryBytes(const ContextDesc& desc, const Settings& settings = {});
  const Settings& settings() const;
  std::uint32_t maxWidth() const;
  std::uint32_t maxHeight() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// What EnvironmentPrefilter makes: an equirectangular image of `width` x
// `height` texels (2:1 is what the mapping expects) whose mip k is the
// environment prefiltered for GGX perceptual roughness k / (levels - 1);
// levels down to 8 texels tall, at most maxMipLevels.
struct PrefilterDesc {
  std::uint32_t width = 1024;  // 8..16384
  std::uint32_t height = 512;  // 4..8192
  std::uint32_t maxMipLevels = 6;      // 1..16
  std::uint32_t samplesPerTexel = 256;  // GGX samples of each prefiltered texel, 1..65536
};

// The environment input the library needs, made from an equirectangular HDR
// image of the engine's (linear radiance, any size): a copy resampled to the
// desc's size with a GGX-prefiltered mip chain, and the sampler to read it
// with (linear, repeating in u across the seam, clamped at the poles).
// Recorded into the engine's command buffer like GiContext.
class EnvironmentPrefilter {
 public:
  // Throws Error for a desc out of range and for what GiContext's
  // constructor refuses about the device.
  EnvironmentPrefilter(const Device& device, const PrefilterDesc& desc = {});
  ~EnvironmentPrefilter();
  EnvironmentPrefilter(const EnvironmentPrefilter&) = delete;
  EnvironmentPrefilter& operator=(const EnvironmentPrefilter&) = delete;

  // Records the prefiltering of `equirect` (R16G16B16A16_SFLOAT or
  // R32G32B32A32_SFLOAT, sampled; `view` shows its mip 0; handed back as
  // InputState::Restore says). Record it when the environment changes,
  // before the frames that use it. Throws Error for a missing image, a
  // format not listed or an UNDEFINED layout (the message names them).
  // `captureStages`: copy every pass's output, for collect().
  void record(VkCommandBuffer commandBuffer, const ImageRef& equirect, bool captureStages = false);
  // The pass times (timings' frameIndex 0) and stage copies of the last
  // record(), once its command buffer has completed; empty after the first
  // call. Throws Error when the command buffer has not completed.
  FrameResults collect();

  // The prefiltered environment for FrameInputs::environment: R16G16B16A16_SFLOAT,
  // all mipLevels() in its view; once record() has run, in layout GENERAL,
  // last written by a compute shader (stage COMPUTE_SHADER, access SHADER_STORAGE_WRITE).
  ImageRef output() const;
  VkSampler sampler() const;
  std::uint32_t mipLevels() const;
  std::uint64_t memoryBytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The Camera of a view whose basis and field of view are given directly:
// `right`, `up`, `forward` orthonormal (x, y, z each), fovY in radians,
// aspect = width / height.
Camera cameraFromBasis(const float position[3], const float right[3], const float up[3], const float forward[3],
                       float fovY, float aspect, const float jitter[2] = nullptr);

}  // namespace bounce::gi
