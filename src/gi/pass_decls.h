// Building blocks of the branches' pass declarations (gpu::PassDesc): the
// resources several branches declare alike, and a pass that binds (part
// of) the frame group first. Each branch adds its own constants
// (src/gi/diffuse/diffuse_passes.cpp, src/gi/specular/specular_passes.cpp).
#pragma once

#include <string>
#include <vector>

#include "gi/frame_constants.h"
#include "gpu/pass.h"

namespace bounce::gi {

gpu::ResourceDecl previousSurfaceDecl();  // gPrev_Surface
gpu::ResourceDecl currentSurfaceDecl();   // gIn_Surface
gpu::ResourceDecl motionDecl();           // gIn_Motion
// A reservoir image pair, `prefix`_Reservoir0/1: rgba32ui each, 32 bytes a
// reservoir (shared/reservoir.glsl).
std::vector<gpu::ResourceDecl> reservoirDecls(const char* prefix, gpu::Access access, const char* purpose);
std::vector<gpu::ResourceDecl> joinDecls(std::vector<gpu::ResourceDecl> a, const std::vector<gpu::ResourceDecl>& b);

// A pass that reads (part of) the frame group first, then its own
// resources, and no branch's constants.
gpu::PassDesc framePass(std::string name, const char* shader, GroupPart group,
                        const std::vector<gpu::ResourceDecl>& own);

}  // namespace bounce::gi
