#include "gi/world_queue.h"

namespace bounce::gi {

std::uint64_t worldQueueBytes(Extent maxSize) {
  const Extent half = extentOf(Resolution::Half, maxSize);
  return (1 + std::uint64_t(half.width) * half.height) * sizeof(std::uint32_t);
}

std::unique_ptr<gpu::Buffer> makeWorldQueue(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize,
                                            const char* name) {
  return std::make_unique<gpu::Buffer>(context, name, worldQueueBytes(maxSize), gpu::BufferUsage::DeviceLocal, &arena);
}

}  // namespace bounce::gi
