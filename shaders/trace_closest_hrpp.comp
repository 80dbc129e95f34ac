// trace_closest_hrpp: trace_closest with HRPP (probe before traversal, shaders/lib/hrpp_predict.glsl).
// The traversal is shaders/lib/trace_kernel.glsl; the interfaces shaders/shared/trace_interface.h
// and shaders/shared/hrpp_interface.h.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require

#define HRPP_ANY_HIT 0
#define HRPP_PREDICT 1
#include "lib/trace_kernel.glsl"
