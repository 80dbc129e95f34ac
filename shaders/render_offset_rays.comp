// render_offset_rays: offset_ray_origin and shadow_ray_to (shaders/lib/offset_ray.glsl) of every
// case, one per invocation and no loops. A check kernel: tests/light_transport_test.cpp compares
// its results with the C++ mirror (host/trace/offset_ray.h) bit for bit.
#version 460
#extension GL_GOOGLE_include_directive : require

#include "render_interface.h"
#include "lib/offset_ray.glsl"

layout(local_size_x = HRPP_RENDER_WORKGROUP_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, set = 0, binding = HRPP_OFFSET_RAYS_BINDING_CASES) readonly restrict buffer
CaseBuffer {
  OffsetRayCase cases[];
};
layout(std430, set = 0, binding = HRPP_OFFSET_RAYS_BINDING_RESULTS) writeonly restrict buffer
ResultBuffer {
  OffsetRayResult results[];
};
layout(push_constant) uniform PushConstants { uint case_count; };

void main() {
  const uint i = gl_GlobalInvocationID.x;
  if (i >= case_count) return;
  const OffsetRayCase c = cases[i];
  results[i].origin = vec4(offset_ray_origin(c.p.xyz, c.n.xyz), 0.0);
  results[i].shadow = shadow_ray_to(c.p.xyz, c.n.xyz, c.q.xyz, c.nq.xyz);
}
