// The steps of traversal.glsl's loop through 4-wide nodes (host/bvh/wide_nodes.h), for the trace
// kernels specialised to them (HRPP_SPEC_NODE_FORMAT): WideNodes (--bvh-nodes wide4) or
// WideFloatNodes (wide4-float). The answer is the binary nodes': the child boxes hold the exact
// ones (decoded WideNode boxes are rounded outward) and the leaves are the binary layout's.
// Included by traversal.glsl.
//
// A step tests up to four children and may leave three for later. They are kept together as
// one group (nearest first), and the top group lives in registers: a step spills at most one
// 16-byte group to the stack and a pop reloads at most one. Llvmpipe pays for every stack store
// or load the code contains, taken by a lane or not, so one site each keeps a wide step's stack
// cost that of a binary step.
#ifndef HRPP_TRAVERSAL_WIDE_GLSL
#define HRPP_TRAVERSAL_WIDE_GLSL

#include "wide_node.h"

// The entry distance of a child whose box the ray enters, else +∞ (a miss or an empty slot).
float entry(RaySetup r, vec3 lo, vec3 hi, int child, float tmax) {
  float t;
  const bool hit = slab_test(r, lo, hi, tmax, t) && child != HRPP_WIDE_EMPTY_SLOT;
  return hit ? t : uintBitsToFloat(0x7F800000u);
}

// Child `i` of a WideNode: its decoded box (`steps`: the node's grid steps).
float quantised_entry(RaySetup r, WideNode n, vec3 steps, uint i, float tmax) {
  vec3 lo, hi;
  hrpp_wide_child_box(n, steps, i, lo, hi);
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
  const vec3 steps = hrpp_grid_steps(n);
  child = n.child;
  return vec4(quantised_entry(r, n, steps, 0u, tmax), quantised_entry(r, n, steps, 1u, tmax),
              quantised_entry(r, n, steps, 2u, tmax), quantised_entry(r, n, steps, 3u, tmax));
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

// The groups of children left for later, over wide nodes: g_groups[0..g_group_count) in memory
// and the top group in registers, g_top (x, y, z: children nearest first; w: how many are left).
// At most one group per tree level, and a wide tree is never deeper than the binary one
// make_gpu_layout checked.
ivec4 g_groups[HRPP_STACK_SIZE];
int g_group_count = 0;
ivec4 g_top = ivec4(kSentinel, kSentinel, kSentinel, 0);

void clear_groups() {
  g_group_count = 0;
  g_top = ivec4(kSentinel, kSentinel, kSentinel, 0);
}

// A step's children beyond the first become the top group.
void push_group(ivec4 c, uint entered) {
  if (entered < 2u) return;
  if (g_top.w > 0) g_groups[g_group_count++] = g_top;
  g_top = ivec4(c.y, c.z, c.w, int(entered) - 1);
}

// The nearest child left for later, or kSentinel when there is none.
int pop_group_child() {
  if (g_top.w == 0 && g_group_count > 0) g_top = g_groups[--g_group_count];
  if (g_top.w == 0) return kSentinel;
  const int child = g_top.x;
  g_top = ivec4(g_top.y, g_top.z, kSentinel, g_top.w - 1);
  return child;
}

#endif  // HRPP_TRAVERSAL_WIDE_GLSL
