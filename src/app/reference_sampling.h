// Sampling a path-traced reference up to a number of samples per pixel, as
// the commands that measure against one (denoise, ghosting) do it.
#pragma once

#include <cstdint>
#include <string>

#include "gpu/frame_loop.h"
#include "render/reference_renderer.h"

namespace bounce::app {

// Adds samples to `pathTracer` until it holds `spp` a pixel (with a progress
// bar named `progressLabel`; none when it is empty), resolves both halves
// and reads them back. Non-finite path samples were left out: says so on
// stderr, after `warningContext` (e.g. "frame 12: ").
render::ReferenceImages sampleReference(render::ReferenceRenderer& pathTracer, gpu::FrameLoop& sampling,
                                        std::uint32_t spp, const std::string& progressLabel,
                                        const std::string& warningContext = "");

}  // namespace bounce::app
