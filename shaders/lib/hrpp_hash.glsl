// HRPP ray hashes: a ray → a key of at most 48 bits. The C++ mirror is host/hrpp/ray_hash.cpp;
// both must agree bit for bit on every input (tests/hrpp_hash_gpu_test.cpp), so everything here
// is integer work on the float bits or single IEEE operations (+ - × / and compares) marked
// `precise`, in the mirror's order; no transcendental functions (their accuracy differs).
// The including kernel enables GL_EXT_shader_explicit_arithmetic_types_int64.
//
// Special floats, the same in every kind:
//   - -0 hashes as +0 (the same ray);
//   - every NaN hashes as the positive quiet NaN 0x7FC00000 (payloads and signs differ);
//   - subnormals and ±Inf keep their bits (exponent 0 and 255 are ordinary exponents here);
//   - grid/θ/φ bins: a NaN value or one below the range falls in bin 0, one at or above the
//     range in the last bin (so ±Inf origins land in the border cells); the grid hashes flush
//     subnormal inputs to +0 (see hrpp_flushed).
#ifndef HRPP_HASH_GLSL
#define HRPP_HASH_GLSL

#include "hrpp_types.h"
#include "ieee_math.glsl"
#include "micro21_bins.h"

uint hrpp_canonical_bits(float f) {
  const uint b = floatBitsToUint(f);
  if ((b & 0x7FFFFFFFu) > 0x7F800000u) return 0x7FC00000u;  // NaN
  if (b == 0x80000000u) return 0u;                           // -0
  return b;
}

// The paper's per-float hash at precision n: the sign bit, the n most significant bits of the
// (biased) exponent and the top min(n, 7) bits of the mantissa, as sign | exponent | mantissa.
// At n = 8 the mantissa keeps 7 bits so the field stays 16 bits wide (1 + 8 + 7); every
// precision's field is then a bit-selection of the next one's, so keys are monotone in n.
uint hrpp_float_hash(float f, uint n) {
  const uint b = hrpp_canonical_bits(f);
  const uint m_bits = min(n, 7u);
  const uint sign = b >> 31;
  const uint exponent = (b >> 23) & 0xFFu;
  const uint mantissa = b & 0x7FFFFFu;
  return (sign << (n + m_bits)) | ((exponent >> (8u - n)) << m_bits) | (mantissa >> (23u - m_bits));
}

// IEEE hash with the paper's xor swizzle: hash_0 = h(o.x) ^ h(d.z), hash_1 = h(o.y) ^ h(d.y),
// hash_2 = h(o.z) ^ h(d.x); key = hash_0 | hash_1 << 16 | hash_2 << 32.
uint64_t hrpp_hash_ieee(vec3 o, vec3 d, uint n) {
  const uint h0 = hrpp_float_hash(o.x, n) ^ hrpp_float_hash(d.z, n);
  const uint h1 = hrpp_float_hash(o.y, n) ^ hrpp_float_hash(d.y, n);
  const uint h2 = hrpp_float_hash(o.z, n) ^ hrpp_float_hash(d.x, n);
  return uint64_t(h0) | (uint64_t(h1) << 16) | (uint64_t(h2) << 32);
}

// Bin of x in [0, cells): NaN or x < 0 → 0, x >= cells → cells - 1, else floor(x). NaN is
// tested on the bits: a compiler may rewrite !(x >= 0) as x < 0.
uint hrpp_bin(float x, uint cells) {
  if ((floatBitsToUint(x) & 0x7FFFFFFFu) > 0x7F800000u || x < 0.0) return 0u;
  if (x >= float(cells)) return cells - 1u;
  return min(uint(x), cells - 1u);
}

