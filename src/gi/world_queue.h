// The host side of gi/world_queue.glsl: the queue of pixels whose world
// rays a pass leaves to a pass of its own (the gather's to
// gi.diffuse.world_candidates, the specular trace's to gi.specular.world_trace).
#pragma once

#include <cstdint>
#include <memory>

#include "gi/image_table.h"
#include "gpu/context.h"
#include "gpu/resources.h"

namespace bounce::gi {

// A count, then room for every half-resolution pixel of maxSize.
std::uint64_t worldQueueBytes(Extent maxSize);
// The queue, in `arena`; the branch clears its count each frame (fillBuffer).
std::unique_ptr<gpu::Buffer> makeWorldQueue(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize,
                                            const char* name);

}  // namespace bounce::gi
