#include "gi/world_queue.h"

namespace bounce::gi {

std::uint64_t worldQueueBytes(Extent maxSize, std::uint32_t entriesPerPixel) {
  const Extent half = extentOf(Resolution::Half, maxSize);
  return (1 + std::uint64_t(half.width) * half.height * entriesPerPixel) * sizeof(std::uint32_t);
}

std::unique_ptr<gpu::Buffer> makeWorldQueue(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize,
                                            const char* name, std::uint32_t entriesPerPixel) {
  return std::make_unique<gpu::Buffer>(context, name, worldQueueBytes(maxSize, entriesPerPixel),
                                       gpu::BufferUsage::DeviceLocal, &arena);
}

}  // namespace bounce::gi
