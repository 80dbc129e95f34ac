// render_accumulate: adds the payload of every unoccluded shadow ray (any-hit miss) to its
// pixel. One shadow ray per path and wavefront, so no two items share a pixel: plain adds.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "lib/render_bindings.glsl"

void main() {
  const uint i = gl_GlobalInvocationID.x;
  uint finished = 0u;
  if (i < pc.count) {
    if (load_hit(i).prim < 0) {
      const ShadowRecord s = shadows[i];
      image[s.pixel].xyz += s.contribution;
    }
    finished = 1u;
  }
  report_done(finished);
}
