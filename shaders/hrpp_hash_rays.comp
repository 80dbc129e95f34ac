// hrpp_hash_rays: the HRPP key of every ray (shaders/lib/hrpp_hash.glsl), one ray per
// invocation and no loops (so lavapipe's loop limiter cannot touch it). Used to check the C++
// mirror (host/hrpp/ray_hash.cpp) bit for bit; host side: host/front/gpu_ray_hash.cpp.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#include "hrpp_interface.h"
#include "lib/hrpp_hash.glsl"

layout(local_size_x = HRPP_HASH_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, set = 0, binding = HRPP_HASH_BINDING_RAYS) readonly restrict buffer RayBuffer {
  Ray rays[];
};
layout(std430, set = 0, binding = HRPP_HASH_BINDING_KEYS) writeonly restrict buffer KeyBuffer {
  uint64_t keys[];
};
layout(std430, set = 0, binding = HRPP_HASH_BINDING_PARAMS) readonly restrict buffer ParamBuffer {
  HashParams params;
};
layout(push_constant) uniform PushConstants { uint ray_count; };

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= ray_count) return;
  keys[i] = hrpp_hash_ray(rays[i].origin, rays[i].dir, rays[i].tmax, params);
}
