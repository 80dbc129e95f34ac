// Embree (3 or 4, reference/embree_api.h) as an outside reference and speed baseline: the same
// triangles, the same ray and hit formats as the CPU reference (trace/cpu_traversal.h) and the
// GPU tracer.
//
//   - one triangle geometry over the scene's non-degenerate triangles (the BVH's set); Embree's
//     primID is mapped back to the scene's triangle id (docs/FORMATS.md);
//   - closest hit: rtcIntersect1, one ray at a time (Embree's single-ray path, the like-for-like
//     baseline for one-ray-per-invocation traversal; the stream API would add ray packing that
//     neither the CPU reference nor the kernels do); any hit: rtcOccluded1;
//   - scene flags none (Embree's fast, not watertight, triangle test), build quality high.
// Embree's test is not watertight and computes t differently, so rays through shared edges and
// vertices can disagree with the watertight reference and t can differ in the last bits.
//
// Optional at build time: without Embree (CMake option HRPP_WITH_EMBREE off, or the package
// missing) embree_available() is false and constructing an EmbreeTracer throws hrpp::Error.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "gpu_types.h"
#include "scene/scene.h"
#include "trace/query_kind.h"

namespace hrpp {

// True when this build has Embree.
bool embree_available();
// "Embree 3.13.5" (the library's version), or "Embree not available".
std::string embree_version();

class EmbreeTracer {
 public:
  // Builds Embree's BVH over the scene's non-degenerate triangles. Throws hrpp::Error without
  // Embree or on an Embree error.
  explicit EmbreeTracer(const Scene& scene);
  ~EmbreeTracer();
  EmbreeTracer(EmbreeTracer&&) noexcept;
  EmbreeTracer& operator=(EmbreeTracer&&) noexcept;
  EmbreeTracer(const EmbreeTracer&) = delete;
  EmbreeTracer& operator=(const EmbreeTracer&) = delete;

  // Closest hit in the hits format: prim = triangle id (-1 miss), t, u, v (barycentrics of v1, v2).
  gpu::Hit closest(const gpu::Ray& ray) const;
  // Any hit in [tmin, tmax].
  bool occluded(const gpu::Ray& ray) const;

  // Every ray on `threads` threads over ray ranges (parallel_ranges; 0: all). Any-hit
  // results: prim 0 occluded, -1 free, t = u = v = 0.
  std::vector<gpu::Hit> trace(std::span<const gpu::Ray> rays, QueryKind kind,
                              int threads = 0) const;
  // The same into `hits` (one per ray), which the caller allocated: benchmarks time the
  // trace alone, not the allocation and first touch of the hit array.
  void trace(std::span<const gpu::Ray> rays, QueryKind kind, std::span<gpu::Hit> hits,
             int threads = 0) const;

  double build_ms() const;  // rtcCommitScene time

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
