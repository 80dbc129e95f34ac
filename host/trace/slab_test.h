// Conservative ray–box slab test (Ize 2013, "Robust BVH Ray Traversal"; pbrt-v4's
// Bounds3::IntersectP): the far distance is enlarged by 1 + 2γ(3) so rounding never culls a box
// the exact ray meets. Inclusive at both ends: a box touched exactly at tmax is still entered,
// which the tie rule (equal t, lower id wins) needs.
#pragma once

#include <algorithm>

#include "trace/ray_setup.h"

namespace hrpp {

// γ(n) = n·ε / (1 − n·ε), ε = 2^-24 (float unit roundoff).
constexpr float kSlabFarScale = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

// True when the ray meets the box lo..hi within [tmin, tmax]; *t_enter = where it enters.
inline bool slab_test(const RaySetup& r, const glm::vec3& lo, const glm::vec3& hi, float tmax,
                      float* t_enter) {
  const glm::vec3 t0 = (lo - r.origin) * r.inv_dir;
  const glm::vec3 t1 = (hi - r.origin) * r.inv_dir;
  const float tnear = std::max(std::max(std::min(t0.x, t1.x), std::min(t0.y, t1.y)),
                               std::max(std::min(t0.z, t1.z), r.tmin));
  const float tfar = std::min(std::min(std::max(t0.x, t1.x), std::max(t0.y, t1.y)),
                              std::min(std::max(t0.z, t1.z), tmax)) * kSlabFarScale;
  *t_enter = tnear;
  return tnear <= tfar;
}

}  // namespace hrpp
