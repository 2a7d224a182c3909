// The GI library's shaders (shaders/gi/), embedded in libbounce_gi
// (cmake/EmbedShaders.cmake): what its passes name in PassDesc::shaders.
#pragma once

#include <span>

#include "gpu/embedded_shaders.h"

namespace bounce::gi {

std::span<const gpu::EmbeddedShader> shaders();

}  // namespace bounce::gi
