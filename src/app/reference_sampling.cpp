#include "app/reference_sampling.h"

#include <cstdio>
#include <memory>

#include "app/progress.h"

namespace bounce::app {

render::ReferenceImages sampleReference(render::ReferenceRenderer& pathTracer, gpu::FrameLoop& sampling,
                                        std::uint32_t spp, const std::string& progressLabel,
                                        const std::string& warningContext) {
  std::unique_ptr<ProgressBar> progress;
  if (!progressLabel.empty()) progress = std::make_unique<ProgressBar>(progressLabel, spp);
  while (pathTracer.samplesPerPixel() < spp) {
    pathTracer.record(sampling.beginFrame(), std::uint32_t(spp - pathTracer.samplesPerPixel()));
    sampling.endFrame();
    if (progress) progress->update(pathTracer.samplesPerPixel());
  }
  sampling.finish();
  if (progress) progress->finish();
  render::ReferenceImages images = pathTracer.resolve(sampling, render::ReferenceHalf::Both);
  if (images.droppedSamples > 0)
    std::fprintf(stderr, "warning: %s%llu reference path samples were not finite and were left out\n",
                 warningContext.c_str(), static_cast<unsigned long long>(images.droppedSamples));
  return images;
}

}  // namespace bounce::app
