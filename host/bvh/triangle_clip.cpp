#include "bvh/triangle_clip.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

namespace hrpp {
namespace {

// A triangle chopped at two planes has at most 5 vertices; each chop adds at most one.
constexpr int kMaxVertices = 8;

// Relative error bound of a point on an edge computed in double (a + s (b - a), a few roundings
// of 2^-53): far below float precision, so widening by it costs nothing measurable.
constexpr double kEdgeError = 0x1p-48;

struct Polygon {
  glm::dvec3 v[kMaxVertices];
  glm::dvec3 lo[kMaxVertices], hi[kMaxVertices];  // each vertex's error box
  int n = 0;
  void add(const glm::dvec3& p, const glm::dvec3& l, const glm::dvec3& h) {
    v[n] = p;
    lo[n] = l;
    hi[n] = h;
    ++n;
  }
};

// The point of edge i -> j of `in` on the plane p[axis] = plane, with its error box: its rounding
// error and its end points' errors, within the end points' error boxes, exactly on the plane on
// `axis`. The end points lie on either side of the plane, so they differ on `axis` (chops are
// all on one axis: earlier crossings are exact there) and the division is defined.
void add_crossing(Polygon& out, const Polygon& in, int i, int j, int axis, double plane) {
  const glm::dvec3 &a = in.v[i], &b = in.v[j];
  const double s = (plane - a[axis]) / (b[axis] - a[axis]);
  glm::dvec3 p = a + s * (b - a), lo, hi;
  for (int c = 0; c < 3; ++c) {
    const double ends = std::max({a[c] - in.lo[i][c], in.hi[i][c] - a[c], b[c] - in.lo[j][c],
                                  in.hi[j][c] - b[c]});
    const double e = kEdgeError * (std::abs(a[c]) + std::abs(b[c])) + ends;
    const double emin = std::min(in.lo[i][c], in.lo[j][c]);
    const double emax = std::max(in.hi[i][c], in.hi[j][c]);
    lo[c] = std::clamp(p[c] - e, emin, emax);
    hi[c] = std::clamp(p[c] + e, emin, emax);
  }
  p[axis] = lo[axis] = hi[axis] = plane;
  out.add(p, lo, hi);
}

// Keeps the part of `in` on the side keep_below ? p[axis] <= plane : p[axis] >= plane.
Polygon chop(const Polygon& in, int axis, double plane, bool keep_below) {
  Polygon out;
  auto inside = [&](const glm::dvec3& p) { return keep_below ? p[axis] <= plane : p[axis] >= plane; };
  for (int i = 0; i < in.n; ++i) {
    const int j = (i + 1) % in.n;
    const bool a_in = inside(in.v[i]), b_in = inside(in.v[j]);
    if (a_in) out.add(in.v[i], in.lo[i], in.hi[i]);
    if (a_in != b_in) add_crossing(out, in, i, j, axis, plane);
  }
  return out;
}

// The largest float <= x, and the smallest float >= x.
float round_down(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
float round_up(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

}  // namespace

Aabb clipped_box(const Triangle& t, int axis, float lo, float hi) {
  Polygon p;
  for (const glm::vec3& v : {t.v0, t.v1, t.v2}) p.add(glm::dvec3(v), glm::dvec3(v), glm::dvec3(v));
  if (lo > -std::numeric_limits<float>::infinity()) p = chop(p, axis, lo, false);
  if (hi < std::numeric_limits<float>::infinity()) p = chop(p, axis, hi, true);
  Aabb box;
  for (int i = 0; i < p.n; ++i)
    for (int c = 0; c < 3; ++c) {
      box.lo[c] = std::min(box.lo[c], round_down(p.lo[i][c]));
      box.hi[c] = std::max(box.hi[c], round_up(p.hi[i][c]));
    }
  return box;
}

}  // namespace hrpp
