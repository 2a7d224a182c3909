#version 460
#extension GL_GOOGLE_include_directive : require
// gi.denoise.post_blur: REBLUR's post-blur, the kernel of
// gi/denoise/spatial_filter.glsl again (as gi.denoise.blur) at
// post_blur_radius_scale of blur's radius, over blur's output (the
// accumulation image) back into the history image: next frame's history
// for temporal accumulation and what temporal stabilisation reads.
// Then each pixel hands last frame's stabilised value (the signal's one
// stabilised image, which stabilisation is about to overwrite) to
// stabilisation through the pre-passed image: no pass reads the pre-pass's
// output after this one, and this pass reads only the pixel's own (its hit
// distance, before the copy). Stabilisation reads its history at
// reprojected taps while it writes: in the image it writes it would read
// other pixels' new values; this way one copy of the result is kept, not
// two.
#include "gi/gi_common.glsl"
#define DENOISE_READS_TILES
#include "gi/denoise/denoise_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

DENOISE_SLOT_IMAGES(readonly, gIn_Filtered, 20)
DENOISE_SLOT_IMAGES(readonly, gPrev_Stabilized, 24)
DENOISE_SLOT_IMAGES(, gInOut_PrePassed, 28)
DENOISE_SLOT_IMAGES(writeonly, gOut_Filtered, 32)
DENOISE_SLOT_LOAD(gIn_Filtered)
DENOISE_SLOT_LOAD(gInOut_PrePassed)
DENOISE_SLOT_STORE(gInOut_PrePassed)
DENOISE_SLOT_STORE(gOut_Filtered)
DENOISE_SLOT_LOAD(gPrev_Stabilized)

#include "gi/denoise/spatial_filter.glsl"

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideFull(pixel)) return;
  float roughness;
  Surface x = denoiseSurfaceRoughness(pixel, roughness);
  bool surface = !tileEmpty(pixel) && x.viewZ > 0.0f;
  for (uint slot = 0u; slot < gSignals.count; ++slot) {
    float hitDistance = gInOut_PrePassedAt(slot, pixel).w;
    gOut_FilteredStore(slot, pixel,
                       surface ? roundedToHalf(spatialFilter(slot, pixel, x, roughness, hitDistance)) : vec4(0.0f));
    gInOut_PrePassedStore(slot, pixel, gPrev_StabilizedAt(slot, pixel));
  }
}
