// The benchmark harness's check of a tracer's hits against a reference's (the CPU reference in
// `hrpp bench`). Closest hits agree when the triangle and t agree (t within 1e-5 relative, plus
// 1e-7 of the scene's diagonal for t near 0); a different triangle at the same t is a tie (both
// are right: shared edges, coplanar triangles), anything else a mismatch. Any-hit: occluded or
// not.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "gpu_types.h"
#include "trace/query_kind.h"

namespace hrpp {

struct Validation {
  std::size_t checked = 0, exact = 0, ties = 0, mismatches = 0;
  std::vector<std::string> examples;  // the first few mismatches, each with its ray
};

// `rays`' hits `test` against `ref` at the indices in `subset`.
Validation validate(std::span<const gpu::Ray> rays, std::span<const gpu::Hit> ref,
                    std::span<const gpu::Hit> test, std::span<const std::size_t> subset,
                    QueryKind kind, float scene_diagonal);

// `want` indices evenly spread over [0, n) (all of them when want is 0 or at least n).
std::vector<std::size_t> spread_subset(std::size_t n, std::size_t want);

}  // namespace hrpp
