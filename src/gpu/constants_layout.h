// The host's side of a constant block or push-constant block, to check it
// against the shader's SPIR-V when a pass is created (gpu/pass.h): every
// member's name, byte offset and size, as the C++ compiler lays the struct
// out. The struct is written once (in a .glsl that also compiles as C++,
// shaders/shared/lang.glsl); a mismatch with the shader's std140/std430
// layout (a vec3 followed by a float, a member added on one side) is then an
// error at pass creation that names the pass, the block and the member,
// never a silently shifted value.
//
//   BOUNCE_CONSTANTS_LAYOUT("gIn_Diffuse", DiffuseConstants, screenCandidates, brightCandidates, ...)
//   BOUNCE_CONSTANTS_LAYOUT("", SpatialReuseParams, radius, samples, passIndex)   // push constants
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace bounce::gpu {

struct MemberLayout {
  std::string name;
  std::size_t offset = 0;
  std::size_t size = 0;
};

struct ConstantsDecl {
  std::string binding;  // the block's binding name (gIn_Frame); empty: the push constants
  std::string type;     // the C++ struct, for messages
  std::size_t size = 0;
  std::vector<MemberLayout> members;  // in declaration order
};

}  // namespace bounce::gpu

#define BOUNCE_LAYOUT_MEMBER_(Type, member) \
  ::bounce::gpu::MemberLayout{#member, offsetof(Type, member), sizeof(Type::member)},

// Every member, however many (no ceiling to raise when a block grows): the
// helper names itself again after each member through BOUNCE_LAYOUT_AGAIN_,
// which is not expanded inside its own expansion, so each further member
// waits for the next rescan, and BOUNCE_LAYOUT_RESCAN_ rescans over a
// thousand times. A block longer than that would leave a macro name
// unexpanded: a compile error, never a short list.
#define BOUNCE_LAYOUT_PARENS_ ()
#define BOUNCE_LAYOUT_RESCAN_(...) \
  BOUNCE_LAYOUT_RESCAN4_(BOUNCE_LAYOUT_RESCAN4_(BOUNCE_LAYOUT_RESCAN4_(BOUNCE_LAYOUT_RESCAN4_(__VA_ARGS__))))
#define BOUNCE_LAYOUT_RESCAN4_(...) \
  BOUNCE_LAYOUT_RESCAN3_(BOUNCE_LAYOUT_RESCAN3_(BOUNCE_LAYOUT_RESCAN3_(BOUNCE_LAYOUT_RESCAN3_(__VA_ARGS__))))
#define BOUNCE_LAYOUT_RESCAN3_(...) \
  BOUNCE_LAYOUT_RESCAN2_(BOUNCE_LAYOUT_RESCAN2_(BOUNCE_LAYOUT_RESCAN2_(BOUNCE_LAYOUT_RESCAN2_(__VA_ARGS__))))
#define BOUNCE_LAYOUT_RESCAN2_(...) \
  BOUNCE_LAYOUT_RESCAN1_(BOUNCE_LAYOUT_RESCAN1_(BOUNCE_LAYOUT_RESCAN1_(BOUNCE_LAYOUT_RESCAN1_(__VA_ARGS__))))
#define BOUNCE_LAYOUT_RESCAN1_(...) __VA_ARGS__
#define BOUNCE_LAYOUT_MEMBERS_(T, a, ...) \
  BOUNCE_LAYOUT_MEMBER_(T, a) __VA_OPT__(BOUNCE_LAYOUT_AGAIN_ BOUNCE_LAYOUT_PARENS_(T, __VA_ARGS__))
#define BOUNCE_LAYOUT_AGAIN_() BOUNCE_LAYOUT_MEMBERS_

// A gpu::ConstantsDecl for `binding` ("" for push constants) holding struct
// Type, listing its members in declaration order.
#define BOUNCE_CONSTANTS_LAYOUT(binding, Type, ...)                                                   \
  ::bounce::gpu::ConstantsDecl {                                                                      \
    binding, #Type, sizeof(Type), {BOUNCE_LAYOUT_RESCAN_(BOUNCE_LAYOUT_MEMBERS_(Type, __VA_ARGS__))}, \
  }