// Grid hashes do arithmetic, and a GPU may flush subnormals to zero (llvmpipe does) where the
// CPU does not. So their inputs are canonical (hrpp_canonical) with subnormals flushed to +0 by
// bits first; what stays subnormal inside is too small to move a value across a bin boundary
// (it would need a scene smaller than 2^-118).
float hrpp_flushed(float f) {
  const uint b = hrpp_canonical_bits(f);
  return (b & 0x7F800000u) == 0u ? 0.0 : uintBitsToFloat(b);
}

vec3 hrpp_flushed(vec3 v) { return vec3(hrpp_flushed(v.x), hrpp_flushed(v.y), hrpp_flushed(v.z)); }

uint hrpp_abs_bits(float f) { return floatBitsToUint(f) & 0x7FFFFFFFu; }

// Origin cell on the 2^n grid: ((p - lo) × scale) per axis, packed x | y << n | z << 2n.
uint hrpp_grid_cell(vec3 p, vec3 lo, vec3 scale, uint n) {
  const uint cells = 1u << n;
  precise vec3 x = (p - lo) * scale;
  return hrpp_bin(x.x, cells) | (hrpp_bin(x.y, cells) << n) | (hrpp_bin(x.z, cells) << (2u * n));
}

// The direction scaled by a power of two (exact) so its largest component lies in [2, 4), then
// components below 2^-60 set to +0 (a flush-to-zero GPU and the CPU then see the same numbers and
// no product below underflows). Returns false for a zero or non-finite direction.
bool hrpp_scaled_direction(vec3 dir, out vec3 u) {
  u = vec3(0.0);
  const vec3 d = hrpp_flushed(dir);
  const uint m = max(max(hrpp_abs_bits(d.x), hrpp_abs_bits(d.y)), hrpp_abs_bits(d.z));
  if (m == 0u || m >= 0x7F800000u) return false;
  const uint e = m >> 23;  // 1..254
  precise vec3 s = d * uintBitsToFloat((255u - e) << 23);  // × 2^(128 - e)
  const uint tiny = 0x21800000u;                            // 2^-60
  u = vec3(hrpp_abs_bits(s.x) < tiny ? 0.0 : s.x, hrpp_abs_bits(s.y) < tiny ? 0.0 : s.y,
           hrpp_abs_bits(s.z) < tiny ? 0.0 : s.z);
  return true;
}

// The diamond angle of (x, y) ≠ (0, 0): a number in [0, 4) monotone in the angle from the x axis,
// counter-clockwise (quadrant q covers [q, q + 1)), from a = x / s, b = y / s, s = |x| + |y|.
float hrpp_diamond_angle(float x, float y) {
  precise float s = abs(x) + abs(y);
  precise float a = ieee_div(x, s);
  precise float b = ieee_div(y, s);
  precise float q1 = 1.0 - a;
  precise float q2 = 2.0 - b;
  precise float q3 = 3.0 + a;
  return b >= 0.0 ? (a >= 0.0 ? b : q1) : (a < 0.0 ? q2 : q3);
}

// cos θ × |cos θ| of the scaled direction u: c = u.z|u.z| / |u|², monotone in θ (no sqrt or
// acos).
float hrpp_signed_cos2(vec3 u) {
  precise float len2 = u.x * u.x + u.y * u.y + u.z * u.z;
  precise float c = ieee_div(u.z * abs(u.z), len2);
  return c;
}

// Direction bins: θ through the signed squared cosine c (hrpp_signed_cos2), θ-bin =
// bin((c + 1) × 2^(n-1)); φ through the diamond angle p ∈ [0, 4) of (d.x, d.y) (monotone in
// φ, no atan2), φ-bin = bin(p × 2^(n-2)), on the scaled direction of hrpp_scaled_direction. A
// zero or non-finite direction gets θ-bin = φ-bin = 0. Returns θ-bin | φ-bin << n.
uint hrpp_direction_bins(vec3 dir, uint n) {
  const uint cells = 1u << n;
  vec3 u;
  if (!hrpp_scaled_direction(dir, u)) return 0u;
  const float c = hrpp_signed_cos2(u);
  precise float theta_x = (c + 1.0) * uintBitsToFloat((126u + n) << 23);  // × 2^(n-1)
  const uint theta = hrpp_bin(theta_x, cells);
  const float p = (u.x != 0.0 || u.y != 0.0) ? hrpp_diamond_angle(u.x, u.y) : 0.0;
  precise float phi_x = p * uintBitsToFloat((125u + n) << 23);  // × 2^(n-2)
  const uint phi = hrpp_bin(phi_x, cells);
  return theta | (phi << n);
}

