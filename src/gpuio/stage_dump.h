// --dump-stages: every captured pass output written as a linear EXR (exact
// values) and a PNG people can look at.
#pragma once

#include <filesystem>
#include <vector>

#include "gpu/recorder.h"
#include "io/image_io.h"

namespace bounce::gpuio {

// An image ready for a PNG, per the Visualize hint: radiance stays linear
// (the PNG writer tonemaps it), vectors are remapped to [0,1], scalar data is
// stretched over its finite min..max.
struct VisualizedImage {
  io::ImageF image;
  io::PngEncoding encoding;
};
VisualizedImage visualize(const io::ImageF& image, gpu::Visualize how);

// Writes <dir>/frame<NNNN>.<pass>.<binding>.exr and .png for each capture
// (completed: its texels on the host); returns the paths written. Creates
// `dir` if needed.
std::vector<std::filesystem::path> writeStageDumps(const std::filesystem::path& dir,
                                                   const std::vector<gpu::CapturedStage>& captures,
                                                   float exposure = 1.0f);

}  // namespace bounce::gpuio
