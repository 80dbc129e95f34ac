// The lobes of a material and the one a path vertex samples: glTF's metallic-roughness BRDF as
// its specification's Appendix B defines it. The metal (GGX, Schlick's Fresnel from the base
// colour to 1) is picked with probability `metallic`, else the dielectric: its specular layer
// (GGX, Schlick's Fresnel from specular_f0 to specular_f90, KHR_materials_specular) or the
// diffuse under it (Lambert × (1 - max F(wo·h))), one of the two picked with a probability its
// weight divides back out. Glass (transmission) replaces both. Each pick is made before the
// vertex's light sample, which then weighs the picked lobe alone against light sampling (MIS),
// as the continuation does: an unbiased estimate of the mixture. α = roughness².
// Shared by render_shade and the CPU reference renderer (glsl_cpp.h).
#ifndef HRPP_MATERIAL_LOBES_H
#define HRPP_MATERIAL_LOBES_H

#include "bsdf.h"
#include "glsl_cpp.h"
#include "render_interface.h"
#include "surface_hit.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

const uint kLobeDiffuse = 0u;
const uint kLobeMetal = 1u;
const uint kLobeGlass = 2u;
const uint kLobeSpecular = 3u;  // the dielectric's specular layer

// The least probability of either of a dielectric's two lobes when it has a specular layer.
const float kMinLayerProb = 0.1f;

// The lobe a vertex samples (one of the material's, picked with u_lobe) and its parameters.
struct Lobe {
  uint kind;  // kLobe*
  bool delta;  // a mirror or glass: no light sample can land in it
  vec3 albedo;  // base colour × texture
  float alpha;  // GGX roughness parameter
  // Schlick's Fresnel of the GGX lobe (the metal's: albedo to 1) or of the specular layer over
  // the diffuse (f90 0: none).
  vec3 f0;
  float f90;
  float weight;  // 1 / the probability of picking this lobe within the dielectric; else 1
};

HRPP_INLINE float max_channel(vec3 v) { return max(v.x, max(v.y, v.z)); }

// glTF's metallicRoughnessTexture at a vertex: its (linear) texel's B channel scales metallic,
// its G channel roughness.
HRPP_INLINE GpuMaterial with_metallic_roughness(GpuMaterial m, vec3 texel) {
  m.metallic *= texel.z;
  m.roughness *= texel.y;
  return m;
}

// The probability with which a dielectric's vertex samples its specular layer: the layer's
// Fresnel at n·wo against the diffuse's share under it, kept within kMinLayerProb of 0 and 1;
// 0 without a layer.
HRPP_INLINE float specular_layer_prob(GpuMaterial m, vec3 albedo, float n_o) {
  if (!kSpecularLayer || !(m.specular_f90 > 0.0f)) return 0.0f;
  const float f = max_channel(fresnel_schlick(m.specular_f0, m.specular_f90, max(n_o, 0.0f)));
  const float d = (1.0f - f) * max_channel(albedo);
  const float p = f + d > 0.0f ? ieee_div(f, f + d) : 0.5f;
  return clamp(p, kMinLayerProb, 1.0f - kMinLayerProb);
}

// n_o: n·wo at the vertex (the shading normal's).
HRPP_INLINE Lobe choose_lobe(GpuMaterial m, vec3 albedo, float n_o, float u_lobe) {
  Lobe l;
  l.kind = kLobeDiffuse;
  l.albedo = albedo;
  l.alpha = max(m.roughness * m.roughness, 1e-4f);
  l.f0 = vec3(0.0f);
  l.f90 = 0.0f;
  l.weight = 1.0f;
  if (kGlass && m.transmission > 0.5f) {
    l.kind = kLobeGlass;
  } else if (kMetal && u_lobe < m.metallic) {
    l.kind = kLobeMetal;
    l.f0 = albedo;
    l.f90 = 1.0f;
  } else if (kSpecularLayer && m.specular_f90 > 0.0f) {
    const float p = specular_layer_prob(m, albedo, n_o);
    const float u = ieee_div(u_lobe - m.metallic, 1.0f - m.metallic);  // uniform in [0, 1)
    l.kind = u < p ? kLobeSpecular : kLobeDiffuse;
    l.weight = ieee_div(1.0f, u < p ? p : 1.0f - p);
    l.f0 = m.specular_f0;
    l.f90 = m.specular_f90;
  }
  l.delta = l.kind == kLobeGlass || (l.kind != kLobeDiffuse && m.roughness < kMirrorRoughness);
  return l;
}

