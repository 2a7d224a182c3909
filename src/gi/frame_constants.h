// What every GI pass of a frame shares: the frame constants (cameras,
// render size, the engine's encodings) and the group of three bindings every
// pass that looks at this frame's surfaces binds: gIn_Frame, gIn_ViewZ and
// gIn_NormalRoughness (shaders/gi/gi_common.glsl and gi/gbuffer.glsl).
#pragma once

#include <array>
#include <span>
#include <vector>

#include "bounce/gi.h"
#include "gi/gi_types.glsl"
#include "gpu/constants_layout.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"

namespace bounce::gi {

// The ScreenView of a camera; throws Error naming `which` ("camera",
// "previousCamera") for one the library cannot use: matrices or jitter not
// finite, a projection that is not a symmetric perspective looking down -Z,
// a view matrix without an inverse.
shared::ScreenView screenView(const Camera& camera, const char* which);

// How much of the group a pass binds: always a prefix, so that every pass
// finds the three at the same bindings (0, 1, 2) and binds them with one
// span. A pass binds only what its shader reads (SPIR-V keeps no unused
// binding, and the host checks each declared one against the shader).
enum class GroupPart {
  Constants = 1,  // gIn_Frame
  Depth = 2,      // + gIn_ViewZ
  Surfaces = 3,   // + gIn_NormalRoughness
};

// The declarations of that part of the group, in binding order.
std::vector<gpu::ResourceDecl> frameGroupDecls(GroupPart part = GroupPart::Surfaces);
// The layout of gIn_Frame (GiFrameConstants), for PassDesc::constants.
gpu::ConstantsDecl frameConstantsLayout();

// The group's binds for one frame. The engine's images are read with
// texelFetch; `nearest` is the sampler they are bound with.
class FrameGroup {
 public:
  FrameGroup(gpu::Buffer& frameConstants, gpu::Image& viewZ, gpu::Image& normalRoughness, VkSampler nearest);
  std::span<const gpu::Bind> binds(GroupPart part = GroupPart::Surfaces) const {
    return std::span<const gpu::Bind>(binds_).first(std::size_t(part));
  }

 private:
  std::array<gpu::Bind, 3> binds_;
};

}  // namespace bounce::gi
