// The device memory a frame's images need, estimated before any of them is
// made: every command that renders, and the viewer, refuse a frame the
// device cannot hold without allocating anything for it.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>

#include "bounce/gi.h"
#include "gpu/context.h"

namespace bounce::render {

// Throws gpu::GpuError when the images of a `width` x `height` frame need
// more than the device's largest heap: the renderer's, the GI library's
// (`gi`: its size and settings; none when GI is off), the path tracer's
// (`reference`) and `extraBytes` of the caller's own (the viewer's display).
// The scene's buffers and textures come on top; a caller checks the total
// in use once they are made.
void requireFrameMemory(const gpu::Context& context, std::uint32_t width, std::uint32_t height,
                        const std::optional<std::pair<gi::ContextDesc, gi::Settings>>& gi, bool reference,
                        std::uint64_t extraBytes = 0);

}  // namespace bounce::render
