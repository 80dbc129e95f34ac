// The material lobes of the path tracer, in a local frame around the shading normal n:
// Lambertian diffuse, GGX microfacet reflection (Walter et al. 2007; visible-normal sampling,
// Heitz, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4), 2018; Schlick Fresnel
// between f0 and f90: glTF's metal and its dielectric's specular layer) and a smooth dielectric
// (exact Fresnel, reflect or refract). Vectors point away from the surface.
// Shared by render_shade and the CPU reference renderer (glsl_cpp.h).
#ifndef HRPP_BSDF_H
#define HRPP_BSDF_H

#include "glsl_cpp.h"
#include "gpu_types.h"  // vec3 on the host

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

const float kPi = 3.14159265358979f;
// Below this GGX roughness a metal is a perfect mirror (a delta lobe): the microfacet terms
// overflow float and no light sample could land in the lobe anyway.
const float kMirrorRoughness = 0.02f;

// Orthonormal basis around unit n (Duff et al., "Building an Orthonormal Basis, Revisited",
// JCGT 6(1), 2017).
HRPP_INLINE void basis(vec3 n, HRPP_OUT(vec3) t, HRPP_OUT(vec3) b) {
  const float s = n.z >= 0.0f ? 1.0f : -1.0f;
  const float a = ieee_div(-1.0f, s + n.z);
  const float c = n.x * n.y * a;
  t = vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
  b = vec3(c, s + n.y * n.y * a, -n.y);
}

HRPP_INLINE vec3 cosine_hemisphere(vec3 n, float u1, float u2) {
  vec3 t, b;
  basis(n, t, b);
  const float r = ieee_sqrt(u1);
  const float phi = 2.0f * kPi * u2;
  return ieee_normalize(r * cos(phi) * t + r * sin(phi) * b + ieee_sqrt(max(0.0f, 1.0f - u1)) * n);
}

// Schlick's Fresnel from f0 at normal incidence to f90 at grazing (glTF: f90 1 for a metal,
// specularFactor for a dielectric's layer).
HRPP_INLINE vec3 fresnel_schlick(vec3 f0, float f90, float cos_theta) {
  const float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0 + (vec3(f90) - f0) * (m2 * m2 * m);
}

// Unpolarised Fresnel reflectance of a smooth dielectric; eta = n_incident / n_transmitted.
HRPP_INLINE float fresnel_dielectric(float cos_i, float eta) {
  const float sin2_t = eta * eta * max(0.0f, 1.0f - cos_i * cos_i);
  if (sin2_t >= 1.0f) return 1.0f;  // total internal reflection
  const float cos_t = ieee_sqrt(1.0f - sin2_t);
  const float rs = ieee_div(eta * cos_i - cos_t, eta * cos_i + cos_t);
  const float rp = ieee_div(cos_i - eta * cos_t, cos_i + eta * cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

HRPP_INLINE float ggx_d(float n_h, float a2) {
  const float d = n_h * n_h * (a2 - 1.0f) + 1.0f;
  return ieee_div(a2, kPi * d * d);
}

// Smith G1 for GGX.
HRPP_INLINE float ggx_g1(float n_v, float a2) {
  return ieee_div(2.0f * n_v, n_v + ieee_sqrt(a2 + (1.0f - a2) * n_v * n_v));
}

// GGX reflection with Schlick's Fresnel (f0, f90): f(wo, wi) · cos(wi) for light sampling.
HRPP_INLINE vec3 ggx_eval_cos(vec3 n, vec3 wo, vec3 wi, vec3 f0, float f90, float alpha) {
  const float n_o = ieee_dot(n, wo), n_i = ieee_dot(n, wi);
  if (n_o <= 0.0f || n_i <= 0.0f) return vec3(0.0f);
  const vec3 h = ieee_normalize(wo + wi);
  const float a2 = alpha * alpha;
  const float d = ggx_d(max(ieee_dot(n, h), 0.0f), a2);
  const float g = ggx_g1(n_o, a2) * ggx_g1(n_i, a2);
  return fresnel_schlick(f0, f90, max(ieee_dot(wi, h), 0.0f)) * ieee_div(d * g, 4.0f * n_o);
}

// GGX reflection: the solid-angle pdf with which ggx_sample draws wi (visible normals):
// G1(wo) D(h) / (4 n·wo).
HRPP_INLINE float ggx_pdf(vec3 n, vec3 wo, vec3 wi, float alpha) {
  const float n_o = ieee_dot(n, wo);
  const vec3 h = ieee_normalize(wo + wi);
  const float n_h = ieee_dot(n, h);
  if (n_o <= 0.0f || n_h <= 0.0f || ieee_dot(wo, h) <= 0.0f) return 0.0f;
  const float a2 = alpha * alpha;
  return ieee_div(ggx_g1(n_o, a2) * ggx_d(n_h, a2), 4.0f * n_o);
}

// GGX reflection: samples wi from the visible normals; returns f·cos/pdf = F · G1(wi), or 0
// when wi falls below the surface.
HRPP_INLINE vec3 ggx_sample(vec3 n, vec3 wo, vec3 f0, float f90, float alpha, float u1, float u2,
                            HRPP_OUT(vec3) wi) {
  vec3 t, b;
  basis(n, t, b);
  const vec3 v = vec3(ieee_dot(wo, t), ieee_dot(wo, b), ieee_dot(wo, n));
  // Heitz 2018, listing 1: stretch, sample the projected disk, unstretch.
  const vec3 vh = ieee_normalize(vec3(alpha * v.x, alpha * v.y, v.z));
  const float len2 = vh.x * vh.x + vh.y * vh.y;
  const vec3 t1 =
      len2 > 0.0f ? vec3(-vh.y, vh.x, 0.0f) * ieee_inversesqrt(len2) : vec3(1.0f, 0.0f, 0.0f);
  const vec3 t2 = ieee_cross(vh, t1);
  const float r = ieee_sqrt(u1);
  const float phi = 2.0f * kPi * u2;
  const float p1 = r * cos(phi);
  float p2 = r * sin(phi);
  const float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * ieee_sqrt(max(0.0f, 1.0f - p1 * p1)) + s * p2;
  const vec3 nh = p1 * t1 + p2 * t2 + ieee_sqrt(max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  const vec3 m = ieee_normalize(vec3(alpha * nh.x, alpha * nh.y, max(0.0f, nh.z)));
  const vec3 h = m.x * t + m.y * b + m.z * n;
  wi = reflect(-wo, h);
  const float n_i = ieee_dot(n, wi);
  if (n_i <= 0.0f) return vec3(0.0f);
  return fresnel_schlick(f0, f90, max(ieee_dot(wi, h), 0.0f)) * ggx_g1(n_i, alpha * alpha);
}

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_BSDF_H
