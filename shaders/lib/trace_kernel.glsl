// Body of the trace kernels: trace_closest.comp (HRPP_ANY_HIT 0) and trace_any.comp
// (HRPP_ANY_HIT 1). Semantics are those of the CPU reference (host/trace/cpu_traversal.h):
// same ray setup, slab and triangle tests, inclusive [tmin, tmax], equal t → lower triangle id,
// invalid rays miss; the visiting order differs (leaf postponing), the answer does not.
//
// Aila–Laine "speculative while-while" traversal (Aila & Laine 2009, "Understanding the
// Efficiency of Ray Traversal on GPUs"): 64-byte nodes holding both child boxes, nearest child
// first, a per-invocation stack, the first leaf met is postponed while the traversal goes on
// until every lane of the subgroup has one (subgroupAny), then the leaves are tested.
//
// Persistent invocations: one lane per subgroup fetches the next rays with atomicAdd on a global
// cursor, but at most pc.rays_per_invocation per invocation, because lavapipe's loop limiter
// (DESIGN.md) silently ends every loop once a subgroup has run 65,535 loop iterations in total.
// Every ray proves it finished: its traversal loop must end at the sentinel and a canary loop
// with a bound unknown to the compiler (pc.canary_iterations) must still run in full. Rays that
// pass count in HRPP_COUNTER_RAYS; the others in counters.aborted; the host compares.
#ifndef HRPP_TRACE_KERNEL_GLSL
#define HRPP_TRACE_KERNEL_GLSL

#include "trace_interface.h"
#ifndef HRPP_PREDICT
#define HRPP_PREDICT 0  // 1: probe the HRPP predictor first (trace_*_hrpp.comp)
#endif
#include "slab_test.glsl"
#include "watertight.glsl"
#include "texel_fetch.glsl"

layout(local_size_x = HRPP_TRACE_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, set = 0, binding = HRPP_TRACE_BINDING_HITS) writeonly restrict buffer HitBuffer {
  Hit hits[];
};
layout(std430, set = 0, binding = HRPP_TRACE_BINDING_COUNTERS) restrict buffer CounterBuffer {
  TraceCounters counters;
};
layout(push_constant) uniform PushConstants { TracePushConstants pc; };

// Stack bottom / end of traversal. Child references: >= 0 interior node, < 0 leaf (~leaf index).
const int kSentinel = 0x7fffffff;

// Work done by this invocation, summed per subgroup at the end.
uint g_interior = 0u;
uint g_leaves = 0u;
uint g_triangles = 0u;

bool is_interior(int ref) { return uint(ref) < uint(kSentinel); }  // leaves are negative

// Tests a leaf's triangles. Returns true when an any-hit query is answered.
bool test_leaf(RaySetup r, int leaf_ref, inout Hit best, inout float tmax) {
  ++g_leaves;
  const BvhLeaf leaf = load_leaf(~leaf_ref);
  const uint end = leaf.first_triangle + leaf.triangle_count;
  for (uint i = leaf.first_triangle; i < end; ++i) {
    ++g_triangles;
    const TriangleRecord tri = load_triangle(i);
    float t, u, v;
    if (!intersect_triangle(r, tri.v0, tri.v1, tri.v2, tmax, t, u, v)) continue;
#if HRPP_ANY_HIT
#if HRPP_PREDICT
    best = Hit(int(tri.prim), 0.0, 0.0, 0.0);  // HRPP inserts the leaf of this triangle
#else
    best = Hit(0, 0.0, 0.0, 0.0);
#endif
    return true;
#else
    const int prim = int(tri.prim);
    if (best.prim >= 0 && t == best.t && prim > best.prim) continue;  // tie: lower id wins
    best = Hit(prim, t, u, v);
    tmax = t;
#endif
  }
  return false;
}

