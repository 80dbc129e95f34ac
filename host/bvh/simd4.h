// Four-lane vectors for the BVH builder's hot loops: SSE2 on x86-64, plain arrays elsewhere.
// Every operation is the IEEE operation of the scalar code lane by lane, so both versions give
// the same bits. A box corner keeps x, y, z in lanes 0-2 and 0 in lane 3; the SAH sweep keeps
// the three axes in lanes 0-2.
#pragma once

#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace hrpp::simd {

#if defined(__SSE2__)

struct Float4 {
  __m128 v;
};
struct Int4 {
  __m128i v;
};

// Loads p[0..2] and 0 (reads p[3], which callers may use for other data).
inline Float4 load3(const float* p) {
  const __m128 mask = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
  return {_mm_and_ps(_mm_loadu_ps(p), mask)};
}
inline void store(float* p, Float4 a) { _mm_storeu_ps(p, a.v); }
inline Float4 splat3(float x) { return {_mm_set_ps(0.0f, x, x, x)}; }
inline Float4 set3(float x, float y, float z) { return {_mm_set_ps(0.0f, z, y, x)}; }
inline Float4 operator+(Float4 a, Float4 b) { return {_mm_add_ps(a.v, b.v)}; }
inline Float4 operator-(Float4 a, Float4 b) { return {_mm_sub_ps(a.v, b.v)}; }
inline Float4 operator*(Float4 a, Float4 b) { return {_mm_mul_ps(a.v, b.v)}; }
inline Float4 operator/(Float4 a, Float4 b) { return {_mm_div_ps(a.v, b.v)}; }
inline Float4 min(Float4 a, Float4 b) { return {_mm_min_ps(a.v, b.v)}; }
inline Float4 max(Float4 a, Float4 b) { return {_mm_max_ps(a.v, b.v)}; }
// Truncates toward zero into out[0..3].
inline void truncate(Float4 a, std::int32_t out[4]) {
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_cvttps_epi32(a.v));
}
// Rows x, y, z of the matrix whose columns are a, b, c (lane 3 of each row 0).
inline void transpose3(Float4 a, Float4 b, Float4 c, Float4& x, Float4& y, Float4& z) {
  __m128 r0 = a.v, r1 = b.v, r2 = c.v, r3 = _mm_setzero_ps();
  _MM_TRANSPOSE4_PS(r0, r1, r2, r3);
  x = {r0};
  y = {r1};
  z = {r2};
}

inline Int4 load(const std::uint32_t* p) { return {_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))}; }
inline Int4 zero_int() { return {_mm_setzero_si128()}; }
inline Int4 splat(std::int32_t x) { return {_mm_set1_epi32(x)}; }
inline Int4 operator+(Int4 a, Int4 b) { return {_mm_add_epi32(a.v, b.v)}; }
inline Float4 to_float(Int4 a) { return {_mm_cvtepi32_ps(a.v)}; }
// Lane masks (all bits set where true) and selection.
inline Float4 positive(Int4 a) { return {_mm_castsi128_ps(_mm_cmpgt_epi32(a.v, _mm_setzero_si128()))}; }
inline Float4 less(Float4 a, Float4 b) { return {_mm_cmplt_ps(a.v, b.v)}; }
inline Float4 operator&(Float4 a, Float4 b) { return {_mm_and_ps(a.v, b.v)}; }
inline Float4 select(Float4 mask, Float4 yes, Float4 no) {
  return {_mm_or_ps(_mm_and_ps(mask.v, yes.v), _mm_andnot_ps(mask.v, no.v))};
}
inline Int4 select(Float4 mask, Int4 yes, Int4 no) {
  const __m128i m = _mm_castps_si128(mask.v);
  return {_mm_or_si128(_mm_and_si128(m, yes.v), _mm_andnot_si128(m, no.v))};
}
inline void store(std::int32_t* p, Int4 a) { _mm_storeu_si128(reinterpret_cast<__m128i*>(p), a.v); }
inline Int4 load(const std::int32_t* p) { return {_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))}; }
inline Float4 mask(bool b) { return {_mm_castsi128_ps(_mm_set1_epi32(-static_cast<int>(b)))}; }
inline Float4 as_float(Int4 mask) { return {_mm_castsi128_ps(mask.v)}; }
// Bit i set when lane i of the mask is true.
inline int bits(Float4 mask) { return _mm_movemask_ps(mask.v); }
inline Int4 operator-(Int4 a, Int4 b) { return {_mm_sub_epi32(a.v, b.v)}; }
// Integer lane masks: -1 where true, 0 where false.
inline Int4 less(Int4 a, Int4 b) { return {_mm_cmplt_epi32(a.v, b.v)}; }
inline Int4 less_equal(Int4 a, Int4 b) { return {_mm_xor_si128(_mm_cmpgt_epi32(a.v, b.v), _mm_set1_epi32(-1))}; }

#else

struct Float4 {
  float v[4];
};
struct Int4 {
  std::int32_t v[4];
};

