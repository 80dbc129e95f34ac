#include "bvh/triangle_clip.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace hrpp {
namespace {

// Relative error bound of a point on an edge computed in double (a + s (b - a), a few roundings
// of 2^-53 each): far below float precision, so widening by it costs no tightness.
constexpr double kEdgeError = 0x1p-48;

// The float next to finite f towards -infinity (below) or +infinity (above).
float next_down(float f) {
  if (f == 0.0f) return -std::numeric_limits<float>::denorm_min();
  const auto bits = std::bit_cast<std::uint32_t>(f);
  return std::bit_cast<float>(f > 0.0f ? bits - 1 : bits + 1);
}
float next_up(float f) { return -next_down(-f); }

// The largest float <= x, and the smallest float >= x (x within the float range).
float round_down(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) > x ? next_down(f) : f;
}
float round_up(double x) {
  const auto f = static_cast<float>(x);
  return static_cast<double>(f) < x ? next_up(f) : f;
}

// Grows both sides by the point where edge (a, b) crosses p[axis] = plane (a and b strictly on
// either side, so they differ on `axis`), with its error bound, within the edge's box.
void grow_by_crossing(ChoppedBoxes& out, const glm::vec3& a, const glm::vec3& b, int axis,
                      float plane) {
  const glm::dvec3 da(a), db(b);
  const double s = (static_cast<double>(plane) - da[axis]) / (db[axis] - da[axis]);
  const glm::dvec3 p = da + s * (db - da);
  glm::vec3 lo, hi;
  for (int c = 0; c < 3; ++c) {
    const double e = kEdgeError * (std::abs(da[c]) + std::abs(db[c]));
    const double emin = std::min(da[c], db[c]), emax = std::max(da[c], db[c]);
    lo[c] = round_down(std::clamp(p[c] - e, emin, emax));
    hi[c] = round_up(std::clamp(p[c] + e, emin, emax));
  }
  lo[axis] = hi[axis] = plane;
  for (Aabb* box : {&out.below, &out.above}) {
    box->grow(lo);
    box->grow(hi);
  }
}

}  // namespace

ChoppedBoxes chop_triangle(const Triangle& t, int axis, float plane) {
  ChoppedBoxes out;
  const glm::vec3 v[3] = {t.v0, t.v1, t.v2};
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 &a = v[i], &b = v[(i + 1) % 3];
    if (a[axis] <= plane) out.below.grow(a);
    if (a[axis] >= plane) out.above.grow(a);
    if ((a[axis] < plane && plane < b[axis]) || (b[axis] < plane && plane < a[axis])) {
      grow_by_crossing(out, a, b, axis, plane);
    }
  }
  return out;
}

}  // namespace hrpp
