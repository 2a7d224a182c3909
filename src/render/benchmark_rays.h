// The ray sets `bounce bench --rays` traces through render.bvh_trace_rays,
// each a distribution the renderer's passes meet (docs/bvh.md, "Ray
// benchmarks"). Deterministic: the same scene and arguments give the same rays.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "render/bvh.h"
#include "render/gpu_bvh.h"
#include "scene/scene.h"

namespace bounce::render {

// From uniformly random points in the scene's box in uniformly random
// directions: incoherent, but most start in empty space, unlike any GI ray.
std::vector<BvhRay> boundsRays(const scene::Scene& scene, std::uint32_t count);

// As GI bounces off any surface cast them: from uniformly random points on
// the placed triangles (by area), a little off a random side, in
// cosine-distributed directions about that side's normal. Falls back to
// boundsRays for a scene without a triangle of positive area.
std::vector<BvhRay> surfaceRays(const scene::Scene& scene, std::uint32_t count);

struct VisibleSurfaceRays {
  std::vector<BvhRay> rays;
  std::uint32_t pixels = 0;         // of the image, width * height
  std::uint32_t visiblePixels = 0;  // those whose primary ray hit a surface (the others see the sky)
};

// As the GI's passes cast them: one cosine-distributed ray about the
// geometric normal (turned towards the camera) of the surface each pixel of
// a width x height image from `camera` sees, a little off it. The surfaces
// are found by `bvh`'s own walk on the CPU through each pixel's centre
// (alpha-masked triangles count as opaque; the CPU has no textures), the
// machine's cores sharing the pixels. The rays follow the pixels in 8x8
// tiles, as the GI's 8x8 workgroups take them, so neighbouring rays start
// close together; `count` rays spread evenly over the visible pixels in that
// order (a pixel repeats when count exceeds them). No rays when no pixel
// sees a surface. `bvh` must hold its instances (setInstances). `progress`,
// when given, is called on the calling thread with the pixels traced so
// far and their total, a few times a second and once at the end.
VisibleSurfaceRays visibleSurfaceRays(
    const SceneBvh& bvh, const scene::CameraPose& camera, std::uint32_t width, std::uint32_t height,
    std::uint32_t count, const std::function<void(std::uint64_t done, std::uint64_t total)>& progress = {});

}  // namespace bounce::render
