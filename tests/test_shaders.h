// The tests' own shaders (shaders/tests/), embedded in bounce_test_shaders:
// probes of the gpu layer and of the shared math that no product carries.
#pragma once

#include <span>

#include "gpu/embedded_shaders.h"

namespace bounce::tests {

std::span<const gpu::EmbeddedShader> shaders();

}  // namespace bounce::tests
