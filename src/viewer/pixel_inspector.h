// bounce view's inspector: the value of every image a user may look at
// (the renderer's and the GI library's) at one pixel of the frame, read
// back in one submission.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "gpu/context.h"
#include "gpu/resources.h"
#include "viewer/panels.h"

namespace bounce::viewer {

// An image a user may look at, by the name the stage list gives it.
struct NamedImage {
  std::string name;
  gpu::Image* image;
};

class PixelInspector {
 public:
  explicit PixelInspector(gpu::Context& context) : context_(context) {}
  // Each image's texel at pixel (x, y) of a frame of `frameWidth` x
  // `frameHeight` (an image of another size at the same place of the
  // picture: half-resolution ones at half the pixel). The GPU must be done
  // with the frame.
  std::vector<InspectedValue> inspect(std::span<const NamedImage> images, std::uint32_t x, std::uint32_t y,
                                      std::uint32_t frameWidth, std::uint32_t frameHeight);

 private:
  gpu::Context& context_;
  std::unique_ptr<gpu::Buffer> readback_;
};

}  // namespace bounce::viewer
