// The traversal of one ray, shared by the trace kernels (shaders/lib/trace_kernel.glsl) and
// HRPP's predict kernel (shaders/hrpp_predict.comp, which tests predicted nodes with it), over
// binary nodes or (the trace kernels specialised to them) 4-wide ones (traversal_wide.glsl).
// Semantics are those of the CPU reference (host/trace/cpu_traversal.h): same ray setup, slab
// and triangle tests, inclusive [tmin, tmax], equal t → lower triangle id, invalid rays miss;
// the visiting order differs (leaf postponing), the answer does not.
//
// Aila–Laine "speculative while-while" traversal (Aila & Laine 2009, "Understanding the
// Efficiency of Ray Traversal on GPUs"): 64-byte nodes holding both child boxes, nearest child
// first, a per-invocation stack, the first leaf met is postponed while the traversal goes on
// until every lane of the subgroup has one (subgroupAny), then the leaves are tested.
//
// The includer defines HRPP_ANY_HIT (0: closest hit; 1: any hit, the first occluder found is
// the answer) and a push-constant block `pc` with a canary_iterations member.
#ifndef HRPP_TRAVERSAL_GLSL
#define HRPP_TRAVERSAL_GLSL

#include "trace_interface.h"
#include "slab_test.glsl"
#include "watertight.glsl"
#include "texel_fetch.glsl"
#include "loop_limiter.glsl"

// Stack bottom / end of traversal. Child references: >= 0 interior node, < 0 leaf (~leaf index).
const int kSentinel = 0x7fffffff;

// Work done by this invocation, summed per subgroup at the end.
uint g_interior = 0u;
uint g_leaves = 0u;
uint g_triangles = 0u;
// Iterations of the interior-node loop, counted by one lane per subgroup and iteration, when
// the kernel is specialised to count them (trace_interface.h, HRPP_SPEC_COUNT_STEPS).
layout(constant_id = HRPP_SPEC_COUNT_STEPS) const bool kCountSteps = false;
uint g_steps = 0u;
// What the node array holds (trace_interface.h, HRPP_SPEC_NODE_FORMAT; traversal_wide.glsl).
layout(constant_id = HRPP_SPEC_NODE_FORMAT) const uint kNodeFormat = HRPP_NODES_BINARY;

bool is_interior(int ref) { return uint(ref) < uint(kSentinel); }  // leaves are negative

// HRPP_TRACE_SKIPPING 1 (the skipping trace kernels, trace_kernel.glsl): the nodes the ray's
// traversal does not enter, child references set per ray (kSentinel: none).
#ifndef HRPP_TRACE_SKIPPING
#define HRPP_TRACE_SKIPPING 0
#endif
#if HRPP_TRACE_SKIPPING
ivec4 g_skip = ivec4(kSentinel);
bool skipped(int ref) { return any(equal(ivec4(ref), g_skip)); }
#endif

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
    best = Hit(int(tri.prim), t, u, v);  // the first occluder found (HRPP inserts its leaf)
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

// The traversal stack of the ray being traced over binary nodes, one child per entry
// (g_stack[0..g_sp)), global so that the node step pushes onto it. Over wide nodes the groups
// of traversal_wide.glsl take its place.
int g_stack[HRPP_STACK_SIZE];
int g_sp = 0;

// One step at binary node `node`: the children the ray enters (`entered`: 0..2), nearest first
// (equal distances: the left first).
ivec4 visit_binary(RaySetup r, int node, float tmax, out uint entered) {
  const BvhNode n = load_node(node);
  float t_left, t_right;
  bool hit_left = slab_test(r, vec3(n.left_xy.x, n.left_xy.z, n.lr_z.x),
                            vec3(n.left_xy.y, n.left_xy.w, n.lr_z.y), tmax, t_left);
  bool hit_right = slab_test(r, vec3(n.right_xy.x, n.right_xy.z, n.lr_z.z),
                             vec3(n.right_xy.y, n.right_xy.w, n.lr_z.w), tmax, t_right);
#if HRPP_TRACE_SKIPPING
  hit_left = hit_left && !skipped(n.link.x);
  hit_right = hit_right && !skipped(n.link.y);
#endif
  entered = uint(hit_left) + uint(hit_right);
  const bool right_first = hit_right && (!hit_left || t_right < t_left);
  return right_first ? ivec4(n.link.y, n.link.x, kSentinel, kSentinel)
                     : ivec4(n.link.x, n.link.y, kSentinel, kSentinel);
}

#include "traversal_wide.glsl"

// One step at interior node `node` in the node format: returns the nearest child the ray enters
// (kSentinel: none) and pushes the others it enters.
int visit(RaySetup r, int node, float tmax) {
  uint entered;
  ivec4 c;
  if (kNodeFormat == HRPP_NODES_BINARY) {
    c = visit_binary(r, node, tmax, entered);
    if (entered > 1u) g_stack[g_sp++] = c.y;
  } else {
    c = visit_wide(r, node, tmax, entered);
    push_group(c, entered);
  }
  return entered > 0u ? c.x : kSentinel;
}

// The nearest child left for later, or kSentinel when there is none.
int pop() {
  if (kNodeFormat != HRPP_NODES_BINARY) return pop_group_child();
  return g_sp > 0 ? g_stack[--g_sp] : kSentinel;
}

// Traces one ray into `best` through the subtree under interior node `start` (0: the whole
// tree; HRPP verifies predicted interior nodes this way). Returns false when the traversal did
// not reach its end.
bool traverse_from(RaySetup r, int start, inout Hit best) {
  g_sp = 0;
  clear_groups();
  float tmax = r.tmax;
  int node = r.valid ? start : kSentinel;
  int leaf = 0;  // postponed leaf (< 0); >= 0: none
  while (node != kSentinel) {
    // Interior nodes until every lane still searching has postponed a leaf.
    bool searching = true;
    while (is_interior(node)) {
      ++g_interior;
      if (kCountSteps && subgroupElect()) ++g_steps;
      int next = visit(r, node, tmax);  // kSentinel: continue with the stack top
      if (next < 0 && leaf >= 0) {  // first leaf: postpone it and keep searching
        searching = false;
        leaf = next;
        next = kSentinel;
      }
      // One pop site: lavapipe runs every branch of a subgroup, so each pop written costs a
      // gather whether a lane takes it or not.
      node = next != kSentinel ? next : pop();
      if (!subgroupAny(searching)) break;
    }
    // A leaf the search popped without a postponed one becomes the postponed one.
    if (node < 0 && leaf >= 0) {
      leaf = node;
      node = pop();
    }
    // The postponed leaf, then any leaf the traversal stopped at.
    while (leaf < 0) {
      if (test_leaf(r, leaf, best, tmax)) {  // any-hit answered
        node = kSentinel;
        leaf = 0;
        break;
      }
      leaf = node;
      if (node < 0) node = pop();
    }
  }
  return node == kSentinel;
}


#endif  // HRPP_TRAVERSAL_GLSL
