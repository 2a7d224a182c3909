// The constants every GI pass reads (binding 0, gIn_Frame), laid out
// identically in GLSL (std140) and C++: two ScreenViews and vec4/uvec4s.
// src/gi/gi_context.cpp fills them from gi::Settings and the frame inputs.
#ifndef BOUNCE_GI_TYPES_GLSL
#define BOUNCE_GI_TYPES_GLSL

#include "shared/screen_view.glsl"

#ifdef __cplusplus
namespace bounce::shared {
#endif

struct GiFrameConstants {
  ScreenView view;
  ScreenView previousView;
  vec4 size;           // full resolution: width, height, 1 / width, 1 / height
  vec4 halfSize;       // reservoirs: width, height, 1 / width, 1 / height
  uvec4 frame;         // x frame index, y 1 = no usable history (cut or first frame), z seed, w 1 = ReSTIR reuse on
  uvec4 candidates;    // x screen, y bright, z environment candidates per pixel, w target function
  uvec4 brightLevel;   // xy size of the bright-pixel pyramid's last level, z its level: each entry is the
                       // brightest pixel of a 2^z x 2^z tile of the frame
  uvec4 options;       // x resolve reservoirs, y 1 = emissive image given
  vec4 temporal;       // x depth tolerance, y cos(normal tolerance), z max M, w environment mip
  vec4 spatial;        // x cos(normal tolerance), y plane tolerance, z 1 = Jacobian, w off-screen environment visibility
  vec4 resolveFilter;  // x visibility steps, y visibility thickness, z variance clipping gamma, w max history frames
};

#ifdef __cplusplus
}  // namespace bounce::shared
#endif

#endif
