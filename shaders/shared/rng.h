// Deterministic random numbers: every (pixel, sample, depth, seed) gets its own stream, so an
// image does not depend on the order in which the wavefront queues hold the paths.
// PCG hash: Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 9(3), 2020.
// Shared by the render kernels and the CPU reference renderer (glsl_cpp.h).
#ifndef HRPP_RNG_H
#define HRPP_RNG_H

#include "glsl_cpp.h"
#include "gpu_types.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

HRPP_INLINE uint pcg_hash(uint v) {
  const uint state = v * 747796405u + 2891336453u;
  const uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

HRPP_INLINE uint rng_init(uint pixel, uint sample_index, uint depth, uint seed) {
  return pcg_hash(pixel ^ pcg_hash(sample_index ^ pcg_hash(depth ^ pcg_hash(seed))));
}

// Uniform in [0, 1): 24 random bits.
HRPP_INLINE float rng_next(HRPP_INOUT(uint) state) {
  state = pcg_hash(state);
  return float(state >> 8u) * (1.0f / 16777216.0f);
}

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_RNG_H
