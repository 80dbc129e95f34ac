// The direction bins of MICRO'21's grid-spherical hash (Liu, Chang, Demoullin et al.,
// "Intersection Prediction for Accelerated GPU Ray Tracing", MICRO 2021; its simulator's
// rt-sim.cc, hash_direction_spherical) at its published 3 sphere bits: θ = acos(d.z) and
// φ = atan2(d.y, d.x) + π in whole degrees, each shifted right by 5 (bins of 32°: θ-bin 0..5,
// φ-bin 0..11). Here without transcendental functions, so that the GPU and the CPU agree bit
// for bit: each bin is the number of bin edges (32°, 64°, ...) at or below the angle, found by
// comparing a monotone image of the angle with the edges' images (computed in double, rounded
// to float; tests/hrpp_hash_test.cpp recomputes them). A ray within a float's rounding of an
// edge may land one bin from the source's, whose acos and atan2 round in float too.
// One definition for shaders/lib/hrpp_hash.glsl and host/hrpp/ray_hash.cpp.
#ifndef HRPP_MICRO21_BINS_H
#define HRPP_MICRO21_BINS_H

#include "glsl_cpp.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

#define HRPP_MICRO21_SPHERE_BITS 3u  // θ-bin | φ-bin << 3

// θ-bin from c = cos θ × |cos θ| (the signed squared cosine d.z|d.z| / |d|²): θ ≥ 32k° ⟺
// c ≤ cos 32k° × |cos 32k°|, k = 1..5.
HRPP_INLINE uint hrpp_micro21_theta_bin(float c) {
  return (c <= uintBitsToFloat(0x3F381C8Cu) ? 1u : 0u) +  // 32°: 0.719185591
         (c <= uintBitsToFloat(0x3E44C805u) ? 1u : 0u) +  // 64°: 0.192169264
         (c <= uintBitsToFloat(0xBC3303CEu) ? 1u : 0u) +  // 96°: -0.0109262001
         (c <= uintBitsToFloat(0xBEC21168u) ? 1u : 0u) +  // 128°: -0.379039049
         (c <= uintBitsToFloat(0xBF620DBFu) ? 1u : 0u);   // 160°: -0.883022249
}

// φ-bin from the diamond angle p ∈ [0, 4) of (-d.x, -d.y) (φ = atan2(d.y, d.x) + π measured as
// the angle of -d from the x axis; p is monotone in it): φ ≥ 32k° ⟺ p ≥ diamond(32k°),
// k = 1..11.
HRPP_INLINE uint hrpp_micro21_phi_bin(float p) {
  return (p >= uintBitsToFloat(0x3EC4E5D2u) ? 1u : 0u) +  // 32°: 0.38456589
         (p >= uintBitsToFloat(0x3F2C12EDu) ? 1u : 0u) +  // 64°: 0.672163785
         (p >= uintBitsToFloat(0x3F8C2C80u) ? 1u : 0u) +  // 96°: 1.09510803
         (p >= uintBitsToFloat(0x3FB8244Cu) ? 1u : 0u) +  // 128°: 1.43860769
         (p >= uintBitsToFloat(0x3FDDD7FCu) ? 1u : 0u) +  // 160°: 1.73315382
         (p >= uintBitsToFloat(0x400B380Eu) ? 1u : 0u) +  // 192°: 2.17529631
         (p >= uintBitsToFloat(0x401F7102u) ? 1u : 0u) +  // 224°: 2.49127245
         (p >= uintBitsToFloat(0x40333A40u) ? 1u : 0u) +  // 256°: 2.8004303
         (p >= uintBitsToFloat(0x404FB1F8u) ? 1u : 0u) +  // 288°: 3.24523735
         (p >= uintBitsToFloat(0x4062CCB5u) ? 1u : 0u) +  // 320°: 3.54374433
         (p >= uintBitsToFloat(0x40781D1Du) ? 1u : 0u);   // 352°: 3.87677693
}

// The bins of a direction with no x and y part (atan2(0, 0) = 0: φ = 180°) and of one along -x
// with y = +0 (atan2(+0, x < 0) = π: φ = 360°), which the diamond angle does not tell apart from
// its neighbours.
#define HRPP_MICRO21_PHI_BIN_VERTICAL 5u
#define HRPP_MICRO21_PHI_BIN_MINUS_X 11u
// A zero or non-finite direction: as the source's zero vector (θ = acos 0 = 90°, φ = 180°).
#define HRPP_MICRO21_THETA_BIN_ZERO 2u

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_MICRO21_BINS_H
