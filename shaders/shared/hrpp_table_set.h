// The set of an HRPP predictor table that holds a key: (key × the 64-bit golden-ratio constant)
// >> 32, modulo the power-of-two set count. One definition for the GPU table
// (shaders/lib/hrpp_table.glsl) and its CPU mirror (host/hrpp/reference_table.cpp). GLSL
// includers enable 64-bit integers first.
#ifndef HRPP_HRPP_TABLE_SET_H
#define HRPP_HRPP_TABLE_SET_H

#include "shared_fn.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

HRPP_SHARED_FN uint hrpp_set_of(uint64_t key, uint sets) {
  return uint((key * 0x9E3779B97F4A7C15ul) >> 32) & (sets - 1u);
}

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_HRPP_TABLE_SET_H
