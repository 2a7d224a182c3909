// GiContext: owns the GI library's images and passes and records one frame.
// The order of the passes and why each reads what it reads is in
// include/bounce/gi.h; docs/gi.md explains the algorithm.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "bounce/gi.h"
#include "gi/gi_types.glsl"
#include "gi/passes.h"
#include "gpu/format.h"
#include "gpu/pass.h"

namespace bounce::gi {
namespace {

using shared::GiFrameConstants;
using shared::ScreenView;

using namespace gpu::formats;

bool finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

// The ScreenView of a camera; throws for what the library cannot use.
ScreenView screenView(const Camera& camera, const char* which) {
  const auto fail = [&](const std::string& why) {
    return std::invalid_argument(std::string("gi: ") + which + ": " + why);
  };
  const glm::mat4& p = camera.viewToClip;
  if (!finite(camera.worldToView) || !finite(p) || !std::isfinite(camera.jitter.x) || !std::isfinite(camera.jitter.y))
    throw fail("camera matrices and jitter must be finite");
  if (!(p[0][0] > 0.0f) || p[1][1] == 0.0f || std::abs(p[2][3] + 1.0f) > 1e-5f || std::abs(p[3][3]) > 1e-6f)
    throw fail("viewToClip must be a perspective projection looking down -Z (as glm::perspective makes)");
  if (std::abs(p[2][0]) > 1e-6f || std::abs(p[2][1]) > 1e-6f)
    throw fail("viewToClip must be symmetric; give sub-pixel jitter in Camera::jitter instead");
  const glm::mat4 viewToWorld = glm::inverse(camera.worldToView);
  if (!finite(viewToWorld)) throw fail("worldToView is not invertible");
  return {camera.worldToView, viewToWorld, glm::vec4(1.0f / p[0][0], 1.0f / std::abs(p[1][1]), camera.jitter)};
}

gpu::ImageDesc imageDesc(const std::string& name, std::uint32_t width, std::uint32_t height, VkFormat format,
                         gpu::Visualize visualize) {
  return {.name = name, .width = width, .height = height, .format = format, .visualize = visualize};
}

}  // namespace

Camera cameraFromBasis(glm::vec3 position, glm::vec3 right, glm::vec3 up, glm::vec3 forward, float fovY, float aspect,
                       glm::vec2 jitter) {
  glm::mat4 viewToWorld(glm::vec4(right, 0.0f), glm::vec4(up, 0.0f), glm::vec4(-forward, 0.0f),
                        glm::vec4(position, 1.0f));
  const float tanHalf = std::tan(fovY * 0.5f);
  glm::mat4 projection(0.0f);
  projection[0][0] = 1.0f / (tanHalf * aspect);
  projection[1][1] = 1.0f / tanHalf;
  projection[2][2] = -1.0f;
  projection[2][3] = -1.0f;
  projection[3][2] = -0.1f;  // near plane 0.1: only the depth row needs one, and GI reads no clip depth
  return {glm::inverse(viewToWorld), projection, jitter};
}

struct GiContext::Impl {
  gpu::Context& device;
  std::uint32_t width, height, halfWidth, halfHeight;
  Settings settings;
  bool hasHistory = false;
  Camera lastCamera;
  std::uint64_t lastFrame = 0;  // the index of the last frame recorded: its images are the current ones

  std::unique_ptr<gpu::Buffer> constants;
  gpu::HistoryImage surface, composite, filtered, moments, reservoir0, reservoir1;
  // Reservoir images: the fresh ones, the first spatial pass's, and those of
  // the stage not kept for the next frame (temporal or second spatial,
  // whichever DiffuseSettings::spatialFeedback does not keep).
  std::unique_ptr<gpu::Image> gathered0, gathered1, transient0, transient1, spatial0, spatial1, diffuse;
  std::vector<std::unique_ptr<gpu::Image>> brightLevels;
  std::unique_ptr<gpu::Image> viewEstimate, viewM, viewW;

  std::unique_ptr<gpu::ComputePass> storeHistory, brightPixels, brightReduce, gather, temporalReuse, spatialReuse,
      resolve, temporalFilter, compositor;
  std::vector<std::unique_ptr<gpu::ComputePass>> reservoirViews;  // created on the first captured frame

