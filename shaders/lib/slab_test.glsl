// Conservative ray–box slab test (Ize 2013, "Robust BVH Ray Traversal"): the GLSL twin of
// host/trace/slab_test.h. Far distance × (1 + 2γ(3)); inclusive at both ends.
#ifndef HRPP_SLAB_TEST_GLSL
#define HRPP_SLAB_TEST_GLSL

#include "ray_setup.glsl"

bool slab_test(RaySetup r, vec3 lo, vec3 hi, float tmax, out float t_enter) {
  const float far_scale = uintBitsToFloat(HRPP_SLAB_FAR_SCALE_BITS);
  precise vec3 t0 = (lo - r.origin) * r.inv_dir;
  precise vec3 t1 = (hi - r.origin) * r.inv_dir;
  // No NaN can occur here (finite reciprocals), so min/max match std::min/std::max up to the
  // sign of a zero, which no comparison below sees.
  const float tnear = max(max(min(t0.x, t1.x), min(t0.y, t1.y)), max(min(t0.z, t1.z), r.tmin));
  precise float tfar =
      min(min(max(t0.x, t1.x), max(t0.y, t1.y)), min(max(t0.z, t1.z), tmax)) * far_scale;
  t_enter = tnear;
  return tnear <= tfar;
}

#endif  // HRPP_SLAB_TEST_GLSL
