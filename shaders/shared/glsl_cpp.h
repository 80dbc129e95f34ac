// GLSL's names in C++: lets a header of shaders/shared/ hold functions, not only structs, that
// compile as GLSL 4.60 and as C++20 with glm, so the CPU reference renderer (host/cpu_render/)
// runs the render kernels' own shading code (docs/ARCHITECTURE.md, "Shared C++/GLSL headers").
// Rules for such code: float literals with an f suffix (a bare 1.0 is a double in C++), no
// swizzles (glm has none by default), functions marked HRPP_INLINE (one definition in every C++
// translation unit), out and inout parameters through HRPP_OUT / HRPP_INOUT, structs filled
// member by member (GLSL's T(...) needs C++20 parenthesised aggregates, which clang has only
// from 16), and no `precise` (C++ is built with -ffp-contract=off: no fused multiply-adds).
// Division, square roots, dot and cross products, normalize, length and refract go through the
// ieee_* names: correctly rounded, step by step in glm's order, on the device
// (shaders/lib/ieee_math.glsl), C++'s own operations here. What still differs is the device's
// sin, cos and pow, and the contraction of other products and sums into fused multiply-adds;
// tests/cpu_render_test.cpp measures the images' agreement.
#ifndef HRPP_GLSL_CPP_H
#define HRPP_GLSL_CPP_H

#ifdef __cplusplus
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>

namespace hrpp::gpu {
using vec2 = glm::vec2;
using ivec2 = glm::ivec2;
using glm::abs;
using glm::clamp;
using glm::floatBitsToUint;
using glm::floor;
using glm::fract;
using glm::greaterThan;
using glm::inversesqrt;
using glm::length;
using glm::max;
using glm::min;
using glm::mix;
using glm::normalize;
using glm::pow;
using glm::reflect;
using glm::refract;
using glm::smoothstep;
using glm::uintBitsToFloat;
using glm::unpackUnorm4x8;
using std::cos;
using std::sin;
using std::sqrt;

inline float ieee_div(float a, float b) { return a / b; }
inline glm::vec3 ieee_div(glm::vec3 a, float b) { return a / b; }
inline float ieee_sqrt(float x) { return std::sqrt(x); }
inline float ieee_inversesqrt(float x) { return glm::inversesqrt(x); }
inline float ieee_dot(glm::vec3 a, glm::vec3 b) { return glm::dot(a, b); }
inline glm::vec3 ieee_cross(glm::vec3 a, glm::vec3 b) { return glm::cross(a, b); }
inline float ieee_length(glm::vec3 v) { return glm::length(v); }
inline glm::vec3 ieee_normalize(glm::vec3 v) { return glm::normalize(v); }
inline glm::vec3 ieee_refract(glm::vec3 i, glm::vec3 n, float eta) { return glm::refract(i, n, eta); }
}  // namespace hrpp::gpu

#define HRPP_INLINE inline
#define HRPP_OUT(T) T&
#define HRPP_INOUT(T) T&
#else
#include "ieee_math.glsl"
#define HRPP_INLINE
#define HRPP_OUT(T) out T
#define HRPP_INOUT(T) inout T
#endif

#endif  // HRPP_GLSL_CPP_H
