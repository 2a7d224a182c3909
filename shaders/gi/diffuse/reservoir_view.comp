#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.reservoir_view: makes a reservoir image visible, for
// --dump-stages only (never in a timed frame): its M and W as scalars (shown
// in false colour) and the estimate it gives at its own surface (radiance *
// cos / pi * W, before visibility), after each reservoir pass.
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 5, rgba32ui) readonly uniform uimage2D gIn_Reservoir1;
layout(set = 0, binding = 6, rgba16f) writeonly uniform image2D gOut_Estimate;
layout(set = 0, binding = 7, r32f) writeonly uniform image2D gOut_M;
layout(set = 0, binding = 8, r32f) writeonly uniform image2D gOut_W;

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideHalf(halfPixel)) return;
  ivec2 pixel = reservoirSurfacePixel(halfPixel);
  Reservoir r = unpackReservoir(imageLoad(gIn_Reservoir0, halfPixel), imageLoad(gIn_Reservoir1, halfPixel));
  Surface x = gbufferSurface(pixel);
  vec3 estimate = vec3(0.0f);
  if (x.viewZ > 0.0f && reservoirHasSample(r))
    estimate = r.radiance * (max(dot(x.normal, sampleDirection(r, x.position)), 0.0f) * kInvPi * r.W);
  imageStore(gOut_Estimate, halfPixel, vec4(sanitizeRadiance(estimate), 1.0f));
  imageStore(gOut_M, halfPixel, vec4(r.M));
  imageStore(gOut_W, halfPixel, vec4(r.W));
}
