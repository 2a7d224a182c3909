#version 460
#extension GL_GOOGLE_include_directive : require
// gi.diffuse.sample_march: the screen-space visibility test of each
// reservoir's sample, once, from the reservoir's own surface (screen
// visibility with gi.diffuse.per_pixel_visibility off): the same march
// the resolve would run from each full-resolution pixel (the depth buffer
// between the surface and the sample, gi.diffuse.visibility_steps steps;
// for the sky, whether the direction meets something the screen shows),
// run once per half-resolution reservoir instead of once per pixel and
// reservoir (16 times fewer marches). A sample the march finds hidden is
// dropped (W = 0; M stays: the candidates were seen), here and in the
// history when the next frame starts from these reservoirs, as
// gi.diffuse.sample_visibility's world ray does in hybrid mode; a march
// that leaves the screen counts as visible, as the resolve's does. The
// resolve then evaluates the samples without marching.
#include "gi/gi_common.glsl"
#include "gi/gbuffer.glsl"
#include "gi/diffuse/diffuse_common.glsl"
#include "shared/reservoir.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 4, rgba32ui) readonly uniform uimage2D gIn_Reservoir0;
layout(set = 0, binding = 5, rgba32ui) uniform uimage2D gInOut_Reservoir1;
layout(set = 0, binding = 6, r32f) readonly uniform image2D gIn_MarchDepth;

#include "gi/screen_trace.glsl"

const uint kSaltSampleMarch = kSaltResolve + 1u;

void main() {
  ivec2 halfPixel = ivec2(gl_GlobalInvocationID.xy);
  if (!insideHalf(halfPixel)) return;
  DiffuseConstants d = gIn_DiffuseConstants.diffuse;
  if (d.visibilitySteps == 0u) return;
  uvec4 first = imageLoad(gIn_Reservoir0, halfPixel);
  uvec4 second = imageLoad(gInOut_Reservoir1, halfPixel);
  Reservoir r = unpackReservoir(first, second);
  if (!reservoirHasSample(r)) return;
  Surface x = gbufferSurface(reservoirSurfacePixel(halfPixel));
  if (x.viewZ <= 0.0f) return;
  uint rng = giSeed(uvec2(halfPixel), kSaltSampleMarch);
  float jitter = rngUniform(rng);
  float visible;
  if (reservoirIsEnvironment(r))
    visible = environmentVisibility(x.position, sampleDirection(r, x.position), x.viewZ, d.visibilitySteps, jitter,
                                    d.visibilityThickness, false);
  else
    visible = screenVisibility(x.position, r.position, d.visibilitySteps, jitter, d.visibilityThickness, false);
  if (visible != kOccluded) return;
  r.W = 0.0f;
  r.flags &= ~kReservoirHasSample;
  packReservoir(r, first, second);
  imageStore(gInOut_Reservoir1, halfPixel, second);
}
