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

  TraversalCounters& operator+=(const TraversalCounters& o) {
    rays += o.rays;
    interior_visited += o.interior_visited;
    leaves_visited += o.leaves_visited;
    triangles_tested += o.triangles_tested;
    hits += o.hits;
    return *this;
  }
};

}  // namespace hrpp
