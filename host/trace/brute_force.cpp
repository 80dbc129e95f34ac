#include "trace/brute_force.h"

#include "scene/load_scene.h"
#include "trace/cpu_traversal.h"
#include "trace/watertight.h"

namespace hrpp {

gpu::Hit brute_force_closest(const Scene& scene, const gpu::Ray& ray) {
  const RaySetup r = setup_ray(ray);
  gpu::Hit best = kMiss;
  if (!r.valid) return best;
  float tmax = ray.tmax;
  for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
    const Triangle& t = scene.triangles[i];
    TriangleHit h;
    // Ids ascend, so a later triangle at equal t never wins: the tie rule holds by order.
    // Degenerate triangles are never hit (they are not in the BVH either).
    if (intersect_triangle(r, t.v0, t.v1, t.v2, tmax, &h) && (best.prim < 0 || h.t < best.t) &&
        !is_degenerate(t)) {
      best = {static_cast<int>(i), h.t, h.u, h.v};
      tmax = h.t;
    }
  }
  return best;
}

bool brute_force_any(const Scene& scene, const gpu::Ray& ray) {
  const RaySetup r = setup_ray(ray);
  if (!r.valid) return false;
  for (const Triangle& t : scene.triangles) {
    TriangleHit h;
    if (intersect_triangle(r, t.v0, t.v1, t.v2, ray.tmax, &h) && !is_degenerate(t)) return true;
  }
  return false;
}

}  // namespace hrpp
