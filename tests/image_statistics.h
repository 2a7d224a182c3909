// Statistics of the images GPU tests read back, shared by the GI tests.
#pragma once

#include <glm/glm.hpp>

#include "io/image_io.h"
#include "shared/color.glsl"

namespace bounce::testing {

// Mean Rec.709 luminance over an image's first three channels, whatever
// they are named (readbacks of rgba images carry alpha after them).
inline double meanLuminance(const io::ImageF& image) {
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      sum += shared::luminance(glm::vec3(image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2)));
  return sum / (double(image.width) * double(image.height));
}

}  // namespace bounce::testing
