// GPU images as float pixels (io::ImageF) and back: what tools and tests
// read and write. Above gpu/ (which knows no image files) and io/.
#pragma once

#include "gpu/context.h"
#include "gpu/resources.h"
#include "io/image_io.h"

namespace bounce::gpuio {

// Converts the float image to the image's format and uploads it (blocking);
// the channel count must be the format's.
void uploadImage(gpu::Context& context, gpu::Image& image, const io::ImageF& pixels);
// Mip 0 of the image as floats (blocking).
io::ImageF readbackImage(gpu::Context& context, gpu::Image& image);
// Texels of a host-visible buffer holding a tightly packed image, as floats.
io::ImageF texelsToImage(const gpu::ImageDesc& desc, const void* texels);

}  // namespace bounce::gpuio
