// The constants every GI pass reads (binding 0, gIn_Frame): the cameras and
// what the engine's frame is, laid out identically in GLSL (std140) and
// C++. src/gi/frame_inputs.cpp fills them from gi::FrameInputs and
// gi::Settings; each pass's declaration checks the layout against the
// shader's SPIR-V (gpu/constants_layout.h). A branch's own settings are in
// its own block (gi/diffuse/diffuse_types.glsl).
#ifndef BOUNCE_GI_TYPES_GLSL
#define BOUNCE_GI_TYPES_GLSL

#include "shared/screen_view.glsl"

#ifdef __cplusplus
namespace bounce::shared {
#endif

// How gIn_NormalRoughness stores a normal (docs/integration.md, "Inputs").
const uint kNormalEncodingXyz = 0u;         // rgba16f: world normal xyz, perceptual roughness w
const uint kNormalEncodingOctahedral = 1u;  // rgb10_a2: octahedral normal * 0.5 + 0.5 in rg, roughness in b

struct GiFrameConstants {
  ScreenView view;
  ScreenView previousView;  // the camera last frame's images were made with
  vec2 renderSize;          // pixels of this frame (FrameInputs::width, height)
  vec2 halfSize;            // reservoirs: ceil(renderSize / 2)
  vec2 motionScale;         // turns the engine's motion vectors into pixels (units and scale settings)
  uint frameIndex;
  uint noHistory;       // 1: nothing of earlier frames may be used (first frame, cut, new render size)
  uint seed;            // Settings::seed
  uint normalEncoding;  // kNormalEncoding*
  uint hasEmissive;     // 1: the engine gave emission apart from the direct light
  uint hasMaterialId;   // 1: the engine gave material ids (FrameInputs::materialId); else every pixel is material 0
  float declaredLightChange;  // FrameInputs::lightChange: the share of the light the engine says it changed
};

#ifdef __cplusplus
}  // namespace bounce::shared
#endif

#endif
