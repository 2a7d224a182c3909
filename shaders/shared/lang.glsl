// The small language shim that lets every file in shaders/shared/ compile both
// as GLSL (for the GPU) and as C++ with glm (for CPU tests and CPU tools).
//
// Rules for shared code, so that both compilers accept it and agree:
// - float literals carry an f suffix (1.0f): GLSL accepts it, and C++ then
//   never promotes to double.
// - no swizzles (v.xy): write vec2(v.x, v.y).
// - out / inout parameters are written OUT(T) / INOUT(T).
// - no GLSL-only built-ins that glm lacks; glm has pack*/unpack*, floatBitsTo*.
// - at most one call with side effects (rngUniform, rngNext) per
//   expression: C++ leaves the order of a call's arguments open, GLSL
//   evaluates them left to right.
// - signs are written as (x >= 0.0f ? 1.0f : -1.0f) where 0 must map to +1,
//   since sign(0) is 0 in both languages.
#ifndef BOUNCE_SHARED_LANG_GLSL
#define BOUNCE_SHARED_LANG_GLSL

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>
namespace bounce::shared {
using namespace glm;
using uint = std::uint32_t;
}  // namespace bounce::shared
#define INOUT(T) T&
#define OUT(T) T&
// Internal linkage (an unnamed namespace) so that the header-defined functions
// can be included by many translation units without violating the ODR; the
// pragma keeps GCC quiet about the ones a given file does not use.
#define BOUNCE_SHARED_BEGIN                                  \
  _Pragma("GCC diagnostic push")                             \
  _Pragma("GCC diagnostic ignored \"-Wunused-function\"")   \
  namespace bounce::shared { namespace {
#define BOUNCE_SHARED_END } } _Pragma("GCC diagnostic pop")
#else
#define INOUT(T) inout T
#define OUT(T) out T
#define BOUNCE_SHARED_BEGIN
#define BOUNCE_SHARED_END
#endif

BOUNCE_SHARED_BEGIN
const float kPi = 3.14159265358979f;
const float kInvPi = 0.318309886183791f;
BOUNCE_SHARED_END

#endif
