#include "render/frame_memory.h"

#include <string>

#include "render/frame_renderer.h"
#include "render/reference_renderer.h"

namespace bounce::render {

void requireFrameMemory(const gpu::Context& context, std::uint32_t width, std::uint32_t height,
                        const std::optional<std::pair<gi::ContextDesc, gi::Settings>>& gi, bool reference,
                        std::uint64_t extraBytes) {
  std::uint64_t bytes = FrameRenderer::frameImageBytes(width, height) + extraBytes;
  if (gi) bytes += gi::GiContext::estimateMemoryBytes(gi->first, gi->second);
  if (reference) bytes += ReferenceRenderer::frameImageBytes(width, height);
  context.requireDeviceMemory(bytes, "a " + std::to_string(width) + "x" + std::to_string(height) + " frame" +
                                         (gi ? " with GI" : "") + (reference ? " and path tracing" : ""));
}

}  // namespace bounce::render