// Traces one ray into `best` through the subtree under interior node `start` (0: the whole
// tree; HRPP verifies predicted interior nodes this way). Returns false when the traversal did
// not reach its end.
bool traverse_from(RaySetup r, int start, inout Hit best) {
  int stack[HRPP_STACK_SIZE];
  int sp = 0;
  float tmax = r.tmax;
  int node = r.valid ? start : kSentinel;
  int leaf = 0;  // postponed leaf (< 0); >= 0: none
  while (node != kSentinel) {
    // Interior nodes until every lane still searching has postponed a leaf.
    bool searching = true;
    while (is_interior(node)) {
      ++g_interior;
      const BvhNode n = load_node(node);
      float t_left, t_right;
      const bool hit_left = slab_test(r, vec3(n.left_xy.x, n.left_xy.z, n.lr_z.x),
                                      vec3(n.left_xy.y, n.left_xy.w, n.lr_z.y), tmax, t_left);
      const bool hit_right = slab_test(r, vec3(n.right_xy.x, n.right_xy.z, n.lr_z.z),
                                       vec3(n.right_xy.y, n.right_xy.w, n.lr_z.w), tmax, t_right);
      int next = kSentinel;  // kSentinel: continue with the stack top
      if (hit_left && hit_right) {
        const bool right_first = t_right < t_left;
        stack[sp++] = right_first ? n.link.x : n.link.y;
        next = right_first ? n.link.y : n.link.x;
      } else if (hit_left || hit_right) {
        next = hit_left ? n.link.x : n.link.y;
      }
      if (next < 0 && leaf >= 0) {  // first leaf: postpone it and keep searching
        searching = false;
        leaf = next;
        next = kSentinel;
      }
      // One pop site: lavapipe runs every branch of a subgroup, so each pop written costs a
      // gather whether a lane takes it or not.
      node = next != kSentinel ? next : (sp > 0 ? stack[--sp] : kSentinel);
      if (!subgroupAny(searching)) break;
    }
    // A leaf the search popped without a postponed one becomes the postponed one.
    if (node < 0 && leaf >= 0) {
      leaf = node;
      node = sp > 0 ? stack[--sp] : kSentinel;
    }
    // The postponed leaf, then any leaf the traversal stopped at.
    while (leaf < 0) {
      if (test_leaf(r, leaf, best, tmax)) {  // any-hit answered
        node = kSentinel;
        leaf = 0;
        break;
      }
      leaf = node;
      if (node < 0) node = sp > 0 ? stack[--sp] : kSentinel;
    }
  }
  return node == kSentinel;
}

#if HRPP_PREDICT
#include "hrpp_predict.glsl"
#endif

// True while the loop limiter has budget left: a loop of pc.canary_iterations (2) iterations
// runs in full. Once a limiter has fired, loops run once, so this reads false from then on.
bool loop_budget_left() {
  uint n = 0u;
  for (uint i = 0u; i < pc.canary_iterations; ++i) ++n;
  return n == pc.canary_iterations;
}

void add_wide(uint counter, uint value) {
  if (value == 0u) return;
  const uint old = atomicAdd(counters.wide[2u * counter], value);
  if (old + value < old) atomicAdd(counters.wide[2u * counter + 1u], 1u);  // carry
}

void main() {
#if HRPP_PREDICT
  if (hrpp.serial != 0u && gl_SubgroupInvocationID != 0u) return;  // one ray per subgroup
#endif
  uint done = 0u, hit_count = 0u, aborted = 0u;
  for (uint k = 0u; k < pc.rays_per_invocation; ++k) {
    // One atomicAdd per subgroup for all its active lanes (any subgroup size).
    const uvec4 lanes = subgroupBallot(true);
    uint base = 0u;
    if (subgroupElect()) base = atomicAdd(counters.next_ray, subgroupBallotBitCount(lanes));
    base = subgroupBroadcastFirst(base);
    if (base >= counters.ray_count) break;  // uniform across the subgroup
    const uint index = base + subgroupBallotExclusiveBitCount(lanes);
    if (index >= counters.ray_count) continue;

    const RaySetup r = setup_ray(load_ray(index));
    Hit best = Hit(-1, 0.0, 0.0, 0.0);
#if HRPP_PREDICT
    const bool finished = hrpp_trace(r, index, best);
#else
    const bool finished = traverse_from(r, 0, best);
#endif
    if (loop_budget_left() && finished) {
      hits[index] = best;
      ++done;
      if (best.prim >= 0) ++hit_count;
    } else {
      ++aborted;
    }
  }

  const uint sums[HRPP_COUNTER_COUNT] = uint[](subgroupAdd(done), subgroupAdd(g_interior),
                                               subgroupAdd(g_leaves), subgroupAdd(g_triangles),
                                               subgroupAdd(hit_count));
  const uint aborted_sum = subgroupAdd(aborted);
  // No loop here: a limiter that fired during the last ray would cut a loop short and lose
  // counts of rays that did finish.
  if (subgroupElect()) {
    add_wide(HRPP_COUNTER_RAYS, sums[HRPP_COUNTER_RAYS]);
    add_wide(HRPP_COUNTER_INTERIOR, sums[HRPP_COUNTER_INTERIOR]);
    add_wide(HRPP_COUNTER_LEAVES, sums[HRPP_COUNTER_LEAVES]);
    add_wide(HRPP_COUNTER_TRIANGLES, sums[HRPP_COUNTER_TRIANGLES]);
    add_wide(HRPP_COUNTER_HITS, sums[HRPP_COUNTER_HITS]);
    if (aborted_sum != 0u) atomicAdd(counters.aborted, aborted_sum);
  }
#if HRPP_PREDICT
  hrpp_flush_counters();
#endif
}

#endif  // HRPP_TRACE_KERNEL_GLSL
