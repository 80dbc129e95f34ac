// trace_closest: closest-hit queries: nearest triangle, ties to the lower id. The traversal is
// shaders/lib/trace_kernel.glsl; the interface shaders/shared/trace_interface.h.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#define HRPP_ANY_HIT 0
#include "lib/trace_kernel.glsl"
