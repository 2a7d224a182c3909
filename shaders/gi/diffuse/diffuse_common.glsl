// What every pass of the diffuse branch shares: its constants (binding 3,
// gIn_DiffuseConstants), filled from gi::DiffuseSettings by
// src/gi/diffuse/diffuse_branch.cpp and laid out identically in GLSL (std140)
// and C++ (checked against each pass's SPIR-V). The including shader
// includes gi/gi_common.glsl first; its own resources start at binding 4.
#ifndef BOUNCE_GI_DIFFUSE_COMMON_GLSL
#define BOUNCE_GI_DIFFUSE_COMMON_GLSL

#ifdef __cplusplus
#include "shared/lang.glsl"
namespace bounce::shared {
#endif

struct DiffuseConstants {
  uvec2 brightLevelSize;  // size of the bright-pixel pyramid's last level at this render size
  uint brightLevel;       // its level: each entry is the brightest pixel of a 2^level x 2^level tile
  uint screenCandidates;  // candidates per pixel: random pixels of the last frame
  uint brightCandidates;  //   picks among its brightest pixels
  uint environmentCandidates;  // uniform hemisphere directions into the environment
  uint targetFunction;         // gi::TargetFunction
  uint resolveReservoirs;      // neighbouring reservoirs each pixel evaluates
  uint visibilitySteps;        // screen-space march steps (0: no visibility test)
  uint jacobian;               // 1: ReSTIR GI's reconnection Jacobian for reused samples
  float temporalMaxM;          // history counts as at most this many frames of samples
  float temporalDepthTolerance;      // fraction of viewZ
  float temporalCosNormalTolerance;  // cos of the angle
  float environmentMip;              // prefiltered level environment candidates read
  float spatialCosNormalTolerance;
  float spatialPlaneTolerance;  // fraction of viewZ
  float visibilityThickness;  // surfaces are this fraction of their viewZ thick
  float varianceClippingGamma;
  float temporalFilterFrames;  // the longest history the temporal filter accumulates
  uint rayCandidates;          // cosine-distributed ray candidates (0 without a bridge that traces)
  uint rayScreenSteps;         // depth-buffer march steps before a ray goes to the bridge
  uint visibilityMode;         // gi::Visibility (Screen without a bridge that traces)
  uint reuseVisibility;        // 1: reuse tests reused samples with world any-hit rays
  uint skyReuseVisibility;     // 1: spatial reuse's normalisation tests sky samples from each neighbour
  uint skyReuseRays;           // of those neighbours, the most one pass tests with a ray
  uint perPixelVisibility;     // 1: the resolve marches from each pixel to each sample; 0: once per reservoir
};

// Neighbours one spatial pass merges at most (more samples are not taken):
// its shader's arrays, and the rays the budget plans for them.
const uint kMaxSpatialNeighbours = 16u;

#ifdef __cplusplus
}  // namespace bounce::shared
#else
// gi::Visibility
const uint kVisibilityScreen = 0u;
const uint kVisibilityWorld = 1u;
const uint kVisibilityHybrid = 2u;

layout(set = 0, binding = 3, std140) CONSTANT_BLOCK DiffuseBlock { DiffuseConstants diffuse; } gIn_DiffuseConstants;
#endif

#endif
