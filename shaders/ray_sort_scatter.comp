// ray_sort_scatter: one block per invocation, as ray_sort_count: each item, in order, goes to
// the next free position of its digit in the block's share of the output (counts[] after
// ray_sort_scan). Items of one digit keep their order: the pass is a stable counting sort. The
// last pass writes only the item's ray index, to order[] (the sort's result).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "lib/ray_sort_bindings.glsl"

layout(local_size_x = HRPP_SORT_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

void main() {
  const uint block = gl_GlobalInvocationID.x;
  uint placed = 0u;
  if (block < pc.blocks) {
    uint next[HRPP_SORT_BINS];
    for (uint d = 0u; d < uint(HRPP_SORT_BINS); ++d) next[d] = counts[d * pc.blocks + block];
    const uint first = block * pc.block_items;
    const uint end = min(first + pc.block_items, pc.count);
    for (uint i = first; i < end; ++i) {
      const uvec2 item = items[pc.src + i];
      const uint d = sort_digit(item.x);
      if (last_pass()) {
        order[next[d]] = item.y;
      } else {
        items[pc.dst + next[d]] = item;
      }
      ++next[d];
      ++placed;
    }
  }
  report_placed(pc.shift / uint(HRPP_SORT_DIGIT_BITS), placed);
}
