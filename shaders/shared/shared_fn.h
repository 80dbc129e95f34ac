// HRPP_SHARED_FN marks a function of a shaders/shared/ header that uses only integers and is
// compiled by the host (C++20: `inline constexpr`) and by GLSL (nothing) from one definition
// (docs/ARCHITECTURE.md, "Shared C++/GLSL headers"). The header opens `namespace hrpp::gpu`
// under __cplusplus itself.
#ifndef HRPP_SHARED_FN_H
#define HRPP_SHARED_FN_H

#ifdef __cplusplus
#include <cstdint>
#define HRPP_SHARED_FN inline constexpr
#else
#define HRPP_SHARED_FN
#endif

#endif  // HRPP_SHARED_FN_H