  Impl(gpu::Context& device, std::uint32_t w, std::uint32_t h, const Settings& s)
      : device(device),
        width(w),
        height(h),
        halfWidth((w + 1) / 2),
        halfHeight((h + 1) / 2),
        settings(s),
        surface(device, imageDesc("gi.history_surface", w, h, kRg32ui, gpu::Visualize::Raw)),
        composite(device, imageDesc("gi.composite", w, h, kRgba16f, gpu::Visualize::Radiance)),
        filtered(device, imageDesc("gi.diffuse.filtered", w, h, kRgba16f, gpu::Visualize::Radiance)),
        moments(device, imageDesc("gi.diffuse.moments", w, h, kRg32f, gpu::Visualize::Raw)),
        reservoir0(device, imageDesc("gi.diffuse.reservoirs0", halfWidth, halfHeight, kRgba32ui, gpu::Visualize::Raw)),
        reservoir1(device, imageDesc("gi.diffuse.reservoirs1", halfWidth, halfHeight, kRgba32ui, gpu::Visualize::Raw)) {
    const auto half = [&](const char* name) {
      return std::make_unique<gpu::Image>(device,
                                          imageDesc(name, halfWidth, halfHeight, kRgba32ui, gpu::Visualize::Raw));
    };
    gathered0 = half("gi.diffuse.gathered0");
    gathered1 = half("gi.diffuse.gathered1");
    transient0 = half("gi.diffuse.transient0");
    transient1 = half("gi.diffuse.transient1");
    spatial0 = half("gi.diffuse.spatial0");
    spatial1 = half("gi.diffuse.spatial1");
    diffuse = std::make_unique<gpu::Image>(device,
                                           imageDesc("gi.diffuse.resolved", w, h, kRgba16f, gpu::Visualize::Radiance));
    // The bright-pixel pyramid: halve until about settings.diffuse.brightPixels entries remain.
    std::uint32_t levelWidth = w, levelHeight = h;
    do {
      levelWidth = (levelWidth + 1) / 2;
      levelHeight = (levelHeight + 1) / 2;
      brightLevels.push_back(std::make_unique<gpu::Image>(
          device, imageDesc("gi.diffuse.bright_level" + std::to_string(brightLevels.size() + 1), levelWidth,
                            levelHeight, kRgba32f, gpu::Visualize::Raw)));
    } while (levelWidth * levelHeight > settings.diffuse.brightPixels && (levelWidth > 1 || levelHeight > 1));

    constants = std::make_unique<gpu::Buffer>(device, "gi.frame_constants", sizeof(GiFrameConstants),
                                              gpu::BufferUsage::DeviceLocal);
    const auto make = [&](gpu::PassDesc desc) { return std::make_unique<gpu::ComputePass>(device, std::move(desc)); };
    storeHistory = make(storeHistoryPass());
    brightPixels = make(brightPixelsPass());
    brightReduce = make(brightPixelsReducePass());
    gather = make(gatherPass());
    temporalReuse = make(temporalReusePass());
    spatialReuse = make(spatialReusePass());
    resolve = make(resolvePass());
    temporalFilter = make(temporalFilterPass());
    compositor = make(gi::compositePass());
  }

  void checkInputs(const FrameInputs& frame) const {
    const auto check = [&](gpu::Image* image, const char* name, VkFormat format) {
      if (!image) throw std::invalid_argument(std::string("gi: frame input ") + name + " is missing");
      if (image->width() != width || image->height() != height)
        throw std::invalid_argument(std::string("gi: frame input ") + name + " '" + image->name() + "' is " +
                                    std::to_string(image->width()) + "x" + std::to_string(image->height()) +
                                    "; the context is " + std::to_string(width) + "x" + std::to_string(height));
      if (format != VK_FORMAT_UNDEFINED && image->format() != format)
        throw std::invalid_argument(std::string("gi: frame input ") + name + " '" + image->name() +
                                    "' has the wrong format (include/bounce/gi.h lists each input's)");
    };
    check(frame.viewZ, "viewZ", kR32f);
    check(frame.normalRoughness, "normalRoughness", kRgba16f);
    check(frame.baseColorMetallic, "baseColorMetallic", kRgba8);
    check(frame.motion, "motion", kRg16f);
    check(frame.direct, "direct", kRgba16f);
    if (frame.emissive) check(frame.emissive, "emissive", kRgba16f);
    if (!frame.environment || frame.environmentSampler == VK_NULL_HANDLE)
      throw std::invalid_argument("gi: frame input environment (image and sampler) is missing");
  }

