// Scalar CPU reference traversal on the GPU layout: the ground truth the kernels are tested
// against. Semantics (shared with the kernels):
//   - stack traversal from the root, nearest child first (ties: left first);
//   - conservative slab test (slab_test.h), watertight triangle test (watertight.h);
//   - a hit needs tmin <= t <= tmax; closest hit: smallest t, equal t → lower triangle id;
//   - a ray with NaN/Inf origin or direction, or a zero direction, misses everything.
#pragma once

#include "bvh/gpu_layout.h"
#include "trace/traversal_counters.h"

namespace hrpp {

gpu::Hit trace_closest(const GpuBvh& bvh, const gpu::Ray& ray, TraversalCounters* counters = nullptr);
bool trace_any(const GpuBvh& bvh, const gpu::Ray& ray, TraversalCounters* counters = nullptr);

inline constexpr gpu::Hit kMiss{-1, 0.0f, 0.0f, 0.0f};

}  // namespace hrpp
