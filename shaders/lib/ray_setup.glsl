// Per-ray constants of the slab and triangle tests: the GLSL twin of host/trace/ray_setup.h,
// the same operations in the same order so CPU and GPU agree bit for bit.
#ifndef HRPP_RAY_SETUP_GLSL
#define HRPP_RAY_SETUP_GLSL

#include "ieee_math.glsl"

struct RaySetup {
  vec3 origin;
  vec3 inv_dir;  // safe reciprocals
  float tmin;
  float tmax;
  int kx, ky, kz;  // watertight test: dominant axis kz, kx/ky swapped when d[kz] < 0
  float sx, sy, sz;
  bool valid;  // false for NaN/Inf origin or direction, or a zero direction: never hits
};

bool hrpp_is_finite(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

// Finite reciprocal (Ize 2013): |d| < 2^-80 becomes ±2^80 with d's sign, never ±Inf.
float safe_reciprocal(float d) {
  const float tiny = uintBitsToFloat(HRPP_TWO_POW_M80_BITS);
  const uint huge = HRPP_TWO_POW_80_BITS;
  precise float r = ieee_div(1.0, d);
  return abs(d) < tiny ? uintBitsToFloat(huge | (floatBitsToUint(d) & 0x80000000u)) : r;
}

RaySetup setup_ray(Ray ray) {
  RaySetup r;
  r.origin = ray.origin;
  r.tmin = ray.tmin;
  r.tmax = ray.tmax;
  const vec3 d = ray.dir;
  r.valid = hrpp_is_finite(ray.origin) && hrpp_is_finite(d) && any(notEqual(d, vec3(0.0))) &&
            !isnan(ray.tmin) && !isnan(ray.tmax);
  r.inv_dir = vec3(safe_reciprocal(d.x), safe_reciprocal(d.y), safe_reciprocal(d.z));
  const vec3 a = abs(d);
  r.kz = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
  r.kx = (r.kz + 1) % 3;
  r.ky = (r.kx + 1) % 3;
  if (d[r.kz] < 0.0) {
    const int k = r.kx;
    r.kx = r.ky;
    r.ky = k;
  }
  precise float sx = ieee_div(d[r.kx], d[r.kz]);
  precise float sy = ieee_div(d[r.ky], d[r.kz]);
  precise float sz = ieee_div(1.0, d[r.kz]);
  r.sx = sx;
  r.sy = sy;
  r.sz = sz;
  return r;
}

#endif  // HRPP_RAY_SETUP_GLSL