  GiFrameConstants frameConstants(const FrameInputs& frame, bool usableHistory) const {
    const DiffuseSettings& d = settings.diffuse;
    GiFrameConstants c{};
    c.view = screenView(frame.camera, "camera");
    // Last frame's images were made with the camera given last frame; the
    // engine's previousCamera is that same camera unless it cut.
    c.previousView = usableHistory ? screenView(frame.previousCamera, "previousCamera")
                     : hasHistory  ? screenView(lastCamera, "last frame's camera")
                                   : c.view;
    c.size = glm::vec4(float(width), float(height), 1.0f / float(width), 1.0f / float(height));
    c.halfSize = glm::vec4(float(halfWidth), float(halfHeight), 1.0f / float(halfWidth), 1.0f / float(halfHeight));
    c.frame =
        glm::uvec4(std::uint32_t(frame.frameIndex), usableHistory ? 0u : 1u, settings.seed, settings.restir ? 1u : 0u);
    // Without last frame's composite there is nothing on screen to gather from.
    c.candidates = glm::uvec4(hasHistory ? d.screenCandidates : 0u, hasHistory ? d.brightCandidates : 0u,
                              d.environmentCandidates, std::uint32_t(d.target));
    const gpu::Image& lastLevel = *brightLevels.back();
    c.brightLevel = glm::uvec4(lastLevel.width(), lastLevel.height(), std::uint32_t(brightLevels.size()), 0u);
    c.options = glm::uvec4(d.resolveReservoirs, frame.emissive ? 1u : 0u, 0u, 0u);
    c.temporal = glm::vec4(d.temporalDepthTolerance, std::cos(glm::radians(d.temporalNormalToleranceDegrees)),
                           float(d.temporalMaxM), d.environmentMip);
    c.spatial = glm::vec4(std::cos(glm::radians(d.spatialNormalToleranceDegrees)), d.spatialPlaneTolerance,
                          d.jacobian ? 1.0f : 0.0f, d.offscreenEnvironmentVisibility);
    c.resolveFilter = glm::vec4(float(d.visibilitySteps), d.visibilityThickness, d.varianceClippingGamma,
                                float(d.temporalFilterFrames));
    return c;
  }

  // The reservoir images after a pass, shown by gi.diffuse.reservoir_view
  // (captured frames only).
  void viewReservoirs(gpu::Recorder& recorder, const FrameInputs& frame, std::size_t which, gpu::Image& first,
                      gpu::Image& second) {
    static const char* const kAfter[] = {"gather", "temporal_reuse", "spatial_reuse1", "spatial_reuse2"};
    if (reservoirViews.empty()) {
      for (const char* after : kAfter)
        reservoirViews.push_back(std::make_unique<gpu::ComputePass>(device, reservoirViewPass(after)));
      viewEstimate = std::make_unique<gpu::Image>(device, imageDesc("gi.diffuse.reservoir_estimate", halfWidth,
                                                                    halfHeight, kRgba16f, gpu::Visualize::Radiance));
      viewM = std::make_unique<gpu::Image>(
          device, imageDesc("gi.diffuse.reservoir_M", halfWidth, halfHeight, kR32f, gpu::Visualize::Heat));
      viewW = std::make_unique<gpu::Image>(
          device, imageDesc("gi.diffuse.reservoir_W", halfWidth, halfHeight, kR32f, gpu::Visualize::Heat));
    }
    recorder.dispatch(*reservoirViews[which], halfWidth, halfHeight,
                      {{"gIn_Frame", *constants},
                       {"gIn_ViewZ", *frame.viewZ},
                       {"gIn_NormalRoughness", *frame.normalRoughness},
                       {"gIn_Reservoir0", first},
                       {"gIn_Reservoir1", second},
                       {"gOut_Estimate", *viewEstimate},
                       {"gOut_M", *viewM},
                       {"gOut_W", *viewW}});
  }

