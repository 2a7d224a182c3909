// The 3x3 luminance neighbourhood two denoiser passes build statistics from
// (history fix's anti-firefly, temporal stabilisation's clamp), read once
// per workgroup into shared memory: each texel is a neighbour of up to
// nine pixels, so a group of 16x16 pixels loads its 18x18 texels (1.27 a
// pixel) instead of 9 a pixel. The including shader defines
// NEIGHBOURHOOD_IMAGE (an rgba16f image of radiance), declares
// kGroupSize (its workgroups are kGroupSize x kGroupSize pixels, one
// denoiser tile, so that tileEmpty() is the same for the whole group and
// a group leaves before loadNeighbourhoodTile() together or not at all),
// and includes gi/denoise/denoise_common.glsl with DENOISE_READS_TILES and
// shared/color.glsl first.
#ifndef BOUNCE_GI_DENOISE_NEIGHBOURHOOD_TILE_GLSL
#define BOUNCE_GI_DENOISE_NEIGHBOURHOOD_TILE_GLSL

const int kNeighbourhoodTile = kGroupSize + 2;
// Luminance, and 1 where the texel is inside the frame and has a surface.
shared vec2 sNeighbourhoodTile[kNeighbourhoodTile][kNeighbourhoodTile];

// Every invocation of the group calls it (it holds a barrier).
void loadNeighbourhoodTile() {
  ivec2 origin = ivec2(gl_WorkGroupID.xy) * kGroupSize - 1;
  for (uint k = gl_LocalInvocationIndex; k < uint(kNeighbourhoodTile * kNeighbourhoodTile);
       k += uint(kGroupSize * kGroupSize)) {
    ivec2 local = ivec2(int(k) % kNeighbourhoodTile, int(k) / kNeighbourhoodTile);
    ivec2 tap = origin + local;
    vec2 value = vec2(0.0f);
    if (insideFull(tap) && denoiseDepth(tap) > 0.0f)
      value = vec2(luminance(imageLoad(NEIGHBOURHOOD_IMAGE, tap).xyz), 1.0f);
    sNeighbourhoodTile[local.y][local.x] = value;
  }
  barrier();
}

// The neighbour `offset` (each axis -1..1) away from this invocation's pixel.
vec2 neighbourhoodTexel(ivec2 offset) {
  ivec2 local = ivec2(gl_LocalInvocationID.xy) + 1 + offset;
  return sNeighbourhoodTile[local.y][local.x];
}

#endif
