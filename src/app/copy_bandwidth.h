// bench.copy_bandwidth: a pass that only copies one buffer into another. Its GPU
// time gives the memory bandwidth compute passes can reach on a device, the
// yardstick for every bandwidth-bound pass.
#pragma once

#include <memory>
#include <span>

#include "gpu/embedded_shaders.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"

namespace bounce::app {

// The shaders of the bounce command itself (shaders/bench/, shaders/app/).
std::span<const gpu::EmbeddedShader> shaders();

class CopyBandwidthProbe {
 public:
  static constexpr const char* kPassName = "bench.copy_bandwidth";
  // Copies `bytes`, or as much as the device binds at once when that is less (see bytes()).
  CopyBandwidthProbe(gpu::Context& context, VkDeviceSize bytes);
  void record(gpu::Recorder& recorder);
  // Bytes of each buffer.
  VkDeviceSize bytes() const { return bytes_; }
  // Bytes read plus bytes written by one dispatch.
  VkDeviceSize bytesMoved() const { return 2 * bytes_; }

 private:
  VkDeviceSize bytes_;
  std::unique_ptr<gpu::Buffer> source_, destination_;
  std::unique_ptr<gpu::ComputePass> pass_;
};

}  // namespace bounce::app
