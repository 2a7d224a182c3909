// gpu.copy_bandwidth: a pass that only copies one buffer into another. Its GPU
// time gives the memory bandwidth compute passes can reach on a device, the
// yardstick for every bandwidth-bound pass.
#pragma once

#include <memory>

#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"

namespace bounce::gpu {

class CopyBandwidthProbe {
 public:
  static constexpr const char* kPassName = "gpu.copy_bandwidth";
  // Copies `bytes`, or as much as the device binds at once when that is less (see bytes()).
  CopyBandwidthProbe(Context& context, VkDeviceSize bytes);
  void record(Recorder& recorder);
  // Bytes of each buffer.
  VkDeviceSize bytes() const { return bytes_; }
  // Bytes read plus bytes written by one dispatch.
  VkDeviceSize bytesMoved() const { return 2 * bytes_; }

 private:
  VkDeviceSize bytes_;
  std::unique_ptr<Buffer> source_, destination_;
  std::unique_ptr<ComputePass> pass_;
};

}  // namespace bounce::gpu
