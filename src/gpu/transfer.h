// Moving bytes between the CPU and the GPU (blocking; for set-up, tests and
// tools, not for per-frame work). Images as float pixels: gpuio/gpu_images.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <string>

#include "gpu/resources.h"

namespace bounce::gpu {

class Context;

// Channel names a readback of this format gets: Y, RG, RGBA.
std::vector<std::string> channelNames(VkFormat format);

void uploadImage(Context& context, Image& image, const void* texels, std::size_t bytes);
// Mip 0's texels exactly as stored (tightly packed rows), for packed
// integer data that a float conversion would round.
std::vector<std::uint8_t> readbackImageBytes(Context& context, Image& image);

void uploadBuffer(Context& context, Buffer& buffer, const void* data, std::size_t bytes);
std::vector<std::uint8_t> readbackBuffer(Context& context, Buffer& buffer);

}  // namespace bounce::gpu
