// ray_sort_count: one block of pc.block_items consecutive items per invocation: how many of
// them have each digit, written to counts[digit * blocks + block] (the order the scan sums in).
// Loops: 2 × HRPP_SORT_BINS + block_items iterations, far inside the loop limiter (the host
// bounds block_items: host/gpu/ray_sorter.cpp).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "lib/ray_sort_bindings.glsl"

layout(local_size_x = HRPP_SORT_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

void main() {
  const uint block = gl_GlobalInvocationID.x;
  if (block >= pc.blocks) return;
  uint histogram[HRPP_SORT_BINS];
  for (uint d = 0u; d < uint(HRPP_SORT_BINS); ++d) histogram[d] = 0u;
  const uint first = block * pc.block_items;
  const uint end = min(first + pc.block_items, pc.count);
  for (uint i = first; i < end; ++i) ++histogram[sort_digit(items[pc.src + i].x)];
  for (uint d = 0u; d < uint(HRPP_SORT_BINS); ++d) counts[d * pc.blocks + block] = histogram[d];
}
