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

// A binding each signal of a dispatch has (the pass declares it once per
// slot, NAME0..NAME3; a slot not in use holds a filler image).
struct SlotDecl {
  const char* name;
  Access access;
  const char* purpose;
  // Sampled slots read through the context's filtering sampler (DENOISE_SLOT_TEXTURES).
  ResourceKind kind = ResourceKind::StorageImage;
};

// A stage: the frame's constants, the denoiser's constants, the tiles and
// the denoiser's packed surfaces (in place of the engine's G-buffer) first,
// then its own resources, then its per-signal ones; the signals in push
// constants.
gpu::PassDesc stagePass(const std::string& pass, const char* shader, std::vector<ResourceDecl> own,
                        std::initializer_list<SlotDecl> slots) {
  own.insert(own.begin(), {denoiseConstants(), tilesDecl(), surfaceDecl()});
  for (const SlotDecl& slot : slots)
    for (std::size_t k = 0; k < shared::kDenoiseSlots; ++k)
      own.push_back({denoiseSlotName(slot.name, k), slot.access,
                     slot.kind == ResourceKind::StorageImage ? kRgba16f : VK_FORMAT_UNDEFINED,
                     std::string(slot.purpose) + " (slot " + std::to_string(k) + "'s signal)", slot.kind});
  gpu::PassDesc desc = framePass("gi.denoise." + pass, shader, GroupPart::Constants, own);
  desc.constants.push_back(denoiseConstantsLayout());
  desc.constants.push_back(
      BOUNCE_CONSTANTS_LAYOUT("", DenoiseSignalParams, kinds, flags, indices, count, radiusScale));
  return desc;
}

constexpr SlotDecl kPrePassedSlot = {
    "gIn_Signal", Access::Read,
    "the pre-passed noisy signal: radiance, hit distance (world units, 0 unknown)"};

}  // namespace

std::string denoiseSlotName(std::string_view binding, std::size_t slot) {
  return std::string(binding) + std::to_string(slot);
}

gpu::PassDesc denoiseClassifyTilesPass() {
  return framePass("gi.denoise.classify_tiles", "gi/denoise/classify_tiles", GroupPart::Surfaces,
                   {{"gOut_Tiles", Access::Write, kR16f, "1 where a 16x16 tile has a surface"},
                    {"gOut_Surface", Access::Write, kRg32ui,
                     "each pixel's viewZ bits and octahedral normal and roughness (packNormalRoughness), viewZ 0 "
                     "without a usable surface: what the later passes' taps read"}});
}

gpu::PassDesc denoisePrePass() {
  return stagePass("pre_pass", "gi/denoise/pre_pass", {},
                   {{"gIn_Signal", Access::Read,
                     "the noisy signal: radiance, hit distance (world units, 0 unknown; checkerboard mode: -1 where "
                     "the pixel has no sample)"},
                    {"gOut_PrePassed", Access::Write,
                     "the pre-blurred signal, every pixel with a value: radiance, hit distance (world units, 0 "
                     "unknown)"}});
}

gpu::PassDesc denoiseTemporalAccumulationPass() {
  return stagePass("temporal_accumulation", "gi/denoise/temporal_accumulation",
                   {motionDecl(), previousSurfaceDecl(), currentSurfaceDecl(), lightChangeDecl()},
                   {kPrePassedSlot,
                    {"gPrev_Filtered", Access::Read,
                     "last frame's post-blurred signal, history length (sampled: Catmull-Rom in bilinear taps)",
                     ResourceKind::SampledImage},
                    {"gPrev_Moments", Access::Read, "last frame's luminance moments"},
                    {"gOut_Accumulated", Access::Write, "radiance, history length"},
                    {"gOut_Moments", Access::Write, "luminance moments: mean, deviation, fast mean"}});
}

gpu::PassDesc denoiseHistoryFixPass() {
  return stagePass("history_fix", "gi/denoise/history_fix", {},
                   {{"gIn_Accumulated", Access::Read, "temporal accumulation's output"},
                    {"gOut_Fixed", Access::Write,
                     "short histories rebuilt, fireflies removed (into the history image, which temporal "
                     "accumulation has read)"}});
}

gpu::PassDesc denoiseBlurPass() {
  return stagePass("blur", "gi/denoise/blur", {},
                   {{"gIn_Filtered", Access::Read, "history fix's output: radiance, history length"},
                    kPrePassedSlot,
                    {"gOut_Filtered", Access::Write, "blurred at the full radius"}});
}

gpu::PassDesc denoisePostBlurPass() {
  return stagePass(
      "post_blur", "gi/denoise/post_blur", {},
      {{"gIn_Filtered", Access::Read, "blur's output: radiance, history length"},
       {"gPrev_Stabilized", Access::Read, "last frame's stabilised signal, before stabilisation overwrites it"},
       {"gInOut_PrePassed", Access::ReadWrite,
        "the pre-passed signal (its hit distance); then last frame's stabilised signal, for stabilisation"},
       {"gOut_Filtered", Access::Write, "blurred again at post_blur_radius_scale: next frame's history"}});
}

gpu::PassDesc denoiseTemporalStabilizationPass() {
  return stagePass("temporal_stabilization", "gi/denoise/temporal_stabilization",
                   {motionDecl(), previousSurfaceDecl(), currentSurfaceDecl(), lightChangeDecl()},
                   {{"gIn_Filtered", Access::Read, "post-blur's output"},
                    {"gPrev_Stabilized", Access::Read,
                     "last frame's stabilised signal (post-blur copied it into the pre-passed image; sampled: "
                     "one bilinear fetch where all four taps count)",
                     ResourceKind::SampledImage},
                    {"gOut_Stabilized", Access::Write, "the denoised signal, history length"}});
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
