// The renderer's shaders (shaders/render/), embedded in bounce_render
// (cmake/EmbedShaders.cmake): what its passes name in PassDesc::shaders.
#pragma once

#include <span>

#include "gpu/embedded_shaders.h"

namespace bounce::render {

std::span<const gpu::EmbeddedShader> shaders();

}  // namespace bounce::render
