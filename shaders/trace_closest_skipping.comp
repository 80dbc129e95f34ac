// trace_closest_skipping: trace_closest (closest-hit queries) over HRPP's queue with fallback skip:
// position j does not enter the nodes of entry j of a skip list, those its prediction tested
// without an answer. The kernel is shaders/lib/trace_kernel.glsl; the interface
// shaders/shared/trace_interface.h.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#define HRPP_ANY_HIT 0
#define HRPP_TRACE_SKIPPING 1
#include "lib/trace_kernel.glsl"
