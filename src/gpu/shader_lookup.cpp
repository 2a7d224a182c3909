#include <string>

#include "gpu/embedded_shaders.h"
#include "gpu/error.h"

namespace bounce::gpu {

std::span<const std::uint32_t> findShader(std::string_view name) {
  for (const EmbeddedShader& shader : embeddedShaders())
    if (name == shader.name) return {shader.words, shader.wordCount};
  std::string known;
  for (const EmbeddedShader& shader : embeddedShaders()) known += std::string(known.empty() ? "" : ", ") + shader.name;
  throw GpuError("no embedded shader named '" + std::string(name) + "' (embedded: " + known + ")");
}

}  // namespace bounce::gpu
