// The gpu layer's context on the engine's device: the library creates no
// instance, device or queue of its own, and destroys nothing of the engine's.
#pragma once

#include <memory>

#include "bounce/gi.h"
#include "gpu/context.h"

namespace bounce::gi {

// Throws Error when a handle is missing, the device is below Vulkan 1.3,
// lacks VK_KHR_push_descriptor, or the queue family cannot run compute.
std::unique_ptr<gpu::Context> openLibraryContext(const Device& device);

}  // namespace bounce::gi
