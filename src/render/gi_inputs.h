// The frame renderer as the GI library's first user: its images and cameras
// as a gi::FrameInputs, exactly what an engine would hand the library.
#pragma once

#include <cstdint>

#include "bounce/gi.h"
#include "render/frame_renderer.h"

namespace bounce::render {

// The gi::Camera of a pose rendered at width x height with `jitter` (pixels).
gi::Camera giCamera(const scene::CameraPose& pose, std::uint32_t width, std::uint32_t height, glm::vec2 jitter);

// The inputs of frame `frameIndex`, which `renderer` has just recorded with
// `view`; `previous` is the view of the frame before (ignored on a cut or
// for the first frame).
gi::FrameInputs giFrameInputs(FrameRenderer& renderer, std::uint64_t frameIndex, const FrameView& view,
                              const FrameView& previous, bool jitter);

}  // namespace bounce::render
