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

// One macro per member count keeps this plain C++ with no preprocessor
// recursion; up to 32 members.
#define BOUNCE_LAYOUT_1_(T, a) BOUNCE_LAYOUT_MEMBER_(T, a)
#define BOUNCE_LAYOUT_2_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_1_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_3_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_2_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_4_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_3_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_5_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_4_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_6_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_5_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_7_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_6_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_8_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_7_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_9_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_8_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_10_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_9_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_11_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_10_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_12_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_11_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_13_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_12_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_14_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_13_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_15_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_14_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_16_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_15_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_17_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_16_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_18_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_17_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_19_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_18_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_20_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_19_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_21_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_20_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_22_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_21_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_23_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_22_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_24_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_23_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_25_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_24_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_26_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_25_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_27_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_26_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_28_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_27_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_29_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_28_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_30_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_29_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_31_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_30_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_32_(T, a, ...) BOUNCE_LAYOUT_MEMBER_(T, a) BOUNCE_LAYOUT_31_(T, __VA_ARGS__)
#define BOUNCE_LAYOUT_PICK_(_1, _2, _3, _4, _5, _6, _7, _8, _9, _10, _11, _12, _13, _14, _15, _16, _17, _18, _19, _20, \
                            _21, _22, _23, _24, _25, _26, _27, _28, _29, _30, _31, _32, NAME, ...)                     \
  NAME

// A gpu::ConstantsDecl for `binding` ("" for push constants) holding struct
// Type, listing its members in declaration order.
#define BOUNCE_CONSTANTS_LAYOUT(binding, Type, ...)                                                                    \
  ::bounce::gpu::ConstantsDecl {                                                                                       \
    binding, #Type, sizeof(Type), {                                                                                    \
      BOUNCE_LAYOUT_PICK_(__VA_ARGS__, BOUNCE_LAYOUT_32_, BOUNCE_LAYOUT_31_, BOUNCE_LAYOUT_30_, BOUNCE_LAYOUT_29_,     \
                          BOUNCE_LAYOUT_28_, BOUNCE_LAYOUT_27_, BOUNCE_LAYOUT_26_, BOUNCE_LAYOUT_25_,                  \
                          BOUNCE_LAYOUT_24_, BOUNCE_LAYOUT_23_, BOUNCE_LAYOUT_22_, BOUNCE_LAYOUT_21_,                  \
                          BOUNCE_LAYOUT_20_, BOUNCE_LAYOUT_19_, BOUNCE_LAYOUT_18_, BOUNCE_LAYOUT_17_,                  \
                          BOUNCE_LAYOUT_16_, BOUNCE_LAYOUT_15_, BOUNCE_LAYOUT_14_, BOUNCE_LAYOUT_13_,                  \
                          BOUNCE_LAYOUT_12_, BOUNCE_LAYOUT_11_, BOUNCE_LAYOUT_10_, BOUNCE_LAYOUT_9_, BOUNCE_LAYOUT_8_, \
                          BOUNCE_LAYOUT_7_, BOUNCE_LAYOUT_6_, BOUNCE_LAYOUT_5_, BOUNCE_LAYOUT_4_, BOUNCE_LAYOUT_3_,    \
                          BOUNCE_LAYOUT_2_, BOUNCE_LAYOUT_1_)                                                          \
      (Type, __VA_ARGS__)                                                                                              \
    }                                                                                                                  \
  }
