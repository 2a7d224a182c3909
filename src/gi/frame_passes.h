// The passes GiContext records around the branches, and the images they
// keep: gi.store_history (this frame's depth and normals, for the next
// frame, and the depth the visibility marches read) before them, gi.composite (the frame) after them.
// Shaders: shaders/gi/store_history.comp, shaders/gi/composite.comp.
#pragma once

#include <span>

#include "gi/image_table.h"
#include "gpu/pass.h"

namespace bounce::gi {

gpu::PassDesc storeHistoryPass();
gpu::PassDesc compositePass();

// The frame's own images, in the order of frameImageTable().
enum FrameImage : std::size_t { kHistorySurface, kMarchDepth, kComposite, kFrameImageCount };
std::span<const ImageSpec> frameImageTable();

}  // namespace bounce::gi
