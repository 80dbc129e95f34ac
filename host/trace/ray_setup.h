// Per-ray constants shared by the slab and triangle tests. The GLSL kernels compute the same
// values in the same order (shaders/lib/), so CPU and GPU agree.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "gpu_types.h"

namespace hrpp {

// Finite reciprocal: a zero (or vanishing) direction component becomes ±2^80 with the zero's
// sign instead of ±Inf, so (plane − origin) × reciprocal is never 0 × Inf = NaN for an origin
// lying on a slab plane (Ize 2013, "Robust BVH Ray Traversal").
// The slab test (slab_test.h) takes |reciprocal| ≥ kParallelReciprocal as "parallel to the axis".
inline constexpr float kParallelReciprocal = 0x1p80f;

inline float safe_reciprocal(float d) {
  constexpr float kTiny = 0x1p-80f;
  return std::fabs(d) < kTiny ? std::copysign(kParallelReciprocal, d) : 1.0f / d;
}

struct RaySetup {
  glm::vec3 origin;
  glm::vec3 inv_dir;   // safe reciprocals
  float tmin, tmax;
  // Watertight test (Woop, Benthin, Wald 2013): kz is the dominant axis of the direction, kx
  // and ky the others (swapped when d[kz] < 0 to keep the winding); shear constants S.
  int kx, ky, kz;
  float sx, sy, sz;
  bool valid;          // false for NaN/Inf origin or direction, or a zero direction: never hits
};

inline bool is_finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

inline RaySetup setup_ray(const gpu::Ray& ray) {
  RaySetup r{};
  r.origin = ray.origin;
  r.tmin = ray.tmin;
  r.tmax = ray.tmax;
  const glm::vec3 d = ray.dir;
  r.valid = is_finite(ray.origin) && is_finite(d) &&
            (d.x != 0.0f || d.y != 0.0f || d.z != 0.0f) && !std::isnan(ray.tmin) &&
            !std::isnan(ray.tmax);
  r.inv_dir = {safe_reciprocal(d.x), safe_reciprocal(d.y), safe_reciprocal(d.z)};
  const glm::vec3 a = glm::abs(d);
  r.kz = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
  r.kx = (r.kz + 1) % 3;
  r.ky = (r.kx + 1) % 3;
  if (d[r.kz] < 0.0f) {
    const int k = r.kx;
    r.kx = r.ky;
    r.ky = k;
  }
  r.sx = d[r.kx] / d[r.kz];
  r.sy = d[r.ky] / d[r.kz];
  r.sz = 1.0f / d[r.kz];
  return r;
}

}  // namespace hrpp
