// trace_any: any-hit (occlusion) queries: prim 0 occluded, -1 free. The traversal is
// shaders/lib/trace_kernel.glsl; the interface shaders/shared/trace_interface.h.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#define HRPP_ANY_HIT 1
#include "lib/trace_kernel.glsl"
