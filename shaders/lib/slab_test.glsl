// Conservative ray–box slab test (Ize 2013, "Robust BVH Ray Traversal"): the GLSL twin of
// host/trace/slab_test.h. Far distance × (1 + 2γ(3)); inclusive at both ends. On an axis the
// ray parallels (|reciprocal| ≥ 2^80) the slab opens on each side that reaches t = 0: an origin
// in the closed slab puts no limit on t (a ray in a box face's plane enters the box), one outside
// bounds t only from the box's side.
#ifndef HRPP_SLAB_TEST_GLSL
#define HRPP_SLAB_TEST_GLSL

#include "ray_setup.glsl"

bool slab_test(RaySetup r, vec3 lo, vec3 hi, float tmax, out float t_enter) {
  const float far_scale = uintBitsToFloat(HRPP_SLAB_FAR_SCALE_BITS);
  const vec3 inf = vec3(uintBitsToFloat(0x7F800000u));
  precise vec3 t0 = (lo - r.origin) * r.inv_dir;
  precise vec3 t1 = (hi - r.origin) * r.inv_dir;
  // No NaN can occur here (finite reciprocals), so min/max match std::min/std::max up to the
  // sign of a zero, which no comparison below sees.
  vec3 t_near = min(t0, t1);
  vec3 t_far = max(t0, t1);
  // Parallel axes: t_near ≤ 0 becomes −∞ and t_far ≥ 0 +∞ (open_parallel_axis in the C++ twin).
  // The thresholds are 0 there and ∓∞ elsewhere, where they change nothing (∓∞ stays ∓∞).
  const vec3 parallel_reciprocal = vec3(uintBitsToFloat(HRPP_TWO_POW_80_BITS));
  const bvec3 parallel = greaterThanEqual(abs(r.inv_dir), parallel_reciprocal);
  t_near = mix(t_near, -inf, lessThanEqual(t_near, mix(-inf, vec3(0.0), parallel)));
  t_far = mix(t_far, inf, greaterThanEqual(t_far, mix(inf, vec3(0.0), parallel)));
  const float tnear = max(max(t_near.x, t_near.y), max(t_near.z, r.tmin));
  precise float tfar = min(min(t_far.x, t_far.y), min(t_far.z, tmax)) * far_scale;
  t_enter = tnear;
  return tnear <= tfar;
}

#endif  // HRPP_SLAB_TEST_GLSL
