#include "double_reference.h"

#include <cmath>
#include <sstream>
#include <string>

#include <glm/glm.hpp>

#include "scene/load_scene.h"

namespace hrpp::test {
namespace {

constexpr double kEps = 0x1p-24;  // float unit roundoff

std::string describe(const gpu::Ray& r) {
  std::ostringstream s;
  s.precision(9);
  s << "ray o=(" << r.origin.x << "," << r.origin.y << "," << r.origin.z << ") d=(" << r.dir.x
    << "," << r.dir.y << "," << r.dir.z << ") t=[" << r.tmin << "," << r.tmax << "]";
  return s.str();
}

}  // namespace

OracleHit oracle_triangle(const Triangle& tri, const gpu::Ray& ray) {
  OracleHit out;
  if (is_degenerate(tri)) return out;  // never in the BVH: never hit
  const glm::dvec3 o(ray.origin), d(ray.dir);
  if (!std::isfinite(o.x + o.y + o.z + d.x + d.y + d.z) || (d.x == 0 && d.y == 0 && d.z == 0) ||
      std::isnan(ray.tmin) || std::isnan(ray.tmax))
    return out;  // invalid rays miss (cpu_traversal.h)
  // The float test's axis choice (ray_setup.h), in double.
  const glm::vec3 af = glm::abs(ray.dir);
  const int kz = (af.x >= af.y && af.x >= af.z) ? 0 : (af.y >= af.z ? 1 : 2);
  int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
  if (d[kz] < 0.0) std::swap(kx, ky);
  const double sx = d[kx] / d[kz], sy = d[ky] / d[kz], sz = 1.0 / d[kz];
  const glm::dvec3 a = glm::dvec3(tri.v0) - o, b = glm::dvec3(tri.v1) - o,
                   c = glm::dvec3(tri.v2) - o;
  auto shear = [&](const glm::dvec3& p, double& x, double& y) {
    x = p[kx] - sx * p[kz];
    y = p[ky] - sy * p[kz];
  };
  double ax, ay, bx, by, cx, cy;
  shear(a, ax, ay);
  shear(b, bx, by);
  shear(c, cx, cy);
  const double U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
  const double ma = std::abs(a.x) + std::abs(a.y) + std::abs(a.z);
  const double mb = std::abs(b.x) + std::abs(b.y) + std::abs(b.z);
  const double mc = std::abs(c.x) + std::abs(c.y) + std::abs(c.z);
  const double tu = 32 * kEps * mb * mc, tv = 32 * kEps * ma * mc, tw = 32 * kEps * ma * mb;
  const bool inside = (U > tu && V > tv && W > tw) || (U < -tu && V < -tv && W < -tw);
  const bool outside = (U > tu || V > tv || W > tw) && (U < -tu || V < -tv || W < -tw);
  const double det = U + V + W;
  const double det_tol = tu + tv + tw;
  if (std::abs(det) <= det_tol) {  // edge-on or nearly: the float det may be 0 or anything
    out.verdict = outside ? Verdict::kMiss : Verdict::kEither;
    return out;
  }
  const double az = sz * a[kz], bz = sz * b[kz], cz = sz * c[kz];
  const double num = U * az + V * bz + W * cz;
  out.t = num / det;
  const double num_tol = tu * std::abs(az) + tv * std::abs(bz) + tw * std::abs(cz) +
                         8 * kEps * (std::abs(U * az) + std::abs(V * bz) + std::abs(W * cz));
  const double adet = std::abs(det);
  out.t_tol = num_tol / (adet - det_tol) + std::abs(out.t) * det_tol / (adet - det_tol) +
              8 * kEps * std::abs(out.t);
  const double lo = ray.tmin, hi = ray.tmax;
  const bool in_range = out.t - out.t_tol >= lo && out.t + out.t_tol <= hi;
  const bool out_of_range = out.t + out.t_tol < lo || out.t - out.t_tol > hi;
  if (outside || out_of_range)
    out.verdict = Verdict::kMiss;
  else if (inside && in_range)
    out.verdict = Verdict::kHit;
  else
    out.verdict = Verdict::kEither;
  return out;
}

std::string judge_closest(const Scene& scene, const gpu::Ray& ray, const gpu::Hit& hit) {
  std::vector<OracleHit> all(scene.triangles.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = oracle_triangle(scene.triangles[i], ray);
  if (hit.prim < 0) {
    for (std::size_t i = 0; i < all.size(); ++i)
      if (all[i].verdict == Verdict::kHit)
        return describe(ray) + ": missed, but triangle " + std::to_string(i) +
               " is certainly hit at t=" + std::to_string(all[i].t);
    return "";
  }
  if (static_cast<std::size_t>(hit.prim) >= all.size()) return describe(ray) + ": bad prim";
  const OracleHit& h = all[hit.prim];
  std::ostringstream why;
  why.precision(9);
  if (h.verdict == Verdict::kMiss) {
    why << describe(ray) << ": hit triangle " << hit.prim << " at t=" << hit.t
        << ", which it certainly misses (exact t=" << h.t << ")";
    return why.str();
  }
  if (std::isfinite(h.t) && std::abs(static_cast<double>(hit.t) - h.t) > h.t_tol) {
    why << describe(ray) << ": triangle " << hit.prim << " t=" << hit.t << ", exact " << h.t
        << " ± " << h.t_tol;
    return why.str();
  }
  const double far = std::isfinite(h.t) ? h.t - h.t_tol : static_cast<double>(hit.t);
  for (std::size_t i = 0; i < all.size(); ++i)
    if (all[i].verdict == Verdict::kHit && all[i].t + all[i].t_tol < far) {
      why << describe(ray) << ": hit triangle " << hit.prim << " at t=" << hit.t << " but triangle "
          << i << " is certainly hit closer, t=" << all[i].t;
      return why.str();
    }
  return "";
}

std::string judge_any(const Scene& scene, const gpu::Ray& ray, bool occluded) {
  bool certain = false, possible = false;
  for (const Triangle& t : scene.triangles) {
    const Verdict v = oracle_triangle(t, ray).verdict;
    certain = certain || v == Verdict::kHit;
    possible = possible || v != Verdict::kMiss;
  }
  if (occluded && !possible) return describe(ray) + ": occluded, but no triangle can be hit";
  if (!occluded && certain) return describe(ray) + ": free, but a triangle is certainly hit";
  return "";
}

}  // namespace hrpp::test
