// render_generate: one camera ray per pixel of the wavefront [pc.first_pixel, + pc.count) for
// sample pc.sample_index: pinhole camera, pixel position jittered by the path's random stream.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "lib/render_bindings.glsl"
#include "lib/rng.glsl"

void main() {
  const uint i = gl_GlobalInvocationID.x;
  uint finished = 0u;
  if (i < pc.count) {
    const uint pixel = pc.first_pixel + i;
    const uint x = pixel % params.width;
    const uint y = pixel / params.width;
    uint rng = rng_init(pixel, pc.sample_index, 0xFFFFFFFFu, params.seed);
    const float sx = (float(x) + rng_next(rng)) / float(params.width);
    const float sy = (float(y) + rng_next(rng)) / float(params.height);
    const float tan_half = params.cam_position.w;
    const float aspect = params.cam_forward.w;
    const vec3 d = params.cam_forward.xyz +
                   (2.0 * sx - 1.0) * tan_half * aspect * params.cam_right.xyz +
                   (1.0 - 2.0 * sy) * tan_half * params.cam_up.xyz;  // image rows top down
    rays[i] = Ray(params.cam_position.xyz, 0.0, normalize(d), HRPP_RAY_TMAX_FAR);
    paths[i] = PathState(vec3(1.0), pixel, pc.sample_index, 0u, 0u, 0u);
    finished = 1u;
  }
  report_done(HRPP_RENDER_DONE_GENERATE, finished);
}
