// The surface a closest hit found: position, normals and texture coordinates interpolated from
// the triangle's shading data (ShadeTriangle), and the texture lookups of its base colour.
// Shared by render_shade and the CPU reference renderer (glsl_cpp.h); each side reads the
// arrays its own way and hands the records to these functions.
#ifndef HRPP_SURFACE_HIT_H
#define HRPP_SURFACE_HIT_H

#include "glsl_cpp.h"
#include "render_interface.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

// The attributes of a vertex the scene stores none for.
HRPP_INLINE ShadeAttributes default_shade_attributes() {
  ShadeAttributes a;
  a.normal_color = vec4(0.0f, 0.0f, 0.0f, HRPP_NO_VERTEX_COLOR);
  a.uv = vec4(0.0f);
  return a;
}

// The ShadeTriangle of a ShadeIndex and its corners' records (corner k: vertex vk, attributes ak).
HRPP_INLINE ShadeTriangle shade_triangle_of(ShadeIndex i, ShadeVertex v0, ShadeVertex v1,
                                            ShadeVertex v2, ShadeAttributes a0,
                                            ShadeAttributes a1, ShadeAttributes a2) {
  ShadeTriangle t;
  t.v0 = v0.position;
  t.material = i.material_data & HRPP_SHADE_MATERIAL_MASK;
  t.v1 = v1.position;
  t.vertex_data = i.material_data >> HRPP_SHADE_DATA_SHIFT;
  t.v2 = v2.position;
  t.light = v0.light;
  t.n0 = a0.normal_color;
  t.n1 = a1.normal_color;
  t.n2 = a2.normal_color;
  t.uv01 = vec4(a0.uv.x, a0.uv.y, a1.uv.x, a1.uv.y);
  t.uv2 = a2.uv;
  return t;
}

struct SurfaceHit {
  vec3 p;
  vec3 ng;  // unit geometric normal facing the incoming ray
  vec3 ns;  // unit shading normal on the side of ng
  vec2 uv;
  vec3 color;  // the interpolated vertex colour; white without vertex colours
  bool front;  // the ray hit the side the triangle's winding faces (glass: entering)
  uint material;
};

// A vertex colour stored as the float value of 0xBBGGRR (ShadeTriangle), as linear RGB.
HRPP_INLINE vec3 vertex_color(float packed) { return vec3(unpackUnorm4x8(uint(packed))); }

// Triangle t hit at barycentrics (h.u, h.v) by a ray along dir.
HRPP_INLINE SurfaceHit make_surface_hit(ShadeTriangle t, Hit h, vec3 dir) {
  const float w = 1.0f - h.u - h.v;
  SurfaceHit s;
  s.p = w * t.v0 + h.u * t.v1 + h.v * t.v2;  // from barycentrics, not o + t·d (offset_ray.h)
  const vec3 ng = ieee_normalize(ieee_cross(t.v1 - t.v0, t.v2 - t.v0));
  s.front = ieee_dot(ng, dir) < 0.0f;
  s.ng = s.front ? ng : -ng;
  s.ns = s.ng;
  if ((t.vertex_data & HRPP_VERTEX_NORMALS) != 0u) {
    const vec3 n = w * vec3(t.n0) + h.u * vec3(t.n1) + h.v * vec3(t.n2);
    if (ieee_dot(n, n) > 0.0f) {
      s.ns = ieee_normalize(n);
      if (ieee_dot(s.ns, s.ng) < 0.0f) s.ns = -s.ns;
    }
  }
  s.uv = w * vec2(t.uv01) + h.u * vec2(t.uv01.z, t.uv01.w) + h.v * vec2(t.uv2);
  s.color = vec3(1.0f);
  if ((t.vertex_data & HRPP_VERTEX_COLORS) != 0u) {
    s.color = w * vertex_color(t.n0.w) + h.u * vertex_color(t.n1.w) + h.v * vertex_color(t.n2.w);
  }
  s.material = t.material;
  return s;
}

HRPP_INLINE vec3 srgb_to_linear(vec3 c) {
  return mix(ieee_div(c, 12.92f), pow(ieee_div(c + 0.055f, 1.055f), vec3(2.4f)), greaterThan(c, vec3(0.04045f)));
}

// An RGBA8 texel (R in the low byte) as linear RGB: sRGB-encoded (glTF's base colour and
// emissive textures) or linear (its metallicRoughnessTexture).
HRPP_INLINE vec3 decode_texel(uint rgba8, bool srgb) {
  const vec3 c = vec3(unpackUnorm4x8(rgba8));
  return srgb ? srgb_to_linear(c) : c;
}

// The four texels of a bilinear lookup at uv (repeat wrap): their indices in the texel array,
// and the weights of the second column and row.
struct TextureFootprint {
  uint i00;
  uint i10;
  uint i01;
  uint i11;
  vec2 f;
};

HRPP_INLINE uint texel_index(GpuTexture t, int x, int y) {
  x = ((x % t.width) + t.width) % t.width;
  y = ((y % t.height) + t.height) % t.height;
  return t.offset + uint(y * t.width + x);
}

HRPP_INLINE TextureFootprint texture_footprint(GpuTexture t, vec2 uv) {
  const vec2 p = uv * vec2(t.width, t.height) - 0.5f;
  const ivec2 i = ivec2(floor(p));
  TextureFootprint f;
  f.i00 = texel_index(t, i.x, i.y);
  f.i10 = texel_index(t, i.x + 1, i.y);
  f.i01 = texel_index(t, i.x, i.y + 1);
  f.i11 = texel_index(t, i.x + 1, i.y + 1);
  f.f = fract(p);
  return f;
}

HRPP_INLINE vec3 bilerp(vec3 c00, vec3 c10, vec3 c01, vec3 c11, vec2 f) {
  return mix(mix(c00, c10, f.x), mix(c01, c11, f.x), f.y);
}

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_SURFACE_HIT_H