HRPP_INLINE bool is_ggx_lobe(Lobe lobe) {
  return (kMetal && lobe.kind == kLobeMetal) || (kSpecularLayer && lobe.kind == kLobeSpecular);
}

// What the specular layer lets through to the diffuse for the pair (wo, wi): 1 - max F(wo·h),
// h their half vector (Appendix B's fresnel_mix); 1 without a layer.
HRPP_INLINE float under_layer(Lobe lobe, vec3 wo, vec3 wi) {
  if (!kSpecularLayer || !(lobe.f90 > 0.0f)) return 1.0f;
  const vec3 h = ieee_normalize(wo + wi);
  return 1.0f - max_channel(fresnel_schlick(lobe.f0, lobe.f90, max(ieee_dot(wo, h), 0.0f)));
}

// f · cos(wi) of the chosen lobe, times its weight (the metal's choice probability cancels its
// mixture weight).
HRPP_INLINE vec3 eval_lobe_cos(Lobe lobe, SurfaceHit s, vec3 wo, vec3 wi) {
  if (ieee_dot(wi, s.ng) <= 0.0f) return vec3(0.0f);
  if (is_ggx_lobe(lobe))
    return ggx_eval_cos(s.ns, wo, wi, lobe.f0, lobe.f90, lobe.alpha) * lobe.weight;
  return lobe.albedo * ieee_div(max(ieee_dot(s.ns, wi), 0.0f), kPi) *
         (under_layer(lobe, wo, wi) * lobe.weight);
}

// The pdf with which the lobe's sampling (sample_bounce) draws wi (solid angle; delta: 0).
HRPP_INLINE float lobe_pdf(Lobe lobe, SurfaceHit s, vec3 wo, vec3 wi) {
  if (lobe.delta) return 0.0f;
  if (is_ggx_lobe(lobe)) return ggx_pdf(s.ns, wo, wi, lobe.alpha);
  return ieee_div(max(ieee_dot(s.ns, wi), 0.0f), kPi);
}

// The continuation of a path: its direction, the lobe's f·cos/pdf, the pdf (solid angle;
// delta lobes: 0) and the geometric normal on the side it leaves into (zero weight: the path
// ends).
struct Bounce {
  vec3 wi;
  vec3 weight;
  float pdf;
  vec3 leave_normal;
};

HRPP_INLINE Bounce sample_bounce(Lobe lobe, GpuMaterial m, SurfaceHit s, vec3 wo, float u1,
                                 float u2) {
  Bounce b;
  b.wi = vec3(0.0f);
  b.weight = vec3(0.0f);
  b.pdf = 0.0f;
  b.leave_normal = s.ng;
  if (kGlass && lobe.kind == kLobeGlass) {
    const float eta = s.front ? ieee_div(1.0f, m.ior) : m.ior;
    const float cos_i = ieee_dot(s.ns, wo);
    const float f = fresnel_dielectric(abs(cos_i), eta);
    if (u1 < f) {
      b.wi = reflect(-wo, s.ns);
      b.weight = vec3(1.0f);
    } else {
      b.wi = ieee_refract(-wo, s.ns, eta);
      b.weight = lobe.albedo;
      b.leave_normal = -s.ng;
    }
  } else if (is_ggx_lobe(lobe)) {
    if (lobe.delta) {
      b.wi = reflect(-wo, s.ns);
      b.weight = fresnel_schlick(lobe.f0, lobe.f90, max(ieee_dot(s.ns, b.wi), 0.0f)) * lobe.weight;
    } else {
      b.weight = ggx_sample(s.ns, wo, lobe.f0, lobe.f90, lobe.alpha, u1, u2, b.wi) * lobe.weight;
      b.pdf = ggx_pdf(s.ns, wo, b.wi, lobe.alpha);
    }
  } else {
    b.wi = cosine_hemisphere(s.ns, u1, u2);
    b.weight = lobe.albedo * (under_layer(lobe, wo, b.wi) * lobe.weight);
    b.pdf = ieee_div(max(ieee_dot(s.ns, b.wi), 0.0f), kPi);
  }
  // A direction on the wrong side of the geometric surface ends the path.
  if (ieee_dot(b.wi, b.leave_normal) <= 0.0f) b.weight = vec3(0.0f);
  return b;
}

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_MATERIAL_LOBES_H
