// hrpp_predict: HRPP's predict stage for hit-all (camera and bounce) rays; the body is
// shaders/lib/hrpp_predict.glsl, the interface shaders/shared/hrpp_interface.h.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require

#define HRPP_ANY_HIT 0
#include "lib/hrpp_predict.glsl"
