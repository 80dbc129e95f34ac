// Axis-aligned bounding box used while building and by the CPU reference.
#pragma once

#include <limits>

#include <glm/glm.hpp>

namespace hrpp {

struct Aabb {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};

  void grow(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void grow(const Aabb& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  glm::vec3 extent() const { return hi - lo; }
  glm::vec3 center() const { return 0.5f * (lo + hi); }
  // Surface area; 0 for an empty box (the SAH weighs nothing by it).
  float area() const {
    if (empty()) return 0.0f;
    const glm::vec3 e = extent();
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
  bool contains(const Aabb& b) const {
    return glm::all(glm::lessThanEqual(lo, b.lo)) && glm::all(glm::lessThanEqual(b.hi, hi));
  }
};

}  // namespace hrpp