template <class R, class A, class B, class Op>
inline R lanes(A a, B b, Op op) {
  return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1]), op(a.v[2], b.v[2]), op(a.v[3], b.v[3])}};
}
inline Float4 load3(const float* p) { return {{p[0], p[1], p[2], 0.0f}}; }
inline void store(float* p, Float4 a) {
  for (int i = 0; i < 4; ++i) p[i] = a.v[i];
}
inline Float4 splat3(float x) { return {{x, x, x, 0.0f}}; }
inline Float4 set3(float x, float y, float z) { return {{x, y, z, 0.0f}}; }
inline Float4 operator+(Float4 a, Float4 b) { return lanes<Float4>(a, b, [](float x, float y) { return x + y; }); }
inline Float4 operator-(Float4 a, Float4 b) { return lanes<Float4>(a, b, [](float x, float y) { return x - y; }); }
inline Float4 operator*(Float4 a, Float4 b) { return lanes<Float4>(a, b, [](float x, float y) { return x * y; }); }
inline Float4 operator/(Float4 a, Float4 b) { return lanes<Float4>(a, b, [](float x, float y) { return x / y; }); }
// Same operand order as SSE's minps/maxps: the second operand when the comparison fails.
inline Float4 min(Float4 a, Float4 b) { return lanes<Float4>(a, b, [](float x, float y) { return x < y ? x : y; }); }
inline Float4 max(Float4 a, Float4 b) { return lanes<Float4>(a, b, [](float x, float y) { return x > y ? x : y; }); }
inline void truncate(Float4 a, std::int32_t out[4]) {
  for (int i = 0; i < 4; ++i) out[i] = static_cast<std::int32_t>(a.v[i]);
}
inline void transpose3(Float4 a, Float4 b, Float4 c, Float4& x, Float4& y, Float4& z) {
  x = {{a.v[0], b.v[0], c.v[0], 0.0f}};
  y = {{a.v[1], b.v[1], c.v[1], 0.0f}};
  z = {{a.v[2], b.v[2], c.v[2], 0.0f}};
}

inline Int4 load(const std::uint32_t* p) {
  return {{static_cast<std::int32_t>(p[0]), static_cast<std::int32_t>(p[1]),
           static_cast<std::int32_t>(p[2]), static_cast<std::int32_t>(p[3])}};
}
inline Int4 zero_int() { return {{0, 0, 0, 0}}; }
inline Int4 splat(std::int32_t x) { return {{x, x, x, x}}; }
inline Int4 operator+(Int4 a, Int4 b) { return lanes<Int4>(a, b, [](std::int32_t x, std::int32_t y) { return x + y; }); }
inline Float4 to_float(Int4 a) {
  Float4 r;
  for (int i = 0; i < 4; ++i) r.v[i] = static_cast<float>(a.v[i]);
  return r;
}
// Lane masks: 1.0f where true (only select and & read them).
inline Float4 positive(Int4 a) {
  Float4 r;
  for (int i = 0; i < 4; ++i) r.v[i] = a.v[i] > 0 ? 1.0f : 0.0f;
  return r;
}
inline Float4 less(Float4 a, Float4 b) { return lanes<Float4>(a, b, [](float x, float y) { return x < y ? 1.0f : 0.0f; }); }
inline Float4 operator&(Float4 a, Float4 b) { return lanes<Float4>(a, b, [](float x, float y) { return x != 0.0f && y != 0.0f ? 1.0f : 0.0f; }); }
inline Float4 select(Float4 mask, Float4 yes, Float4 no) {
  Float4 r;
  for (int i = 0; i < 4; ++i) r.v[i] = mask.v[i] != 0.0f ? yes.v[i] : no.v[i];
  return r;
}
inline Int4 select(Float4 mask, Int4 yes, Int4 no) {
  Int4 r;
  for (int i = 0; i < 4; ++i) r.v[i] = mask.v[i] != 0.0f ? yes.v[i] : no.v[i];
  return r;
}
inline void store(std::int32_t* p, Int4 a) {
  for (int i = 0; i < 4; ++i) p[i] = a.v[i];
}
inline Int4 load(const std::int32_t* p) { return {{p[0], p[1], p[2], p[3]}}; }
inline Float4 mask(bool b) { const float m = b ? 1.0f : 0.0f; return {{m, m, m, m}}; }
inline Float4 as_float(Int4 mask) {
  Float4 r;
  for (int i = 0; i < 4; ++i) r.v[i] = mask.v[i] != 0 ? 1.0f : 0.0f;
  return r;
}
inline int bits(Float4 mask) {
  int b = 0;
  for (int i = 0; i < 4; ++i) b |= (mask.v[i] != 0.0f) << i;
  return b;
}
inline Int4 operator-(Int4 a, Int4 b) { return lanes<Int4>(a, b, [](std::int32_t x, std::int32_t y) { return x - y; }); }
inline Int4 less(Int4 a, Int4 b) { return lanes<Int4>(a, b, [](std::int32_t x, std::int32_t y) { return x < y ? -1 : 0; }); }
inline Int4 less_equal(Int4 a, Int4 b) { return lanes<Int4>(a, b, [](std::int32_t x, std::int32_t y) { return x <= y ? -1 : 0; }); }

#endif

inline float lane(Float4 a, int i) {
  alignas(16) float f[4];
  store(f, a);
  return f[i];
}

// Surface areas 2 (ex ey + ey ez + ez ex) of three boxes, one per lane, from their extents.
inline Float4 area(Float4 ex, Float4 ey, Float4 ez) {
  return splat3(2.0f) * (ex * ey + ey * ez + ez * ex);
}
// Surface area of one box [lo, hi], as Aabb::area computes it (for a non-empty box).
inline float area(Float4 lo, Float4 hi) {
  alignas(16) float e[4];
  store(e, hi - lo);
  return 2.0f * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]);
}

}  // namespace hrpp::simd
