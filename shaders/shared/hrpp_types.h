// HRPP (hash-based ray path prediction): the constants and structs that the C++ side
// (host/hrpp/) and the GLSL side (shaders/lib/hrpp_*.glsl) share. One definition each; the host
// static_asserts sizes (host/hrpp/ray_hash.h, host/hrpp/predictor_table.h).
#ifndef HRPP_HRPP_TYPES_H
#define HRPP_HRPP_TYPES_H

#include "gpu_types.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

// Hash kinds (--hash). Every kind takes a precision N = 1..8 (--hash-bits) and gives a key of at
// most 48 bits; the exact definitions are in shaders/lib/hrpp_hash.glsl (the C++ mirror,
// host/hrpp/ray_hash.cpp, repeats them operation for operation).
#define HRPP_HASH_IEEE 0            // the paper's IEEE-754 bit hash with the xor swizzle
#define HRPP_HASH_GRID_SPHERICAL 1  // MICRO'21: origin on a 2^N grid, direction as θ/φ bins
#define HRPP_HASH_TWO_POINT 2       // origin and a point further along the ray, both on grids
#define HRPP_HASH_BITS_MAX 8

// Keys are < 2^48, so a tag of all ones never equals a key: it marks an empty table entry.
#define HRPP_KEY_BITS 48

// Parameters of one hash: what the kernels need besides the ray. The grid values are computed
// once on the host (host/hrpp/ray_hash.cpp, make_hash_params) and used as floats by both sides,
// so neither side divides by the scene extent itself.
//   grid_lo, grid_scale: origin cell along axis a = (o[a] - grid_lo[a]) * grid_scale[a], where
//     grid_scale[a] = 2^N / extent[a] of the scene box (0 for a flat axis: one cell);
//   far_lo, far_scale: the same for the two-point hash's second point, on the scene box grown by
//     `reach` on every side;
//   reach: the scene box's largest extent, the max-norm distance of the second point.
struct HashParams {
  vec3 grid_lo;
  uint kind;  // HRPP_HASH_*
  vec3 grid_scale;
  uint bits;  // precision N, 1..HRPP_HASH_BITS_MAX
  vec3 far_lo;
  float reach;
  vec3 far_scale;
  uint pad;
};

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_HRPP_TYPES_H
