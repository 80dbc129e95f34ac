// render_generate: one camera ray per pixel of the wavefront [pc.first_pixel, + pc.count) for
// sample pc.sample_index: pinhole camera, pixel position jittered by the path's random stream
// (camera_ray, shaders/shared/path_vertex.h, which the CPU reference renderer runs too).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "lib/render_bindings.glsl"
#include "path_vertex.h"

void main() {
  const uint i = gl_GlobalInvocationID.x;
  uint finished = 0u;
  if (i < pc.count) {
    const uint pixel = pc.first_pixel + i;
    rays[i] = camera_ray(params, pixel, pc.sample_index);
    paths[i] = camera_path(pixel, pc.sample_index);
    finished = 1u;
  }
  report_done(HRPP_RENDER_DONE_GENERATE, finished);
}
