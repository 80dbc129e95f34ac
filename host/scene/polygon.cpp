// triangulate_polygon(): convexity on the Newell normal, then a fan or ear clipping.
#include "scene/polygon.h"

#include <cmath>

namespace hrpp {
namespace {

glm::vec3 newell_normal(const std::vector<glm::vec3>& c) {
  glm::vec3 n(0.0f);
  for (std::size_t i = 0; i < c.size(); ++i) {
    const glm::vec3& a = c[i];
    const glm::vec3& b = c[(i + 1) % c.size()];
    n += glm::vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  return n;
}

// The corners on the polygon's plane (the axis the normal leans on most dropped), turned so
// that the polygon runs counter-clockwise there.
std::vector<glm::vec2> projected(const std::vector<glm::vec3>& c, const glm::vec3& n) {
  const glm::vec3 a = glm::abs(n);
  const int drop = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  const bool flip = n[drop] < 0.0f;
  std::vector<glm::vec2> p(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) p[i] = glm::vec2(c[i][u], flip ? -c[i][v] : c[i][v]);
  return p;
}

float cross2(glm::vec2 a, glm::vec2 b, glm::vec2 c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool convex(const std::vector<glm::vec2>& p) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (cross2(p[(i + p.size() - 1) % p.size()], p[i], p[(i + 1) % p.size()]) < 0.0f) return false;
  }
  return true;
}

bool inside(glm::vec2 q, glm::vec2 a, glm::vec2 b, glm::vec2 c) {
  return cross2(a, b, q) >= 0.0f && cross2(b, c, q) >= 0.0f && cross2(c, a, q) >= 0.0f;
}

// Whether corner k of the remaining polygon `r` is an ear: convex, and no other corner inside.
bool is_ear(const std::vector<glm::vec2>& p, const std::vector<std::uint32_t>& r, std::size_t k) {
  const std::size_t m = r.size();
  const glm::vec2 a = p[r[(k + m - 1) % m]], b = p[r[k]], c = p[r[(k + 1) % m]];
  if (!(cross2(a, b, c) > 0.0f)) return false;
  for (std::size_t j = 0; j < m; ++j) {
    if (j == k || j == (k + 1) % m || j == (k + m - 1) % m) continue;
    if (inside(p[r[j]], a, b, c)) return false;
  }
  return true;
}

void fan(const std::vector<std::uint32_t>& r, std::vector<std::uint32_t>& out) {
  for (std::size_t i = 1; i + 1 < r.size(); ++i) out.insert(out.end(), {r[0], r[i], r[i + 1]});
}

}  // namespace

std::vector<std::uint32_t> triangulate_polygon(const std::vector<glm::vec3>& corners) {
  std::vector<std::uint32_t> r(corners.size()), out;
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = static_cast<std::uint32_t>(i);
  const std::vector<glm::vec2> p = projected(corners, newell_normal(corners));
  if (corners.size() <= 3 || convex(p)) {
    fan(r, out);
    return out;
  }
  while (r.size() > 3) {
    std::size_t k = 0;
    while (k < r.size() && !is_ear(p, r, k)) ++k;
    if (k == r.size()) break;  // no ear: degenerate or self-intersecting
    const std::size_t m = r.size();
    out.insert(out.end(), {r[(k + m - 1) % m], r[k], r[(k + 1) % m]});
    r.erase(r.begin() + static_cast<std::ptrdiff_t>(k));
  }
  fan(r, out);
  return out;
}

}  // namespace hrpp
