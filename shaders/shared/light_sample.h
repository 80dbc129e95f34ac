// Next-event estimation: one sample of one light seen from a surface point, with the shadow ray
// that tests it (offset at both ends: offset_ray.glsl, host/trace/offset_ray.h). Shared by
// render_shade and the CPU reference renderer (glsl_cpp.h). The feature constants
// (kEmissiveTriangles, ...) are the kernels' specialization constants (render_bindings.glsl);
// the CPU side compiles every feature in (render_interface.h).
#ifndef HRPP_LIGHT_SAMPLE_H
#define HRPP_LIGHT_SAMPLE_H

#include "glsl_cpp.h"
#include "render_interface.h"
#include "surface_hit.h"

#ifdef __cplusplus
#include "trace/offset_ray.h"
namespace hrpp::gpu {
#else
#include "offset_ray.glsl"
#endif

// A ray from o along unit dir up to tmax (tmin 0: the origins are offset instead).
HRPP_INLINE Ray ray_from(vec3 o, vec3 dir, float tmax) {
  Ray r;
  r.origin = o;
  r.tmin = 0.0f;
  r.dir = dir;
  r.tmax = tmax;
  return r;
}

struct LightSample {
  vec3 wi;    // unit direction from the surface point to the light
  vec3 li;    // incident radiance × 1/pdf of the sample (zero: nothing to add)
  float pdf;  // area lights: the solid-angle pdf of wi (the light's pick not included); 0: a
              // delta light, which no BSDF sample can find
  float dist;  // area lights: from the shadow ray's origin to the sampled point
  Ray shadow;  // from the surface point to the light, offset at both ends
};

// Solid-angle pdf of a point sampled uniformly on a triangle of doubled area `area2`, at
// distance `dist` along a direction whose cosine with the triangle's normal is `cos_l`.
HRPP_INLINE float triangle_solid_angle_pdf(float area2, float cos_l, float dist) {
  return ieee_div(dist * dist, abs(cos_l) * 0.5f * area2);
}

// A point uniformly on emissive triangle l (radiance l.color; one-sided: cos_inner 1) seen from
// s: the shadow ray ends just short of it, moved off the triangle towards s.
HRPP_INLINE LightSample sample_triangle_light(GpuLight l, SurfaceHit s, float u1, float u2) {
  const float r = ieee_sqrt(u1);
  const vec3 q = l.position + r * (1.0f - u2) * l.dir + r * u2 * l.edge2;
  const vec3 c = ieee_cross(l.dir, l.edge2);
  const float area2 = ieee_length(c);
  const vec3 to = q - s.p;
  const float d2 = ieee_dot(to, to);
  LightSample ls;
  ls.wi = ieee_div(to, ieee_sqrt(d2));
  const float cos_l = ieee_div(ieee_dot(c, ls.wi), area2);  // > 0: s sees the side c points away from
  ls.li = l.color * ieee_div(abs(cos_l) * 0.5f * area2, d2);
  if (l.cos_inner > 0.5f && !(cos_l < 0.0f)) ls.li = vec3(0.0f);  // one-sided, seen from behind
  ls.shadow = shadow_ray_to(s.p, s.ng, q, ieee_div(cos_l > 0.0f ? -c : c, area2));
  // The pdf as a BSDF ray would see q: from the offset origin that ray leaves (hit_light_pdf).
  const vec3 from_origin = q - ls.shadow.origin;
  ls.dist = ieee_length(from_origin);
  ls.pdf = triangle_solid_angle_pdf(area2, ieee_div(ieee_dot(c, from_origin), ls.dist * area2), ls.dist);
  return ls;
}

// Point and spot lights (intensity l.color, spot cones from l.dir): the shadow ray ends just
// short of the light's position.
HRPP_INLINE LightSample sample_point_light(GpuLight l, SurfaceHit s) {
  const vec3 to = l.position - s.p;
  const float d2 = ieee_dot(to, to);
  LightSample ls;
  ls.wi = ieee_div(to, ieee_sqrt(d2));
  ls.li = ieee_div(l.color, d2);
  ls.pdf = 0.0f;
  ls.dist = 0.0f;
  if (l.type == HRPP_LIGHT_SPOT)
    ls.li *= smoothstep(l.cos_outer, l.cos_inner, ieee_dot(-ls.wi, l.dir));
  ls.shadow = shadow_ray_to(s.p, s.ng, l.position, vec3(0.0f));
  return ls;
}

// One sample of light l for next-event estimation from s. Directional lights (irradiance
// l.color, travelling along l.dir): a shadow ray to infinity.
HRPP_INLINE LightSample sample_light(GpuLight l, SurfaceHit s, float u1, float u2) {
  if (kEmissiveTriangles && l.type == HRPP_LIGHT_TRIANGLE)
    return sample_triangle_light(l, s, u1, u2);
  if ((kPointLights && l.type == HRPP_LIGHT_POINT) || (kSpotLights && l.type == HRPP_LIGHT_SPOT))
    return sample_point_light(l, s);
  LightSample ls;
  ls.wi = -l.dir;
  ls.li = kDirectionalLights && l.type == HRPP_LIGHT_DIRECTIONAL ? l.color : vec3(0.0f);
  ls.pdf = 0.0f;
  ls.dist = 0.0f;
  ls.shadow = ray_from(offset_ray_origin(s.p, s.ng), ls.wi, float(HRPP_RAY_TMAX_FAR));
  return ls;
}

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_LIGHT_SAMPLE_H
