// Work counted per ray class by the CPU reference (and, with the same names, by the kernels).
#pragma once

#include <cstdint>

namespace hrpp {

struct TraversalCounters {
  std::uint64_t rays = 0;
  std::uint64_t interior_visited = 0;  // interior nodes whose two child boxes were tested
  std::uint64_t leaves_visited = 0;    // leaves whose triangles were tested
  std::uint64_t triangles_tested = 0;
  std::uint64_t hits = 0;
  // GPU only, when counted (GpuTracerConfig::count_steps): subgroup iterations of the
  // interior-node loop; 0 otherwise.
  std::uint64_t interior_steps = 0;

  TraversalCounters& operator+=(const TraversalCounters& o) {
    rays += o.rays;
    interior_visited += o.interior_visited;
    leaves_visited += o.leaves_visited;
    triangles_tested += o.triangles_tested;
    hits += o.hits;
    interior_steps += o.interior_steps;
    return *this;
  }
};

// The lanes' use of the interior-node loop: interior nodes visited over the lane slots of its
// subgroup iterations (steps × lanes per subgroup); 0 when the steps were not counted.
inline double lane_use(const TraversalCounters& c, std::uint32_t subgroup_size) {
  const double slots = static_cast<double>(c.interior_steps) * subgroup_size;
  return slots > 0.0 ? static_cast<double>(c.interior_visited) / slots : 0.0;
}

}  // namespace hrpp
