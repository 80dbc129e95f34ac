// hrpp_pass_args: sizes hrpp_predict's indirect dispatch over a pass that takes a fraction of a
// trace's rays (the pilot schedule's pilots, the adaptive predictor's sample:
// shaders/shared/hrpp_passes.h) from the queue's ray count, so that the pass launches only the
// workgroups that have rays. The trace's own indirect arguments launch a workgroup per
// trace_group_rays of every ray, and on lavapipe a workgroup that leaves at once still costs
// about 3 us (256 of them 0.8 ms, a dispatch of one 0.02 ms: docs/DEVICES.md,
// "Workgroup cost").
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

#include "hrpp_interface.h"

layout(local_size_x = 1, local_size_y = 1, local_size_z = 1) in;
layout(push_constant) uniform PushConstants { StagePushConstants pc; };
layout(std430, set = 0, binding = 0) restrict buffer QueueBuffer { PredictQueue queue; };

void main() {
  const uint n = hrpp_pass_ray_count(queue.ray_count, pc.pilot_pass, pc.pilot_stride);
  queue.predict_groups[0] = (n + pc.trace_group_rays - 1u) / pc.trace_group_rays;
  queue.predict_groups[1] = 1u;
  queue.predict_groups[2] = 1u;
}
