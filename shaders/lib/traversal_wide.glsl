// The traversal of one ray through 4-wide nodes (host/bvh/wide_nodes.h), for the trace kernels
// specialised to them (HRPP_SPEC_NODE_FORMAT): WideNodes (--bvh-nodes wide4) or WideFloatNodes
// (wide4-float). The same while-while loop, leaf postponing and leaf test as traversal.glsl's
// binary traverse_from, and the same answer: the child boxes hold the exact ones (decoded
// WideNode boxes are rounded outward) and the leaves are the binary layout's.
//
// A step tests up to four children and may leave three for later. They are kept together as
// one group (nearest first), and the top group lives in registers: a step spills at most one
// 16-byte group to the stack and a pop reloads at most one. Llvmpipe pays for every stack store
// or load the code contains, taken by a lane or not, so one site each keeps a wide step's stack
// cost that of a binary step.
#ifndef HRPP_TRAVERSAL_WIDE_GLSL
#define HRPP_TRAVERSAL_WIDE_GLSL

#include "traversal.glsl"
#include "wide_node.h"

// The entry distance of a child whose box the ray enters, else +∞ (a miss or an empty slot).
float entry(RaySetup r, vec3 lo, vec3 hi, int child, float tmax) {
  float t;
  const bool hit = slab_test(r, lo, hi, tmax, t) && child != HRPP_WIDE_EMPTY_SLOT;
  return hit ? t : uintBitsToFloat(0x7F800000u);
}

// Child `i` of a WideNode: its decoded box.
float quantised_entry(RaySetup r, WideNode n, uint i, float tmax) {
  vec3 lo, hi;
  hrpp_wide_child_box(n, i, lo, hi);
  return entry(r, lo, hi, n.child[i], tmax);
}

// Child `i` of a WideFloatNode: its exact box.
float float_entry(RaySetup r, WideFloatNode n, uint i, float tmax) {
  return entry(r, vec3(n.lo_x[i], n.lo_y[i], n.lo_z[i]), vec3(n.hi_x[i], n.hi_y[i], n.hi_z[i]),
               n.child[i], tmax);
}

// The entry distances of wide node `node`'s four children, and their references.
vec4 child_entries(RaySetup r, int node, float tmax, out ivec4 child) {
  if (kNodeFormat == HRPP_NODES_WIDE_FLOAT) {
    const WideFloatNode n = load_wide_float_node(node);
    child = n.child;
    return vec4(float_entry(r, n, 0u, tmax), float_entry(r, n, 1u, tmax),
                float_entry(r, n, 2u, tmax), float_entry(r, n, 3u, tmax));
  }
  const WideNode n = load_wide_node(node);
  child = n.child;
  return vec4(quantised_entry(r, n, 0u, tmax), quantised_entry(r, n, 1u, tmax),
              quantised_entry(r, n, 2u, tmax), quantised_entry(r, n, 3u, tmax));
}

// Puts the child with the smaller entry distance first.
void order_pair(inout float ta, inout int a, inout float tb, inout int b) {
  const bool swap = tb < ta;
  const float t = ta;
  const int c = a;
  ta = swap ? tb : ta;
  a = swap ? b : a;
  tb = swap ? t : tb;
  b = swap ? c : b;
}

// One step at wide node `node`: the children the ray enters (`entered`: 0..4), nearest first
// (a sorting network of five compare-exchanges, branch-free).
ivec4 visit_wide(RaySetup r, int node, float tmax, out uint entered) {
  ivec4 c;
  vec4 t = child_entries(r, node, tmax, c);
  order_pair(t.x, c.x, t.y, c.y);
  order_pair(t.z, c.z, t.w, c.w);
  order_pair(t.x, c.x, t.z, c.z);
  order_pair(t.y, c.y, t.w, c.w);
  order_pair(t.y, c.y, t.z, c.z);
  const float no_entry = uintBitsToFloat(0x7F800000u);
  entered = uint(t.x < no_entry) + uint(t.y < no_entry) + uint(t.z < no_entry) +
            uint(t.w < no_entry);
  return c;
}

// The group stack of the ray being traced: groups[0..g_sp) in memory, g_top in registers
// (x, y, z: children nearest first; w: how many are left). At most one group per tree level,
// and a wide tree is never deeper than the binary one make_gpu_layout checked.
ivec4 g_groups[HRPP_STACK_SIZE];
int g_sp = 0;
ivec4 g_top = ivec4(kSentinel, kSentinel, kSentinel, 0);

// A step's children beyond the first become the top group.
void push_group(ivec4 c, uint entered) {
  if (entered < 2u) return;
  if (g_top.w > 0) g_groups[g_sp++] = g_top;
  g_top = ivec4(c.y, c.z, c.w, int(entered) - 1);
}

// The nearest child left for later, or kSentinel when there is none.
int pop_child() {
  if (g_top.w == 0 && g_sp > 0) g_top = g_groups[--g_sp];
  if (g_top.w == 0) return kSentinel;
  const int child = g_top.x;
  g_top = ivec4(g_top.y, g_top.z, kSentinel, g_top.w - 1);
  return child;
}

// Traces one ray into `best` from the root. Returns false when the traversal did not reach its
// end.
bool traverse_wide(RaySetup r, inout Hit best) {
  g_sp = 0;
  g_top = ivec4(kSentinel, kSentinel, kSentinel, 0);
  float tmax = r.tmax;
  int node = r.valid ? 0 : kSentinel;
  int leaf = 0;  // postponed leaf (< 0); >= 0: none
  while (node != kSentinel) {
    // Interior nodes until every lane still searching has postponed a leaf.
    bool searching = true;
    while (is_interior(node)) {
      ++g_interior;
      if (kCountSteps && subgroupElect()) ++g_steps;
      uint entered;
      const ivec4 c = visit_wide(r, node, tmax, entered);
      push_group(c, entered);
      int next = entered > 0u ? c.x : kSentinel;  // kSentinel: continue with the stack top
      if (next < 0 && leaf >= 0) {  // first leaf: postpone it and keep searching
        searching = false;
        leaf = next;
        next = kSentinel;
      }
      node = next != kSentinel ? next : pop_child();
      if (!subgroupAny(searching)) break;
    }
    // A leaf the search popped without a postponed one becomes the postponed one.
    if (node < 0 && leaf >= 0) {
      leaf = node;
      node = pop_child();
    }
    // The postponed leaf, then any leaf the traversal stopped at.
    while (leaf < 0) {
      if (test_leaf(r, leaf, best, tmax)) {  // any-hit answered
        node = kSentinel;
        leaf = 0;
        break;
      }
      leaf = node;
      if (node < 0) node = pop_child();
    }
  }
  return node == kSentinel;
}

#endif  // HRPP_TRAVERSAL_WIDE_GLSL
