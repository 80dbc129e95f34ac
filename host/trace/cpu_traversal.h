// Scalar CPU reference traversal on the GPU layout: the ground truth the kernels are tested
// against. Semantics (shared with the kernels):
//   - stack traversal from the root, nearest child first (ties: left first);
//   - conservative slab test (slab_test.h), watertight triangle test (watertight.h);
//   - a hit needs tmin <= t <= tmax; closest hit: smallest t, equal t → lower triangle id;
//   - a ray with NaN/Inf origin or direction, or a zero direction, misses everything.
// Without a counters pointer nothing is counted: the loop compiles without its increments.
#pragma once

#include <span>

#include "bvh/gpu_layout.h"
#include "trace/query_kind.h"
#include "trace/traversal_counters.h"

namespace hrpp {

gpu::Hit trace_closest(const GpuBvh& bvh, const gpu::Ray& ray, TraversalCounters* counters = nullptr);
bool trace_any(const GpuBvh& bvh, const gpu::Ray& ray, TraversalCounters* counters = nullptr);

// Any-hit query that also says which triangle answered it (the first hit met, in traversal
// order): HRPP inserts the leaf that held it.
gpu::Hit trace_any_hit(const GpuBvh& bvh, const gpu::Ray& ray, TraversalCounters* counters = nullptr);

// trace_closest (QueryKind::kClosest) or trace_any_hit (kAny) that does not enter the nodes in
// `skip` (child references; 0, the root: nothing is entered): the queue's trace with
// fallback skip (host/hrpp/reference_predictor.h).
gpu::Hit trace_skipping(const GpuBvh& bvh, const gpu::Ray& ray, QueryKind kind,
                        std::span<const int> skip, TraversalCounters* counters = nullptr);

// The subtree under `root` (a child reference: interior node index, or ~leaf index) with the
// ray's [tmin, tmax], improving `best` as the traversal does (closest: smaller t, ties to the
// lower id). QueryKind::kAny: stops at the first hit, best.prim = its triangle id; returns true
// then.
// Counts interior nodes, leaves and triangles only (HRPP's verification of predicted nodes).
bool trace_subtree(const GpuBvh& bvh, const gpu::Ray& ray, int root, QueryKind kind, gpu::Hit& best,
                   TraversalCounters* counters = nullptr);

inline constexpr gpu::Hit kMiss{-1, 0.0f, 0.0f, 0.0f};

}  // namespace hrpp
