// The reference path tracer: ground truth for one frame of a FrameRenderer,
// split into the same images the GI passes make (docs/reference.md):
//
//   direct             render.direct_light's image (exact: delta lights, one shadow ray)
//   indirect diffuse   demodulated: incoming light through the Lambert lobe of albedo 1
//   indirect specular  demodulated: the GGX lobe's reflected light / specularReflectance()
//   radiance           direct + base colour (1 - metallic) diffuse + specularReflectance specular
//
// Passes:
//   render.reference_path     adds samples per pixel to running sums (even ones to half A, odd to B)
//   render.reference_resolve  running sums -> the images above
//
// Usage: record the frame with the FrameRenderer and let it finish (the
// light distributions read the environment it built), then
//
//   ReferenceRenderer reference(context, frameRenderer, scene, frameIndex, time, options);
//   while (reference.samplesPerPixel() < wanted)
//     reference.record(loop.beginFrame(), wanted - reference.samplesPerPixel()), loop.endFrame();
//   ReferenceImages images = reference.resolve(loop, ReferenceHalf::Both);
//
// A path-traced sequence at a few samples per pixel (bounce denoise): per
// frame, record it with the FrameRenderer, then in the same command buffer
//
//   reference.restart(recorder, frameIndex, time);
//   while (reference.samplesPerPixel() < spp) reference.record(recorder, spp - reference.samplesPerPixel());
//   reference.recordResolve(recorder);   // indirectDiffuseImage() etc. now hold this frame's
#pragma once

#include <cstdint>
#include <memory>

#include "gpu/context.h"
#include "gpu/frame_loop.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"
#include "io/image_io.h"
#include "render/frame_renderer.h"
#include "render/light_sampling.h"
#include "render/reference_types.glsl"
#include "scene/scene.h"

namespace bounce::render {

struct ReferenceOptions {
  std::uint32_t maxBounces = 24;      // surfaces a path may bounce off after the primary hit
  std::uint32_t rouletteBounces = 3;  // Russian roulette from this bounce on
  std::uint32_t seed = 0;             // other seeds give independent noise; the same seed the same bits
  // Samples per pixel a dispatch adds at most (0: automatic, about a million
  // paths per dispatch on a GPU, so small images do not pay a submission per
  // sample; 1 on a CPU device, see reference_renderer.cpp).
  std::uint32_t samplesPerDispatch = 0;
  // The material lobes paths follow: shared::kLobesAll, or one lobe for
  // closed-form tests (a Lambert or mirror furnace).
  std::uint32_t lobes = shared::kLobesAll;
};

enum class ReferenceHalf { Both, A, B };

struct ReferenceImages {
  io::ImageF radiance;               // RGB
  io::ImageF direct;                 // RGB
  io::ImageF indirectDiffuse;        // RGB, demodulated
  io::ImageF indirectSpecular;       // RGB, demodulated
  std::uint64_t droppedSamples = 0;  // non-finite path samples left out (should be 0)
};

class ReferenceRenderer {
 public:
  // `frameIndex` is the FrameRenderer frame whose G-buffer and constants are
  // traced from, `time` the scene time it was rendered at. Reads the
  // environment back (blocking) to build its light distribution. `scene` is
  // kept by reference for restart(), as the FrameRenderer keeps it.
  ReferenceRenderer(gpu::Context& context, FrameRenderer& frame, const scene::Scene& scene, std::uint64_t frameIndex,
                    float time, const ReferenceOptions& options);
  ~ReferenceRenderer();
  // The bytes of its images at a render size (the sums of both halves, the
  // resolved frame and parts; the environment's distribution comes on top).
  static std::uint64_t frameImageBytes(std::uint32_t width, std::uint32_t height);

  // Adds up to `samples` samples per pixel (one dispatch; fewer when
  // samplesPerDispatch is smaller); returns how many it added. Throws
  // gpu::GpuError when the FrameRenderer's materials changed since the
  // reference (re)started: its sums and light list hold the old ones, so
  // restart() it first.
  std::uint32_t record(gpu::Recorder& recorder, std::uint32_t samples);
  std::uint64_t samplesPerPixel() const { return samples_; }
  // Whether the FrameRenderer's materials changed (setMaterial) since the
  // last (re)start: record() refuses until restart().
  bool materialsChanged() const { return frame_.materialRevision() != materialRevision_; }
  std::uint64_t samplesPerPixel(ReferenceHalf half) const;

  // Records the resolve into a frame of `loop`, waits, reads the images back.
  ReferenceImages resolve(gpu::FrameLoop& loop, ReferenceHalf half);

  // Starts over on another frame of the FrameRenderer (frame `frameIndex`,
  // the scene at `time`): records the clearing of the sums, and
  // samplesPerPixel() is 0 again. The samples drawn next are numbered on
  // from every sample drawn before, so each frame's noise is independent
  // of the earlier frames'. In an animated scene, and after
  // FrameRenderer::setMaterial, the emissive triangles are made anew (for
  // `time`, from the renderer's materials; blocking): the frames that used
  // the old ones must have completed (FrameLoop::finish()).
  void restart(gpu::Recorder& recorder, std::uint64_t frameIndex, float time);
  // Records the resolve of the samples so far (as resolve() does) without
  // waiting or reading back: the images below hold them once it has run.
  void recordResolve(gpu::Recorder& recorder, ReferenceHalf half = ReferenceHalf::Both);
  // rgba32f: the frame; indirect diffuse and specular, demodulated, alpha
  // the mean first-hit distance of their paths in world units
  // (shared::kEscapedHitDistance for the sky, 0 where no path had a ray):
  // the signals FrameInputs::noisy[kDiffuseSignal] and noisy[kSpecularSignal] take.
  gpu::Image& radianceImage() { return *radiance_; }
  gpu::Image& indirectDiffuseImage() { return *diffuse_; }
  gpu::Image& indirectSpecularImage() { return *specular_; }

  std::size_t emissiveTriangleCount() const { return emissiveCount_; }
  bool samplesEnvironment() const { return environmentWidth_ > 0; }
  std::uint32_t samplesPerDispatch() const { return samplesPerDispatch_; }

 private:
  void uploadEmissiveTriangles(float time);
  void clearSums(gpu::Recorder& recorder);

  gpu::Context& context_;
  FrameRenderer& frame_;
  const scene::Scene& scene_;
  std::uint64_t frameIndex_;
  float time_;                          // the scene time the emissive triangles are placed at
  std::uint64_t materialRevision_ = 0;  // the FrameRenderer's materialRevision() they were made from
  ReferenceOptions options_;
  std::uint32_t samplesPerDispatch_ = 1;
  std::uint32_t environmentWidth_ = 0, environmentHeight_ = 0;
  std::size_t emissiveCount_ = 0;
  float emissivePower_ = 0.0f;
  std::uint64_t samples_ = 0;     // since the last restart
  std::uint64_t sampleBase_ = 0;  // drawn before it
  std::unique_ptr<gpu::Buffer> environmentCdf_, emissiveTriangles_;
  std::unique_ptr<gpu::Image> diffuseSum_[2], specularSum_[2];  // [0] half A, [1] half B
  std::unique_ptr<gpu::Image> hitDistanceSum_;                  // both halves
  std::unique_ptr<gpu::Image> radiance_, diffuse_, specular_;
  std::unique_ptr<gpu::ComputePass> pathPass_, resolvePass_;
};

}  // namespace bounce::render