  void record(gpu::Recorder& recorder, const FrameInputs& frame) {
    checkInputs(frame);
    const std::uint64_t f = frame.frameIndex;
    const bool usableHistory = hasHistory && !frame.cameraCut;
    const GiFrameConstants c = frameConstants(frame, usableHistory);
    recorder.updateBuffer(*constants, &c, sizeof c);
    const bool showReservoirs = recorder.capturing();

    recorder.dispatch(*storeHistory, width, height,
                      {{"gIn_Frame", *constants},
                       {"gIn_ViewZ", *frame.viewZ},
                       {"gIn_NormalRoughness", *frame.normalRoughness},
                       {"gOut_Surface", surface.current(f)}});

    const DiffuseSettings& d = settings.diffuse;
    if (d.enabled)
      recordDiffuse(recorder, frame, showReservoirs);
    else
      recorder.clearImage(filtered.current(f), {});  // no indirect diffuse: the composite is the direct light
    recorder.dispatch(*compositor, width, height,
                      {{"gIn_Frame", *constants},
                       {"gIn_ViewZ", *frame.viewZ},
                       {"gIn_Direct", *frame.direct},
                       {"gIn_BaseColorMetallic", *frame.baseColorMetallic},
                       // Not read without an emissive image (the constants say so); bound only to fill the slot.
                       {"gIn_Emissive", frame.emissive ? *frame.emissive : *frame.direct},
                       {"gIn_IndirectDiffuse", filtered.current(f)},
                       {"gOut_Composite", composite.current(f)}});
    hasHistory = true;
    lastCamera = frame.camera;
    lastFrame = f;
  }

