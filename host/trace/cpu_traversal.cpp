#include "trace/cpu_traversal.h"

#include <algorithm>

#include "trace/slab_test.h"
#include "trace/watertight.h"

namespace hrpp {
namespace {

// The counters of an uncounted trace: every increment compiles to nothing, so a call without
// counters runs the traversal loop alone (the CPU tracers' timed path).
struct NoCount {
  constexpr NoCount& operator++() { return *this; }
};
struct NoCounters {
  NoCount rays, interior_visited, leaves_visited, triangles_tested, hits;
};

// Tests the leaf's triangles; returns true when `best` improved (any_only: on the first hit).
template <class Counters>
[[gnu::always_inline]] inline bool test_leaf(const GpuBvh& bvh, const RaySetup& r,
                                             const gpu::BvhLeaf& leaf, gpu::Hit& best,
                                             float& tmax, bool any_only, Counters& c) {
  ++c.leaves_visited;
  bool found = false;
  for (gpu::uint i = leaf.first_triangle; i < leaf.first_triangle + leaf.triangle_count; ++i) {
    const gpu::TriangleRecord& tri = bvh.triangles[i];
    ++c.triangles_tested;
    TriangleHit h;
    if (!intersect_triangle(r, tri.v0, tri.v1, tri.v2, tmax, &h)) continue;
    const int prim = static_cast<int>(tri.prim);
    if (best.prim >= 0 && h.t == best.t && prim > best.prim) continue;  // tie: lower id wins
    best = {prim, h.t, h.u, h.v};
    tmax = h.t;
    found = true;
    if (any_only) return true;
  }
  return found;
}

[[gnu::always_inline]] inline bool contains(std::span<const int> refs, int ref) {
  return std::find(refs.begin(), refs.end(), ref) != refs.end();
}

// Stack traversal of the subtree under `root` (interior node index or ~leaf) into `best`;
// tmax starts at `tmax`; children in `skip` are not entered. Returns true when an any-hit query
// was answered.
template <class Counters>
bool traverse_from(const GpuBvh& bvh, const RaySetup& r, int root, float tmax, gpu::Hit& best,
                   bool any_only, Counters& c, std::span<const int> skip = {}) {
  int stack[HRPP_STACK_SIZE];
  int sp = 0;
  int node = root;
  while (true) {
    if (is_leaf_ref(node)) {
      if (test_leaf(bvh, r, bvh.leaves[leaf_index(node)], best, tmax, any_only, c) && any_only)
        return true;
    } else {
      ++c.interior_visited;
      const gpu::BvhNode& n = bvh.nodes[node];
      float t_left, t_right;
      const bool hit_left = slab_test(r, {n.left_xy.x, n.left_xy.z, n.lr_z.x},
                                      {n.left_xy.y, n.left_xy.w, n.lr_z.y}, tmax, &t_left) &&
                            !contains(skip, n.link.x);
      const bool hit_right = slab_test(r, {n.right_xy.x, n.right_xy.z, n.lr_z.z},
                                       {n.right_xy.y, n.right_xy.w, n.lr_z.w}, tmax, &t_right) &&
                             !contains(skip, n.link.y);
      if (hit_left && hit_right) {
        const bool right_first = t_right < t_left;
        stack[sp++] = right_first ? n.link.x : n.link.y;
        node = right_first ? n.link.y : n.link.x;
        continue;
      }
      if (hit_left || hit_right) {
        node = hit_left ? n.link.x : n.link.y;
        continue;
      }
    }
    if (sp == 0) return false;
    node = stack[--sp];
  }
}

template <class Counters>
gpu::Hit traverse_counting(const GpuBvh& bvh, const gpu::Ray& ray, bool any_only, Counters& c,
                           std::span<const int> skip) {
  ++c.rays;
  gpu::Hit best = kMiss;
  const RaySetup r = setup_ray(ray);
  if (r.valid && !bvh.nodes.empty() && !contains(skip, 0))
    traverse_from(bvh, r, 0, ray.tmax, best, any_only, c, skip);
  if (best.prim >= 0) ++c.hits;
  return best;
}

gpu::Hit traverse(const GpuBvh& bvh, const gpu::Ray& ray, bool any_only, TraversalCounters* out,
                  std::span<const int> skip = {}) {
  if (!out) {
    NoCounters none;
    return traverse_counting(bvh, ray, any_only, none, skip);
  }
  TraversalCounters c;
  const gpu::Hit best = traverse_counting(bvh, ray, any_only, c, skip);
  *out += c;
  return best;
}

}  // namespace

gpu::Hit trace_closest(const GpuBvh& bvh, const gpu::Ray& ray, TraversalCounters* counters) {
  return traverse(bvh, ray, false, counters);
}

bool trace_any(const GpuBvh& bvh, const gpu::Ray& ray, TraversalCounters* counters) {
  return traverse(bvh, ray, true, counters).prim >= 0;
}

gpu::Hit trace_any_hit(const GpuBvh& bvh, const gpu::Ray& ray, TraversalCounters* counters) {
  return traverse(bvh, ray, true, counters);
}

gpu::Hit trace_skipping(const GpuBvh& bvh, const gpu::Ray& ray, QueryKind kind,
                        std::span<const int> skip, TraversalCounters* counters) {
  return traverse(bvh, ray, kind == QueryKind::kAny, counters, skip);
}

bool trace_subtree(const GpuBvh& bvh, const gpu::Ray& ray, int root, QueryKind kind, gpu::Hit& best,
                   TraversalCounters* counters) {
  const RaySetup r = setup_ray(ray);
  if (!r.valid) return false;
  const bool any_only = kind == QueryKind::kAny;
  if (!counters) {
    NoCounters none;
    return traverse_from(bvh, r, root, ray.tmax, best, any_only, none);
  }
  TraversalCounters c;
  const bool answered = traverse_from(bvh, r, root, ray.tmax, best, any_only, c);
  *counters += c;
  return answered;
}

}  // namespace hrpp
