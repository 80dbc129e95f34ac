// ray_sort_gather: one sorted position per invocation: copies the ray the sort put there
// (order[j]) to sorted_rays[j], texel by texel. Optional: the indexed trace kernels read the
// rays through order[] instead (host/gpu/ray_sorter.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "lib/ray_sort_bindings.glsl"

layout(local_size_x = HRPP_SORT_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

void main() {
  const uint j = gl_GlobalInvocationID.x;
  uint placed = 0u;
  if (j < pc.count) {
    const int from = int(2u * order[j]);
    const int to = int(2u * j);
    imageStore(sorted_rays, to, texelFetch(ray_texels, from));
    imageStore(sorted_rays, to + 1, texelFetch(ray_texels, from + 1));
    placed = 1u;
  }
  report_placed(HRPP_SORT_PASSES, placed);
}