  // The diffuse branch, gathering to temporal filter (seed 001).
  void recordDiffuse(gpu::Recorder& recorder, const FrameInputs& frame, bool showReservoirs) {
    const std::uint64_t f = frame.frameIndex;
    const DiffuseSettings& d = settings.diffuse;
    if (hasHistory && d.brightCandidates > 0) {
      recorder.dispatch(*brightPixels, brightLevels[0]->width(), brightLevels[0]->height(),
                        {{"gIn_Frame", *constants},
                         {"gPrev_Composite", composite.previous(f)},
                         {"gPrev_Surface", surface.previous(f)},
                         {"gOut_Brightest", *brightLevels[0]}});
      for (std::size_t level = 1; level < brightLevels.size(); ++level)
        recorder.dispatch(*brightReduce, brightLevels[level]->width(), brightLevels[level]->height(),
                          {{"gIn_Brightest", *brightLevels[level - 1]}, {"gOut_Brightest", *brightLevels[level]}});
    }

    recorder.dispatch(*gather, halfWidth, halfHeight,
                      {{"gIn_Frame", *constants},
                       {"gIn_ViewZ", *frame.viewZ},
                       {"gIn_NormalRoughness", *frame.normalRoughness},
                       {"gPrev_Composite", composite.previous(f)},
                       {"gPrev_Surface", surface.previous(f)},
                       {"gIn_Brightest", *brightLevels.back()},
                       {"gIn_Environment", *frame.environment, frame.environmentSampler},
                       {"gOut_Reservoir0", *gathered0},
                       {"gOut_Reservoir1", *gathered1}});
    if (showReservoirs) viewReservoirs(recorder, frame, 0, *gathered0, *gathered1);

    gpu::Image* final0 = gathered0.get();
    gpu::Image* final1 = gathered1.get();
    if (settings.restir) {
      // The reservoirs the next frame's temporal reuse starts from are the
      // history images; the others are scratch.
      const bool feedback = d.spatialFeedback;
      gpu::Image& temporalOut0 = feedback ? *transient0 : reservoir0.current(f);
      gpu::Image& temporalOut1 = feedback ? *transient1 : reservoir1.current(f);
      gpu::Image& spatialOut0 = feedback ? reservoir0.current(f) : *transient0;
      gpu::Image& spatialOut1 = feedback ? reservoir1.current(f) : *transient1;
      recorder.dispatch(*temporalReuse, halfWidth, halfHeight,
                        {{"gIn_Frame", *constants},
                         {"gIn_ViewZ", *frame.viewZ},
                         {"gIn_NormalRoughness", *frame.normalRoughness},
                         {"gIn_Motion", *frame.motion},
                         {"gPrev_Surface", surface.previous(f)},
                         {"gIn_Reservoir0", *gathered0},
                         {"gIn_Reservoir1", *gathered1},
                         {"gPrev_Reservoir0", reservoir0.previous(f)},
                         {"gPrev_Reservoir1", reservoir1.previous(f)},
                         {"gOut_Reservoir0", temporalOut0},
                         {"gOut_Reservoir1", temporalOut1}});
      if (showReservoirs) viewReservoirs(recorder, frame, 1, temporalOut0, temporalOut1);
      // The two spatial passes are one shader with other parameters.
      const auto spatialPass = [&](gpu::Image& in0, gpu::Image& in1, gpu::Image& out0, gpu::Image& out1,
                                   const SpatialReuseParams& params) {
        recorder.dispatch(*spatialReuse, halfWidth, halfHeight,
                          {{"gIn_Frame", *constants},
                           {"gIn_ViewZ", *frame.viewZ},
                           {"gIn_NormalRoughness", *frame.normalRoughness},
                           {"gIn_Reservoir0", in0},
                           {"gIn_Reservoir1", in1},
                           {"gOut_Reservoir0", out0},
                           {"gOut_Reservoir1", out1}},
                          params);
      };
      spatialPass(temporalOut0, temporalOut1, *spatial0, *spatial1, {d.spatialRadius, d.spatialSamples, 0u});
      if (showReservoirs) viewReservoirs(recorder, frame, 2, *spatial0, *spatial1);
      spatialPass(*spatial0, *spatial1, spatialOut0, spatialOut1, {d.spatial2Radius, d.spatial2Samples, 1u});
      final0 = &spatialOut0;
      final1 = &spatialOut1;
      if (showReservoirs) viewReservoirs(recorder, frame, 3, *final0, *final1);
    }

    recorder.dispatch(*resolve, width, height,
                      {{"gIn_Frame", *constants},
                       {"gIn_ViewZ", *frame.viewZ},
                       {"gIn_NormalRoughness", *frame.normalRoughness},
                       {"gIn_Reservoir0", *final0},
                       {"gIn_Reservoir1", *final1},
                       {"gOut_Diffuse", *diffuse}});
    recorder.dispatch(*temporalFilter, width, height,
                      {{"gIn_Frame", *constants},
                       {"gIn_ViewZ", *frame.viewZ},
                       {"gIn_NormalRoughness", *frame.normalRoughness},
                       {"gIn_Motion", *frame.motion},
                       {"gIn_Diffuse", *diffuse},
                       {"gPrev_Surface", surface.previous(f)},
                       {"gPrev_Filtered", filtered.previous(f)},
                       {"gPrev_Moments", moments.previous(f)},
                       {"gOut_Filtered", filtered.current(f)},
                       {"gOut_Moments", moments.current(f)}});
  }
};

GiContext::GiContext(gpu::Context& device, std::uint32_t width, std::uint32_t height, const Settings& settings) {
  if (width == 0 || height == 0 || width > 16384 || height > 16384)
    throw std::invalid_argument("gi: size " + std::to_string(width) + "x" + std::to_string(height) +
                                " is outside 1..16384");
  validate(settings);
  impl_ = std::make_unique<Impl>(device, width, height, settings);
}

GiContext::~GiContext() = default;

void GiContext::record(gpu::Recorder& recorder, const FrameInputs& frame) { impl_->record(recorder, frame); }

gpu::Image& GiContext::indirectDiffuse() { return impl_->filtered.current(impl_->lastFrame); }
gpu::Image& GiContext::composite() { return impl_->composite.current(impl_->lastFrame); }

std::vector<NamedImage> GiContext::images() {
  Impl& i = *impl_;
  const std::uint64_t f = i.lastFrame;
  std::vector<NamedImage> list = {{"history_surface", &i.surface.current(f)},
                                  {"diffuse.gathered0", i.gathered0.get()},
                                  {"diffuse.gathered1", i.gathered1.get()},
                                  {"diffuse.transient0", i.transient0.get()},
                                  {"diffuse.transient1", i.transient1.get()},
                                  {"diffuse.spatial0", i.spatial0.get()},
                                  {"diffuse.spatial1", i.spatial1.get()},
                                  {"diffuse.reservoirs0", &i.reservoir0.current(f)},
                                  {"diffuse.reservoirs1", &i.reservoir1.current(f)},
                                  {"diffuse.resolved", i.diffuse.get()},
                                  {"diffuse.filtered", &i.filtered.current(f)},
                                  {"diffuse.moments", &i.moments.current(f)},
                                  {"composite", &i.composite.current(f)}};
  for (const auto& level : i.brightLevels) list.push_back({level->name().substr(3), level.get()});
  return list;
}

const Settings& GiContext::settings() const { return impl_->settings; }
std::uint32_t GiContext::width() const { return impl_->width; }
std::uint32_t GiContext::height() const { return impl_->height; }

}  // namespace bounce::gi
