// The denoiser's settings, gi.denoise.*: its section of the settings table (gi/settings_table.h).
#include <array>

#include "gi/settings_table.h"

namespace bounce::gi::settings_table {
namespace {

constexpr std::array kEntries{
    Entry{"denoise.enabled", inDenoise(&DenoiseSettings::enabled), kNoBounds,
          "denoise both branches' signals with the REBLUR-class denoiser (off: each branch's own temporal filter)"},
    Entry{"denoise.max_accumulated_frames", inDenoise(&DenoiseSettings::maxAccumulatedFrames), closed(1, 255),
          "temporal accumulation: the longest history, in frames (specular: fewer on smooth lobes)"},
    Entry{"denoise.history_fix_frames", inDenoise(&DenoiseSettings::historyFixFrames), closed(0, 32),
          "history fix: pixels with a shorter history are rebuilt from a wide neighbourhood (0: off)"},
    Entry{"denoise.diffuse_pre_pass_radius", inDenoise(&DenoiseSettings::diffusePrePassRadius), closed(0, 128),
          "pre-pass: the widest radius in pixels of the diffuse pre-blur, for light from far away; 0: no pre-pass "
          "(at 1080 rows; scaled with the height)"},
    Entry{"denoise.specular_pre_pass_radius", inDenoise(&DenoiseSettings::specularPrePassRadius), closed(0, 128),
          "pre-pass: the same for specular, also scaled by the roughness and cut to the lobe's footprint; 0: no "
          "pre-pass (at 1080 rows; scaled with the height)"},
    Entry{"denoise.history_fix_stride", inDenoise(&DenoiseSettings::historyFixStride), closed(1, 64),
          "history fix: pixels between its 5x5 taps at a history of 0 frames (at 1080 rows; scaled with the height)"},
    Entry{"denoise.blur_radius", inDenoise(&DenoiseSettings::blurRadius), closed(0, 128),
          "blur: radius in pixels at the first frame of a history, shrinking as sqrt(1 / (1 + history length)) (at "
          "1080 rows; scaled with the height)"},
    Entry{"denoise.min_blur_radius", inDenoise(&DenoiseSettings::minBlurRadius), closed(0, 128),
          "blur: the smallest radius in pixels, however long the history (at 1080 rows; scaled with the height)"},
    Entry{"denoise.post_blur_radius_scale", inDenoise(&DenoiseSettings::postBlurRadiusScale), closed(0, 4),
          "post-blur: its radius as a fraction of blur's"},
    Entry{"denoise.plane_distance_sensitivity", inDenoise(&DenoiseSettings::planeDistanceSensitivity), aboveUpTo(0, 1),
          "spatial passes: a neighbour this fraction of viewZ off the pixel's plane weighs 0"},
    Entry{"denoise.lobe_angle_fraction", inDenoise(&DenoiseSettings::lobeAngleFraction), aboveUpTo(0, 1),
          "spatial passes: the normal weight's cone holds 0.75 * this^2 of the lobe once the history is long (0.75 "
          "at its start)"},
    Entry{"denoise.roughness_fraction", inDenoise(&DenoiseSettings::roughnessFraction), aboveUpTo(0, 4),
          "spatial passes (specular): a neighbour's roughness may differ by this fraction of the pixel's"},
    Entry{"denoise.stabilization_frames", inDenoise(&DenoiseSettings::stabilizationFrames), closed(0, 255),
          "temporal stabilisation: its longest history, in frames (0: off)"},
    Entry{"denoise.disocclusion_threshold", inDenoise(&DenoiseSettings::disocclusionThreshold), aboveUpTo(0, 1),
          "temporal accumulation: last frame's depth may differ by this fraction of the frustum's width seen "
          "head-on (plus a pixel; wider at grazing angles and for a still camera)"},
    Entry{"denoise.normal_tolerance_degrees", inDenoise(&DenoiseSettings::normalToleranceDegrees), open(0, 180),
          "temporal passes: a reprojected history's normal may differ from the pixel's by this many degrees"},
    Entry{"denoise.depth_tolerance", inDenoise(&DenoiseSettings::depthTolerance), aboveUpTo(0, 1),
          "temporal stabilisation and the reflection's (virtual) history (specular kind): reprojected depth may "
          "differ by this fraction of viewZ"},
    Entry{"denoise.clamp_sigma", inDenoise(&DenoiseSettings::clampSigma), aboveUpTo(0, 100),
          "history clamping (accumulation and stabilisation): mean +- this many sigma"},
    Entry{"denoise.anti_firefly", inDenoise(&DenoiseSettings::antiFirefly), kNoBounds,
          "history fix brings a pixel above its neighbours' mean + 2 sigma down to it"},
    Entry{"denoise.checkerboard", inDenoise(&DenoiseSettings::checkerboard), kNoBounds,
          "the engine's noisy signals (FrameInputs::noisy) are checkerboarded, as REBLUR's checkerboard mode: "
          "ceil(width / 2) x height, pixel (x, y) stored at (x / 2, y) where x + y + frameIndex is odd (kind "
          "diffuse) or even (kind specular); the pre-pass fills the other pixels. Ignored for the branches' own "
          "signals, which are full resolution"},
};

}  // namespace

std::span<const Entry> denoiseSection() { return kEntries; }

}  // namespace bounce::gi::settings_table
