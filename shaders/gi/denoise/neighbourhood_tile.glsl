// The 3x3 luminance neighbourhood two denoiser passes build statistics from
// (history fix's anti-firefly, temporal stabilisation's clamp), read once
// per workgroup into shared memory for every signal of the dispatch: each
// texel is a neighbour of up to nine pixels, so a group of 16x16 pixels
// loads its 18x18 texels (1.27 a pixel) instead of 9 a pixel. The
// including shader defines NEIGHBOURHOOD_AT(slot, pixel) (a slot's
// radiance at a pixel, rgba16f), declares kGroupSize (its workgroups are
// kGroupSize x kGroupSize pixels, one denoiser tile, so that tileEmpty()
// is the same for the whole group and a group leaves before
// loadNeighbourhoodTile() together or not at all), and includes
// gi/denoise/denoise_common.glsl with DENOISE_READS_TILES and
// shared/color.glsl first.
#ifndef BOUNCE_GI_DENOISE_NEIGHBOURHOOD_TILE_GLSL
#define BOUNCE_GI_DENOISE_NEIGHBOURHOOD_TILE_GLSL

const int kNeighbourhoodTile = kGroupSize + 2;
// Each slot's luminance, and whether the texel is inside the frame and has a surface.
shared vec4 sNeighbourhoodLuminance[kNeighbourhoodTile][kNeighbourhoodTile];
shared bool sNeighbourhoodSurface[kNeighbourhoodTile][kNeighbourhoodTile];

// Every invocation of the group calls it (it holds a barrier).
void loadNeighbourhoodTile() {
  ivec2 origin = ivec2(gl_WorkGroupID.xy) * kGroupSize - 1;
  for (uint k = gl_LocalInvocationIndex; k < uint(kNeighbourhoodTile * kNeighbourhoodTile);
       k += uint(kGroupSize * kGroupSize)) {
    ivec2 local = ivec2(int(k) % kNeighbourhoodTile, int(k) / kNeighbourhoodTile);
    ivec2 tap = origin + local;
    vec4 luminances = vec4(0.0f);
    bool surface = insideFull(tap) && denoiseDepth(tap) > 0.0f;
    if (surface)
      for (uint slot = 0u; slot < gSignals.count; ++slot) luminances[slot] = luminance(NEIGHBOURHOOD_AT(slot, tap).xyz);
    sNeighbourhoodLuminance[local.y][local.x] = luminances;
    sNeighbourhoodSurface[local.y][local.x] = surface;
  }
  barrier();
}

// The neighbour `offset` (each axis -1..1) away from this invocation's
// pixel: the slot's luminance, and 1 where it has a surface (else 0).
vec2 neighbourhoodTexel(uint slot, ivec2 offset) {
  ivec2 local = ivec2(gl_LocalInvocationID.xy) + 1 + offset;
  return sNeighbourhoodSurface[local.y][local.x] ? vec2(sNeighbourhoodLuminance[local.y][local.x][slot], 1.0f)
                                                 : vec2(0.0f);
}

#endif
