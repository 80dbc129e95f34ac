// render_accumulate: adds the payload of every unoccluded shadow ray (any-hit miss) to its
// pixel. One shadow ray per path and wavefront, so no two items share a pixel: plain adds.
// Runs on queues.shadow_rays items (dispatched indirectly: render_shade sized it).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "lib/render_bindings.glsl"

void main() {
  const uint i = gl_GlobalInvocationID.x;
  uint finished = 0u;
  if (i < queues.shadow_rays) {
    if (load_shadow_hit(i).prim < 0) {
      const ShadowRecord s = shadows[i];
      image[s.pixel].xyz += s.contribution;
    }
    finished = 1u;
  }
  report_done(HRPP_RENDER_DONE_ACCUMULATE, finished);
}
