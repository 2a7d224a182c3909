// The host side of gi/world_queue.glsl: the queue of work whose world rays
// a pass leaves to a pass of its own (pixels: the gather's to
// gi.diffuse.world_candidates, the specular trace's to
// gi.specular.world_trace; test slots: spatial reuse's to
// gi.diffuse.neighbour_visibility).
#pragma once

#include <cstdint>
#include <memory>

#include "gi/image_table.h"
#include "gpu/context.h"
#include "gpu/resources.h"

namespace bounce::gi {

// A count, then room for `entriesPerPixel` entries of every half-resolution pixel of maxSize.
std::uint64_t worldQueueBytes(Extent maxSize, std::uint32_t entriesPerPixel = 1);
// The queue, in `arena`; the branch clears its count before each writer (fillBuffer).
std::unique_ptr<gpu::Buffer> makeWorldQueue(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize,
                                            const char* name, std::uint32_t entriesPerPixel = 1);

}  // namespace bounce::gi
