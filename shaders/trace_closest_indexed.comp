// trace_closest_indexed: trace_closest (closest-hit queries) over a ray index list: position j
// traces ray list[j] and writes its hit at that ray's index, so a reordering moves no ray
// and no hit. The kernel is shaders/lib/trace_kernel.glsl; the interface
// shaders/shared/trace_interface.h.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#define HRPP_ANY_HIT 0
#define HRPP_TRACE_INDEXED 1
#include "lib/trace_kernel.glsl"
