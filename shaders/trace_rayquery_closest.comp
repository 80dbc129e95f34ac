// trace_rayquery_closest: closest-hit queries: the nearest triangle, by the driver's traversal
// (VK_KHR_ray_query). The body is shaders/lib/ray_query_kernel.glsl; the interface
// shaders/shared/trace_interface.h (HRPP_RAY_QUERY_BINDING_*).
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#define HRPP_ANY_HIT 0
#include "lib/ray_query_kernel.glsl"