// MICRO'21 grid-spherical hash (Liu et al., "Intersection Prediction for Accelerated GPU Ray
// Tracing"): origin cell (3n bits) | θ-bin << 3n | φ-bin << (3n + d), with d = h.second_bits
// bits per direction bin (3n + 2d ≤ 40 bits).
uint64_t hrpp_hash_grid_spherical(vec3 o, vec3 d, HashParams h) {
  const uint n = h.bits;
  return uint64_t(hrpp_grid_cell(hrpp_flushed(o), h.grid_lo, h.grid_scale, n)) |
         (uint64_t(hrpp_direction_bins(d, h.second_bits)) << (3u * n));
}

// MICRO'21's own grid-spherical hash (its simulator's rt-sim.cc, hash_grid_spherical): the
// origin's cell on the 2^n grid packed x << 2n | y << n | z (x highest), xor the direction's
// bins φ-bin << 3 | θ-bin at 32° each (shaders/shared/micro21_bins.h), on the scaled direction
// (hrpp_scaled_direction). A key of max(3n, 7) bits.
uint64_t hrpp_hash_micro21(vec3 o, vec3 d, HashParams h) {
  const uint n = h.bits, cells = 1u << n;
  precise vec3 x = (hrpp_flushed(o) - h.grid_lo) * h.grid_scale;
  const uint cell = (hrpp_bin(x.x, cells) << (2u * n)) | (hrpp_bin(x.y, cells) << n) |
                    hrpp_bin(x.z, cells);
  vec3 u;
  uint theta = HRPP_MICRO21_THETA_BIN_ZERO, phi = HRPP_MICRO21_PHI_BIN_VERTICAL;
  if (hrpp_scaled_direction(d, u)) {
    theta = hrpp_micro21_theta_bin(hrpp_signed_cos2(u));
    if (u.y == 0.0 && u.x < 0.0)
      phi = HRPP_MICRO21_PHI_BIN_MINUS_X;
    else if (u.x != 0.0 || u.y != 0.0)
      phi = hrpp_micro21_phi_bin(hrpp_diamond_angle(-u.x, -u.y));
  }
  return uint64_t(cell ^ ((phi << HRPP_MICRO21_SPHERE_BITS) | theta));
}

// Two-point hash: the origin's cell on the scene grid and the cell of q = o + u × (reach / m),
// with u the scaled direction (hrpp_scaled_direction) and m its largest |component| (q lies
// `reach` away from o in the max norm), on the grid over the scene box grown by reach:
// origin cell | q's cell << 3n (6n ≤ 48 bits). A zero or non-finite direction puts q in cell 0.
uint64_t hrpp_hash_two_point(vec3 o, vec3 d, HashParams h) {
  const uint n = h.bits;
  const vec3 oc = hrpp_flushed(o);
  vec3 u;
  uint far_cell = 0u;
  if (hrpp_scaled_direction(d, u)) {
    const float m = uintBitsToFloat(max(max(hrpp_abs_bits(u.x), hrpp_abs_bits(u.y)),
                                        hrpp_abs_bits(u.z)));
    precise float k = ieee_div(h.reach, m);
    precise vec3 q = oc + u * k;
    far_cell = hrpp_grid_cell(q, h.far_lo, h.far_scale, n);
  }
  return uint64_t(hrpp_grid_cell(oc, h.grid_lo, h.grid_scale, n)) |
         (uint64_t(far_cell) << (3u * n));
}

