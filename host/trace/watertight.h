// Watertight ray–triangle test (Woop, Benthin, Wald 2013, "Watertight Ray/Triangle
// Intersection", JCGT 2(1)). Edge functions are evaluated in a sheared space where the ray is
// the +z axis; when one is exactly zero it is recomputed in double, so a ray through a shared
// edge or vertex hits exactly one of the triangles meeting there. Both faces are hit.
#pragma once

#include "trace/ray_setup.h"

namespace hrpp {

struct TriangleHit {
  float t, u, v;  // u, v: barycentric weights of v1 and v2
};

inline bool intersect_triangle(const RaySetup& r, const glm::vec3& v0, const glm::vec3& v1,
                               const glm::vec3& v2, float tmax, TriangleHit* hit) {
  const glm::vec3 a = v0 - r.origin;
  const glm::vec3 b = v1 - r.origin;
  const glm::vec3 c = v2 - r.origin;
  const float ax = a[r.kx] - r.sx * a[r.kz];
  const float ay = a[r.ky] - r.sy * a[r.kz];
  const float bx = b[r.kx] - r.sx * b[r.kz];
  const float by = b[r.ky] - r.sy * b[r.kz];
  const float cx = c[r.kx] - r.sx * c[r.kz];
  const float cy = c[r.ky] - r.sy * c[r.kz];
  float u = cx * by - cy * bx;
  float v = ax * cy - ay * cx;
  float w = bx * ay - by * ax;
  if (u == 0.0f || v == 0.0f || w == 0.0f) {
    u = static_cast<float>(static_cast<double>(cx) * by - static_cast<double>(cy) * bx);
    v = static_cast<float>(static_cast<double>(ax) * cy - static_cast<double>(ay) * cx);
    w = static_cast<float>(static_cast<double>(bx) * ay - static_cast<double>(by) * ax);
  }
  if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
  const float det = u + v + w;
  if (det == 0.0f) return false;
  const float az = r.sz * a[r.kz];
  const float bz = r.sz * b[r.kz];
  const float cz = r.sz * c[r.kz];
  // t from the normalised barycentrics (in [0, 1] on a hit), not (u·az + v·bz + w·cz)/det: the
  // edge functions grow with the square of the triangle's size, and that sum overflows to +Inf
  // once |edge function × z| passes FLT_MAX (a triangle 1e17 across at distance 1e4).
  const float inv_det = 1.0f / det;
  const float b0 = u * inv_det;
  const float b1 = v * inv_det;
  const float b2 = w * inv_det;
  const float t = b0 * az + b1 * bz + b2 * cz;
  if (!(t >= r.tmin && t <= tmax)) return false;
  hit->t = t;
  hit->u = b1;
  hit->v = b2;
  return true;
}

}  // namespace hrpp
