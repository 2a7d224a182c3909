#include <string>

#include "gpu/embedded_shaders.h"
#include "gpu/error.h"

namespace bounce::gpu {

std::span<const std::uint32_t> findShader(std::span<const EmbeddedShader> library, std::string_view name,
                                          bool constantsInStorageBuffers) {
  for (const EmbeddedShader& shader : library)
    if (name == shader.name && shader.constantsInStorageBuffers == constantsInStorageBuffers)
      return {shader.words, shader.wordCount};
  std::string known;
  for (const EmbeddedShader& shader : library)
    if (!shader.constantsInStorageBuffers) known += std::string(known.empty() ? "" : ", ") + shader.name;
  throw GpuError("no embedded shader named '" + std::string(name) + "' (embedded: " +
                 (known.empty() ? std::string("none") : known) + ")");
}

}  // namespace bounce::gpu
