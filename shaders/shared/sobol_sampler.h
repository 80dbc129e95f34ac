// Low-discrepancy samples for the path tracer (RenderParams.sampler = HRPP_SAMPLER_SOBOL): each
// pair of a path vertex's sample dimensions takes the 2D Sobol (0,2)-sequence, Owen-scrambled,
// with the sample index shuffled per (pixel, depth, pair, seed) so that pixels and pairs are
// decorrelated: Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020. Within a pixel,
// the first 2^k samples of a pair form a (0,k,2)-net: one point in every elementary interval of
// area 2^-k. No tables and no loops (shaders/CMakeLists.txt kernels run under lavapipe's loop
// limiter). Shared by the render kernels and the CPU reference renderer (glsl_cpp.h).
#ifndef HRPP_SOBOL_SAMPLER_H
#define HRPP_SOBOL_SAMPLER_H

#include "glsl_cpp.h"
#include "gpu_types.h"
#include "rng.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

HRPP_INLINE uint reverse_bits(uint x) {
  x = ((x >> 1u) & 0x55555555u) | ((x & 0x55555555u) << 1u);
  x = ((x >> 2u) & 0x33333333u) | ((x & 0x33333333u) << 2u);
  x = ((x >> 4u) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4u);
  x = ((x >> 8u) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8u);
  return (x >> 16u) | (x << 16u);
}

// Sobol dimension 0 of index i, as 32 bits of a binary fraction: the van der Corput sequence.
HRPP_INLINE uint sobol_dim0(uint i) { return reverse_bits(i); }

// Sobol dimension 1: its generator matrix is Pascal's triangle mod 2, so by Lucas' theorem digit
// j is the parity of the index bits k that contain j bitwise (k & j == j): a superset sum, five
// butterfly steps.
HRPP_INLINE uint sobol_dim1(uint i) {
  i ^= (i >> 1u) & 0x55555555u;
  i ^= (i >> 2u) & 0x33333333u;
  i ^= (i >> 4u) & 0x0F0F0F0Fu;
  i ^= (i >> 8u) & 0x00FF00FFu;
  i ^= (i >> 16u) & 0x0000FFFFu;
  return reverse_bits(i);
}

// A hash in which each output bit depends only on the input bits below it (Laine and Karras
// 2011, with Burley's constants as improved by Vegdahl).
HRPP_INLINE uint laine_karras_permutation(uint x, uint seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16u) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

// Owen scrambling of a binary fraction (digit j depends on digits before it only): a random
// permutation at every node of the binary tree of intervals.
HRPP_INLINE uint nested_uniform_scramble(uint x, uint seed) {
  return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

// Sample `index` of the 2D pair whose stream is `seed`, in [0, 1)^2 (24 bits each).
HRPP_INLINE vec2 sobol_pair(uint index, uint seed) {
  const uint i = nested_uniform_scramble(index, seed);  // the pair's own sample order
  const uint x = nested_uniform_scramble(sobol_dim0(i), pcg_hash(seed ^ 0xa511e9b3u));
  const uint y = nested_uniform_scramble(sobol_dim1(i), pcg_hash(seed ^ 0x63d83595u));
  return vec2(float(x >> 8u), float(y >> 8u)) * (1.0f / 16777216.0f);
}

// The stream of pair `pair` at depth `depth` of pixel `pixel` (camera jitter: depth
// 0xFFFFFFFF).
HRPP_INLINE uint sobol_stream(uint pixel, uint depth, uint pair, uint seed) {
  return rng_init(pixel, pair, depth, seed ^ 0x5bd1e995u);
}

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_SOBOL_SAMPLER_H
