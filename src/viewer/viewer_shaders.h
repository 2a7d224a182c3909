// The viewer's own shaders (shaders/viewer/), embedded in the binary.
#pragma once

#include <span>

#include "gpu/embedded_shaders.h"

namespace bounce::viewer {

std::span<const gpu::EmbeddedShader> shaders();

}  // namespace bounce::viewer
