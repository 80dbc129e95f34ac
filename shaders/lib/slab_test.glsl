// Conservative ray–box slab test (Ize 2013, "Robust BVH Ray Traversal"): the GLSL twin of
// host/trace/slab_test.h. Far distance × (1 + 2γ(3)); inclusive at both ends. On an axis the
// ray parallels (|reciprocal| ≥ 2^80) an origin in the closed slab puts no limit on t (a ray in
// a box face's plane enters the box); one outside bounds t only from the box's side.
#ifndef HRPP_SLAB_TEST_GLSL
#define HRPP_SLAB_TEST_GLSL

#include "ray_setup.glsl"

// [t_near, t_far] of one axis: where the ray is between the planes lo and hi.
void slab_axis(float lo, float hi, float origin, float inv_dir, out float t_near,
               out float t_far) {
  const float inf = uintBitsToFloat(0x7F800000u);
  precise float t0 = (lo - origin) * inv_dir;
  precise float t1 = (hi - origin) * inv_dir;
  // No NaN can occur here (finite reciprocals), so min/max match std::min/std::max up to the
  // sign of a zero, which no comparison in slab_test sees.
  t_near = min(t0, t1);
  t_far = max(t0, t1);
  if (abs(inv_dir) < uintBitsToFloat(HRPP_TWO_POW_80_BITS)) return;
  const bool in_slab = lo <= origin && origin <= hi;
  if (in_slab || t_near > 0.0) t_far = inf;   // t0, t1 > 0 outside: heading towards it
  if (in_slab || t_far < 0.0) t_near = -inf;  // t0, t1 < 0 outside: heading away
}

bool slab_test(RaySetup r, vec3 lo, vec3 hi, float tmax, out float t_enter) {
  const float far_scale = uintBitsToFloat(HRPP_SLAB_FAR_SCALE_BITS);
  vec3 t_near, t_far;
  for (int i = 0; i < 3; ++i)
    slab_axis(lo[i], hi[i], r.origin[i], r.inv_dir[i], t_near[i], t_far[i]);
  const float tnear = max(max(t_near.x, t_near.y), max(t_near.z, r.tmin));
  precise float tfar = min(min(t_far.x, t_far.y), min(t_far.z, tmax)) * far_scale;
  t_enter = tnear;
  return tnear <= tfar;
}

#endif  // HRPP_SLAB_TEST_GLSL