// Octahedral cells of a direction: (a, b) = (u.x, u.y) / (|u.x| + |u.y| + |u.z|) on the scaled
// direction u (hrpp_scaled_direction), the lower hemisphere folded over the diamond's edges
// (a, b) → (±(1 - |b|), ±(1 - |a|)) with the signs of a and b, then each of a, b ∈ [-1, 1] binned
// as bin((x + 1) × 2^(n-1)). Cells within a factor 3 of each other's solid angle, no
// trigonometry. A zero or non-finite direction is cell 0. Returns a-bin | b-bin << n.
uint hrpp_octahedral_cell(vec3 dir, uint n) {
  const uint cells = 1u << n;
  vec3 u;
  if (!hrpp_scaled_direction(dir, u)) return 0u;
  precise float s = abs(u.x) + abs(u.y) + abs(u.z);
  precise float a = ieee_div(u.x, s);
  precise float b = ieee_div(u.y, s);
  if (u.z < 0.0) {
    precise float fa = 1.0 - abs(b);
    precise float fb = 1.0 - abs(a);
    a = a >= 0.0 ? fa : -fa;
    b = b >= 0.0 ? fb : -fb;
  }
  const float scale = uintBitsToFloat((126u + n) << 23);  // 2^(n-1)
  precise float x = (a + 1.0) * scale;
  precise float y = (b + 1.0) * scale;
  return hrpp_bin(x, cells) | (hrpp_bin(y, cells) << n);
}

// Light-space keys for shadow rays, which run from a receiver o towards a point on a light and
// end there (tmax): the light end e = o + d × tmax on the grid over the scene box at C =
// second_bits = min(n + 1, 8) bits per axis (far_lo, far_scale: which light, and which part of an
// area light; a directional light's rays end far outside, in a border cell) | the octahedral
// cell of -d (the direction from the light to the receiver, at n bits) << 3C; with `with_depth`
// also the receiver's distance from the light in quarter octaves, bits 21..28 of tmax (sign,
// exponent and 2 mantissa bits; 8 bits, wrapping every 64 octaves) << (3C + 2n): the light end
// and the direction fix the line, the depth where on it the receiver lies (3C + 2n + 8 ≤ 48
// bits). Receivers in one cone from one part of a light share a key, so they test the occluders
// that earlier rays of that cone found first.
uint64_t hrpp_hash_light(vec3 o, vec3 d, float tmax, HashParams h, bool with_depth) {
  const uint n = h.bits, c = h.second_bits;
  const vec3 oc = hrpp_flushed(o);
  precise vec3 e = oc + hrpp_flushed(d) * hrpp_flushed(tmax);
  uint64_t key = uint64_t(hrpp_grid_cell(e, h.far_lo, h.far_scale, c)) |
                 (uint64_t(hrpp_octahedral_cell(-d, n)) << (3u * c));
  if (with_depth) key |= uint64_t((hrpp_canonical_bits(tmax) >> 21) & 0xFFu) << (3u * c + 2u * n);
  return key;
}

// The key of a ray with its end tmax (only the light-space keys read it).
uint64_t hrpp_hash_ray(vec3 o, vec3 d, float tmax, HashParams h) {
  if (h.kind == HRPP_HASH_GRID_SPHERICAL) return hrpp_hash_grid_spherical(o, d, h);
  if (h.kind == HRPP_HASH_TWO_POINT) return hrpp_hash_two_point(o, d, h);
  if (h.kind == HRPP_HASH_LIGHT) return hrpp_hash_light(o, d, tmax, h, false);
  if (h.kind == HRPP_HASH_LIGHT_DEPTH) return hrpp_hash_light(o, d, tmax, h, true);
  if (h.kind == HRPP_HASH_MICRO21) return hrpp_hash_micro21(o, d, h);
  return hrpp_hash_ieee(o, d, h.bits);
}

#endif  // HRPP_HASH_GLSL
