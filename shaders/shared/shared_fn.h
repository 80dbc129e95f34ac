// HRPP_SHARED_FN marks a function of a shaders/shared/ header that uses only integers and is
// compiled by the host (C++20: `inline constexpr`) and by GLSL (nothing) from one definition
// (docs/ARCHITECTURE.md, "Shared C++/GLSL headers"); in C++ GLSL's integer names are aliases
// in hrpp::gpu, which such a header opens under __cplusplus itself.
#ifndef HRPP_SHARED_FN_H
#define HRPP_SHARED_FN_H

#ifdef __cplusplus
#include <cstdint>
namespace hrpp::gpu {
using uint = std::uint32_t;
using uint64_t = std::uint64_t;
}  // namespace hrpp::gpu
#define HRPP_SHARED_FN inline constexpr
#else
#define HRPP_SHARED_FN
#endif

#endif  // HRPP_SHARED_FN_H
