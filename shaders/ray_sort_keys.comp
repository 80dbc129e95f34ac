// ray_sort_keys: one ray per invocation: its reordering key (shaders/lib/ray_sort_key.glsl) and
// its queue index, the first radix pass's input.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "lib/ray_sort_bindings.glsl"
#include "lib/ray_sort_key.glsl"

layout(local_size_x = HRPP_SORT_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  const uvec4 a = texelFetch(ray_texels, int(2u * i));
  const uvec4 b = texelFetch(ray_texels, int(2u * i + 1u));
  const Ray r = Ray(uintBitsToFloat(a.xyz), uintBitsToFloat(a.w), uintBitsToFloat(b.xyz),
                    uintBitsToFloat(b.w));
  items[pc.dst + i] = uvec2(ray_sort_key(r, pc.lo.xyz, pc.scale.xyz), i);
}
