// The Bounce GI library: screen-space ReSTIR global illumination for an
// engine's G-buffer. It sees images and camera matrices, never a scene.
//
//   gi::GiContext gi(device, width, height, settings);
//   every frame, after the engine's G-buffer and direct light:
//     gi.record(recorder, inputs);            // into the engine's command buffer
//     ... present or read gi.composite() (HDR), gi.indirectDiffuse() ...
//
// The passes it records (docs/passes.md has each one's inputs and outputs):
//   gi.store_history                    this frame's depth and normals, for the next frame
//   gi.diffuse.bright_pixels            2x2 -> 1 reductions of the previous frame to its brightest pixels
//   gi.diffuse.gather                   half res: candidates from the previous frame, the brightest
//                                       pixels and the environment into one reservoir per pixel
//   gi.diffuse.temporal_reuse           half res: merge with last frame's reservoir (ReSTIR)
//   gi.diffuse.spatial_reuse            half res: merge with neighbours, twice (ReSTIR)
//   gi.diffuse.resolve                  full res: each pixel evaluates nearby reservoirs with
//                                       screen-space visibility -> indirect diffuse
//   gi.diffuse.temporal_filter          full res: reprojected, variance-clipped history
//   gi.composite                        direct + albedo * indirect diffuse (+ emission)
// The composite is what the next frame's gathering samples, so light keeps
// bouncing from frame to frame.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>
#include <glm/glm.hpp>

#include "bounce/gi_settings.h"
#include "gpu/context.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"

namespace bounce::gi {

// A camera as engines keep it. Views are right-handed and look down -Z
// with +Y up; the projection must be a symmetric perspective (what
// glm::perspective makes, with or without Vulkan's flipped Y), with any
// sub-pixel jitter given apart, in pixels.
struct Camera {
  glm::mat4 worldToView{1.0f};
  glm::mat4 viewToClip{1.0f};
  glm::vec2 jitter{0.0f};  // the G-buffer's sample of pixel (i, j) lies at (i + 0.5, j + 0.5) + jitter
};

// What the engine hands the library each frame: its images (all the
// context's size, in these formats; docs/conventions.md) and cameras. No
// image value is trusted to be finite: NaN or infinity in an input makes that
// pixel background, a disocclusion or no light (docs/gi.md, "Non-finite
// inputs"), and nothing the library stores is ever non-finite.
struct FrameInputs {
  gpu::Image* viewZ = nullptr;                    // r32f: positive distance along the view axis; 0 = background
  gpu::Image* normalRoughness = nullptr;          // rgba16f: world shading normal, perceptual roughness
  gpu::Image* baseColorMetallic = nullptr;        // rgba8: linear base colour, metallic
  gpu::Image* motion = nullptr;                   // rg16f: pixels, previous position = current + motion
  gpu::Image* direct = nullptr;                   // rgba16f: direct light, linear HDR; background pixels show the sky
  gpu::Image* emissive = nullptr;                 // optional rgba16f: emission, added by the composite (leave null
                                                  // when `direct` already holds it)
  gpu::Image* environment = nullptr;              // rgba16f equirect with a prefiltered mip chain (mip k = GGX
                                                  // roughness k / (levels - 1)); sampled
  VkSampler environmentSampler = VK_NULL_HANDLE;  // repeats in u
  Camera camera;
  Camera previousCamera;  // ignored on a cut
  std::uint64_t frameIndex = 0;
  bool cameraCut = false;  // nothing of earlier frames is reused
};

// An image the library made, for --dump-stages and debugging.
struct NamedImage {
  std::string name;
  gpu::Image* image;
};

class GiContext {
 public:
  // Throws std::invalid_argument for bad settings or sizes (0, or above 16384).
  GiContext(gpu::Context& device, std::uint32_t width, std::uint32_t height, const Settings& settings = {});
  ~GiContext();
  GiContext(const GiContext&) = delete;
  GiContext& operator=(const GiContext&) = delete;

  // Records every pass for one frame. Throws std::invalid_argument naming the
  // input when an image is missing, of the wrong size or format, or a camera
  // is not finite or not a symmetric perspective.
  void record(gpu::Recorder& recorder, const FrameInputs& frame);

  // Indirect diffuse after the temporal filter, demodulated (light arriving
  // through a white Lambert lobe; multiply by base colour (1 - metallic)).
  gpu::Image& indirectDiffuse();
  // The composited HDR frame (rgba16f).
  gpu::Image& composite();
  // Every image of the library (history, reservoirs, intermediate results).
  std::vector<NamedImage> images();

  const Settings& settings() const;
  std::uint32_t width() const;
  std::uint32_t height() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The Camera for a view whose basis and field of view are given directly:
// `right`, `up`, `forward` orthonormal, fovY in radians, aspect = width / height.
Camera cameraFromBasis(glm::vec3 position, glm::vec3 right, glm::vec3 up, glm::vec3 forward, float fovY, float aspect,
                       glm::vec2 jitter = glm::vec2(0.0f));

}  // namespace bounce::gi
