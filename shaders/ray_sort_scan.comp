// ray_sort_scan: one workgroup: the exclusive prefix sums of counts[] in place, so that
// counts[digit * blocks + block] becomes the first sorted position of that block's items with
// that digit. Each invocation sums a contiguous chunk, invocation 0 scans the chunk sums, each
// invocation writes its chunk's prefixes.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "lib/ray_sort_bindings.glsl"

layout(local_size_x = HRPP_SORT_SCAN_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

shared uint chunk_start[HRPP_SORT_SCAN_WORKGROUP_SIZE];

void main() {
  const uint lane = gl_LocalInvocationID.x;
  const uint total = uint(HRPP_SORT_BINS) * pc.blocks;
  const uint per = (total + uint(HRPP_SORT_SCAN_WORKGROUP_SIZE) - 1u) /
                   uint(HRPP_SORT_SCAN_WORKGROUP_SIZE);
  const uint first = min(lane * per, total);
  const uint end = min(first + per, total);
  uint sum = 0u;
  for (uint i = first; i < end; ++i) sum += counts[i];
  chunk_start[lane] = sum;
  memoryBarrierShared();
  barrier();
  if (lane == 0u) {
    uint run = 0u;
    for (uint k = 0u; k < uint(HRPP_SORT_SCAN_WORKGROUP_SIZE); ++k) {
      const uint s = chunk_start[k];
      chunk_start[k] = run;
      run += s;
    }
  }
  memoryBarrierShared();
  barrier();
  uint run = chunk_start[lane];
  for (uint i = first; i < end; ++i) {
    const uint c = counts[i];
    counts[i] = run;
    run += c;
  }
}
