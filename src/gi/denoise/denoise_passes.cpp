#include "gi/denoise/denoise_passes.h"

#include <vector>

#include "gi/denoise/denoise_common.glsl"
#include "gi/light_change.h"
#include "gi/pass_decls.h"
#include "gpu/constants_layout.h"
#include "gpu/format.h"

namespace bounce::gi {
namespace {

using gpu::Access;
using gpu::ResourceDecl;
using gpu::ResourceKind;
using shared::DenoiseConstants;

using namespace gpu::formats;

ResourceDecl denoiseConstants() {
  return {"gIn_DenoiseConstants", Access::Read, VK_FORMAT_UNDEFINED, "the denoiser's settings",
          ResourceKind::UniformBuffer};
}

gpu::ConstantsDecl denoiseConstantsLayout() {
  return BOUNCE_CONSTANTS_LAYOUT("gIn_DenoiseConstants", DenoiseConstants, hitDistanceParameters, maxAccumulatedFrames,
                                 historyFixFrames, historyFixStride, blurRadius, postBlurRadiusScale, minBlurRadius,
                                 planeDistanceSensitivity, lobeAngleFraction, roughnessFraction, stabilizationFrames,
                                 clampSigma, depthTolerance, cosNormalTolerance, disocclusionThreshold, frameIndex,
                                 antiFirefly, diffusePrePassRadius, specularPrePassRadius);
}

ResourceDecl tilesDecl() {
  return {"gIn_Tiles", Access::Read, kR16f, "1 where a 16x16 tile has a surface (gi.denoise.classify_tiles)"};
}

ResourceDecl surfaceDecl() {
  return {"gIn_DenoiseSurface", Access::Read, kRg32ui,
          "this frame's viewZ bits, octahedral normal and roughness (gi.denoise.classify_tiles)"};
}

// A per-signal pass: the frame's constants, the denoiser's constants, the
// tiles and the denoiser's packed surfaces (in place of the engine's
// G-buffer) first, then its own resources; the signal in push constants.
gpu::PassDesc signalPass(const std::string& pass, const std::string& signal, const char* shader,
                         std::vector<ResourceDecl> own) {
  own.insert(own.begin(), {denoiseConstants(), tilesDecl(), surfaceDecl()});
  gpu::PassDesc desc = framePass("gi.denoise." + signal + "." + pass, shader, GroupPart::Constants, own);
  desc.constants.push_back(denoiseConstantsLayout());
  desc.constants.push_back(BOUNCE_CONSTANTS_LAYOUT("", DenoiseSignalParams, slot, kind, flags, radiusScale));
  return desc;
}

ResourceDecl noisyDecl() {
  return {"gIn_Signal", Access::Read, kRgba16f,
          "the noisy signal (pre-passed, but for the pre-pass): radiance, hit distance (world units, 0 unknown)"};
}

gpu::PassDesc blur(const std::string& name, const std::string& signal, const char* output) {
  return signalPass(name, signal, "gi/denoise/blur",
                    {{"gIn_Filtered", Access::Read, kRgba16f, "the signal to blur: radiance, history length"},
                     noisyDecl(),
                     {"gOut_Filtered", Access::Write, kRgba16f, output}});
}

}  // namespace

gpu::PassDesc denoiseClassifyTilesPass() {
  return framePass("gi.denoise.classify_tiles", "gi/denoise/classify_tiles", GroupPart::Surfaces,
                   {{"gOut_Tiles", Access::Write, kR16f, "1 where a 16x16 tile has a surface"},
                    {"gOut_Surface", Access::Write, kRg32ui,
                     "each pixel's viewZ bits and octahedral normal and roughness (packNormalRoughness), viewZ 0 "
                     "without a usable surface: what the later passes' taps read"}});
}

gpu::PassDesc denoisePrePass(const std::string& signal) {
  return signalPass("pre_pass", signal, "gi/denoise/pre_pass",
                    {{"gIn_Signal", Access::Read, kRgba16f,
                      "the noisy signal: radiance, hit distance (world units, 0 unknown; checkerboard mode: -1 "
                      "where the pixel has no sample)"},
                     {"gOut_PrePassed", Access::Write, kRgba16f,
                      "the pre-blurred signal, every pixel with a value: radiance, hit distance (world units, 0 "
                      "unknown)"}});
}

gpu::PassDesc denoiseTemporalAccumulationPass(const std::string& signal) {
  return signalPass("temporal_accumulation", signal, "gi/denoise/temporal_accumulation",
                    {motionDecl(),
                     noisyDecl(),
                     previousSurfaceDecl(),
                     {"gPrev_Filtered", Access::Read, kRgba16f, "last frame's post-blurred signal, history length"},
                     {"gPrev_Moments", Access::Read, kRgba16f, "last frame's luminance moments"},
                     {"gOut_Accumulated", Access::Write, kRgba16f, "radiance, history length"},
                     {"gOut_Moments", Access::Write, kRgba16f, "luminance moments: mean, deviation, fast mean"},
                     currentSurfaceDecl(),
                     lightChangeDecl()});
}

gpu::PassDesc denoiseHistoryFixPass(const std::string& signal) {
  return signalPass("history_fix", signal, "gi/denoise/history_fix",
                    {{"gIn_Accumulated", Access::Read, kRgba16f, "temporal accumulation's output"},
                     {"gOut_Fixed", Access::Write, kRgba16f, "short histories rebuilt, fireflies removed"}});
}

gpu::PassDesc denoiseBlurPass(const std::string& signal) {
  return blur("blur", signal, "blurred at the full radius");
}

gpu::PassDesc denoisePostBlurPass(const std::string& signal) {
  return blur("post_blur", signal, "blurred again at post_blur_radius_scale: next frame's history");
}

gpu::PassDesc denoiseTemporalStabilizationPass(const std::string& signal) {
  return signalPass("temporal_stabilization", signal, "gi/denoise/temporal_stabilization",
                    {motionDecl(),
                     {"gIn_Filtered", Access::Read, kRgba16f, "post-blur's output"},
                     previousSurfaceDecl(),
                     {"gPrev_Stabilized", Access::Read, kRgba16f, "last frame's stabilised signal"},
                     {"gOut_Stabilized", Access::Write, kRgba16f, "the denoised signal, history length"},
                     currentSurfaceDecl(),
                     lightChangeDecl()});
}

gpu::PassDesc denoiseValidationPass() {
  gpu::PassDesc desc = framePass(
      "gi.denoise.validation", "gi/denoise/validation", GroupPart::Surfaces,
      {denoiseConstants(),
       motionDecl(),
       {"gIn_DiffuseHistory", Access::Read, kRgba16f, "the first diffuse-kind signal's history: its length"},
       {"gIn_SpecularHistory", Access::Read, kRgba16f, "the first specular-kind signal's history: its length"},
       {"gIn_SpecularMoments", Access::Read, kRgba16f, "its temporal accumulation: the virtual history's share"},
       {"gIn_Diffuse", Access::Read, kRgba16f, "the denoised diffuse-kind light"},
       {"gIn_Specular", Access::Read, kRgba16f, "the denoised specular-kind light"},
       {"gOut_Validation", Access::Write, kRgba16f,
        "4 x 2 panels: viewZ, normals, motion, virtual history; histories, denoised light with disocclusions"}});
  desc.constants.push_back(denoiseConstantsLayout());
  desc.constants.push_back(BOUNCE_CONSTANTS_LAYOUT("", DenoiseValidationParams, diffuseShown, specularShown));
  return desc;
}

}  // namespace bounce::gi
