#include "harness/validation.h"

#include <cmath>
#include <cstdio>

namespace hrpp {

Validation validate(std::span<const gpu::Ray> rays, std::span<const gpu::Hit> ref,
                    std::span<const gpu::Hit> test, std::span<const std::size_t> subset,
                    QueryKind kind, float scene_diagonal) {
  Validation v;
  for (const std::size_t i : subset) {
    const gpu::Hit& r = ref[i];
    const gpu::Hit& t = test[i];
    ++v.checked;
    bool ok;
    if (kind == QueryKind::kAny) {
      ok = (r.prim >= 0) == (t.prim >= 0);
      if (ok) ++v.exact;
    } else if (r.prim < 0 || t.prim < 0) {
      ok = r.prim == t.prim;
      if (ok) ++v.exact;
    } else {
      const float tol = 1e-5f * std::fabs(r.t) + 1e-7f * scene_diagonal;
      const bool same_t = std::fabs(r.t - t.t) <= tol;
      ok = same_t;
      if (same_t && r.prim != t.prim) ++v.ties;
      if (r.prim == t.prim && r.t == t.t) ++v.exact;
    }
    if (!ok) {
      ++v.mismatches;
      if (v.examples.size() < 5) {
        char buf[320];
        const gpu::Ray& ray = rays[i];
        std::snprintf(buf, sizeof buf,
                      "ray %zu o=(%.9g %.9g %.9g) d=(%.9g %.9g %.9g) [%g, %g]: reference prim %d "
                      "t %.9g, this tracer prim %d t %.9g",
                      i, ray.origin.x, ray.origin.y, ray.origin.z, ray.dir.x, ray.dir.y, ray.dir.z,
                      ray.tmin, ray.tmax, r.prim, r.t, t.prim, t.t);
        v.examples.emplace_back(buf);
      }
    }
  }
  return v;
}

std::vector<std::size_t> spread_subset(std::size_t n, std::size_t want) {
  if (want == 0 || want > n) want = n;
  std::vector<std::size_t> subset;
  subset.reserve(want);
  for (std::size_t k = 0; k < want; ++k) subset.push_back(k * n / want);
  return subset;
}

}  // namespace hrpp
