// render_shade: one path vertex per item of the wavefront. Misses add the environment; hits add
// emission (camera rays and after delta bounces only: every other bounce's light comes from
// next-event estimation), sample one light for a shadow ray (render_accumulate adds its payload
// when trace_any finds it unoccluded), and sample the material for the continuation ray, with
// Russian roulette. Lobes: shaders/lib/bsdf.glsl. Outputs are compacted with atomicAdd; every
// path owns its random stream, so the order in the queues does not change the image. The
// shadow queue's size also becomes the indirect dispatch arguments of trace_any and
// render_accumulate here (queue_dispatch_args), so no kernel runs between them.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "lib/render_bindings.glsl"
#include "lib/rng.glsl"
#include "lib/offset_ray.glsl"
#include "lib/bsdf.glsl"

struct SurfaceHit {
  vec3 p;
  vec3 ng;  // unit geometric normal facing the incoming ray
  vec3 ns;  // unit shading normal on the side of ng
  vec2 uv;
  bool front;  // the ray hit the side the triangle's winding faces (glass: entering)
  uint material;
};

vec3 fetch3(uint texel) { return uintBitsToFloat(texelFetch(shade_triangles, int(texel)).xyz); }

SurfaceHit surface_at(Hit h, vec3 dir) {
  const uint base = uint(h.prim) * 8u;
  const uvec4 t0 = texelFetch(shade_triangles, int(base));
  const uvec4 t1 = texelFetch(shade_triangles, int(base + 1u));
  const vec3 v0 = uintBitsToFloat(t0.xyz), v1 = uintBitsToFloat(t1.xyz), v2 = fetch3(base + 2u);
  const float w = 1.0 - h.u - h.v;
  SurfaceHit s;
  s.p = w * v0 + h.u * v1 + h.v * v2;  // from barycentrics, not o + t·d (offset_ray.h)
  const vec3 ng = normalize(cross(v1 - v0, v2 - v0));
  s.front = dot(ng, dir) < 0.0;
  s.ng = s.front ? ng : -ng;
  s.ns = s.ng;
  if (t1.w != 0u) {
    const vec3 n = w * fetch3(base + 3u) + h.u * fetch3(base + 4u) + h.v * fetch3(base + 5u);
    if (dot(n, n) > 0.0) {
      s.ns = normalize(n);
      if (dot(s.ns, s.ng) < 0.0) s.ns = -s.ns;
    }
  }
  const vec4 uv01 = uintBitsToFloat(texelFetch(shade_triangles, int(base + 6u)));
  const vec2 uv2 = uintBitsToFloat(texelFetch(shade_triangles, int(base + 7u)).xy);
  s.uv = w * uv01.xy + h.u * uv01.zw + h.v * uv2;
  s.material = t0.w;
  return s;
}

vec3 srgb_to_linear(vec3 c) {
  return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

// Bilinear, repeat wrap, texels decoded from sRGB (glTF base colour).
vec3 texel(GpuTexture t, int x, int y) {
  x = ((x % t.width) + t.width) % t.width;
  y = ((y % t.height) + t.height) % t.height;
  const vec4 c = unpackUnorm4x8(texels[t.offset + uint(y * t.width + x)]);
  return srgb_to_linear(c.rgb);
}

vec3 sample_texture(int index, vec2 uv) {
  const GpuTexture t = textures[index];
  const vec2 p = uv * vec2(t.width, t.height) - 0.5;
  const vec2 f = fract(p);
  const ivec2 i = ivec2(floor(p));
  return mix(mix(texel(t, i.x, i.y), texel(t, i.x + 1, i.y), f.x),
             mix(texel(t, i.x, i.y + 1), texel(t, i.x + 1, i.y + 1), f.x), f.y);
}

// Light index with probability cdf[i] - cdf[i - 1] (binary search; bounded by 32 steps).
uint pick_light(float u, out float prob) {
  uint lo = 0u, hi = params.light_count - 1u;
  for (int step = 0; step < 32 && lo < hi; ++step) {
    const uint mid = (lo + hi) / 2u;
    if (u < light_cdf(mid)) hi = mid; else lo = mid + 1u;
  }
  prob = light_cdf(lo) - (lo > 0u ? light_cdf(lo - 1u) : 0.0);
  return lo;
}

struct LightSample {
  vec3 wi;    // unit direction from the surface point to the light
  vec3 li;    // incident radiance × 1/pdf of the sample (zero: nothing to add)
  Ray shadow;  // from the surface point to the light, offset at both ends (offset_ray.glsl)
};

// A point uniformly on emissive triangle l (radiance l.color, two-sided) seen from s: the
// shadow ray ends just short of it, moved off the triangle towards s.
LightSample sample_triangle_light(GpuLight l, SurfaceHit s, float u1, float u2) {
  const float r = sqrt(u1);
  const vec3 q = l.position + r * (1.0 - u2) * l.dir + r * u2 * l.edge2;
  const vec3 c = cross(l.dir, l.edge2);
  const float area2 = length(c);
  const vec3 to = q - s.p;
  const float d2 = dot(to, to);
  LightSample ls;
  ls.wi = to / sqrt(d2);
  const float cos_l = dot(c, ls.wi) / area2;  // > 0: s sees the side c points away from
  ls.li = l.color * (abs(cos_l) * 0.5 * area2 / d2);
  ls.shadow = shadow_ray_to(s.p, s.ng, q, (cos_l > 0.0 ? -c : c) / area2);
  return ls;
}

// Point and spot lights (intensity l.color, spot cones from l.dir): the shadow ray ends just
// short of the light's position.
LightSample sample_point_light(GpuLight l, SurfaceHit s) {
  const vec3 to = l.position - s.p;
  const float d2 = dot(to, to);
  LightSample ls;
  ls.wi = to / sqrt(d2);
  ls.li = l.color / d2;
  if (l.type == HRPP_LIGHT_SPOT)
    ls.li *= smoothstep(l.cos_outer, l.cos_inner, dot(-ls.wi, l.dir));
  ls.shadow = shadow_ray_to(s.p, s.ng, l.position, vec3(0.0));
  return ls;
}

// One sample of light l for next-event estimation from s. Directional lights (irradiance
// l.color, travelling along l.dir): a shadow ray to infinity.
LightSample sample_light(GpuLight l, SurfaceHit s, float u1, float u2) {
  if (kEmissiveTriangles && l.type == HRPP_LIGHT_TRIANGLE)
    return sample_triangle_light(l, s, u1, u2);
  if ((kPointLights && l.type == HRPP_LIGHT_POINT) || (kSpotLights && l.type == HRPP_LIGHT_SPOT))
    return sample_point_light(l, s);
  LightSample ls;
  ls.wi = -l.dir;
  ls.li = kDirectionalLights && l.type == HRPP_LIGHT_DIRECTIONAL ? l.color : vec3(0.0);
  ls.shadow = Ray(offset_ray_origin(s.p, s.ng), 0.0, ls.wi, HRPP_RAY_TMAX_FAR);
  return ls;
}

const uint kLobeDiffuse = 0u;
const uint kLobeMetal = 1u;
const uint kLobeGlass = 2u;

// f · cos(wi) of the chosen lobe (the lobe choice probability cancels its mixture weight).
vec3 eval_lobe_cos(uint lobe, SurfaceHit s, vec3 wo, vec3 wi, vec3 albedo, float alpha) {
  if (dot(wi, s.ng) <= 0.0) return vec3(0.0);
  if (kMetal && lobe == kLobeMetal) return ggx_eval_cos(s.ns, wo, wi, albedo, alpha);
  return albedo * (max(dot(s.ns, wi), 0.0) / kPi);
}

uint groups(uint items, uint per_group) { return (items + per_group - 1u) / per_group; }

// The workgroups trace_any and render_accumulate need for the shadow rays queued so far: every
// slot below the largest one taken is filled, so the max over subgroups of (slot + 1) is the
// queue's size. One atomicMax per subgroup and argument. The host starts them at (0, 1, 1).
void queue_dispatch_args(uint slot_end) {
  const uint top = subgroupMax(slot_end);
  if (subgroupElect() && top != 0u) {
    atomicMax(queues.trace_any_groups[0], groups(top, params.trace_any_group_rays));
    atomicMax(queues.accumulate_groups[0], groups(top, HRPP_RENDER_WORKGROUP_SIZE));
  }
}

void main() {
  const uint i = gl_GlobalInvocationID.x;
  uint finished = 0u;
  uint shadow_end = 0u;  // slot + 1 of this path's shadow ray, 0: none
  if (i < pc.count) {
    finished = 1u;
    const Ray ray = load_ray(i);
    const Hit hit = load_hit(i);
    const PathState path = load_path(i);
    vec3 radiance = vec3(0.0);
    if (hit.prim < 0) {
      if (kEnvironment) radiance += path.throughput * params.environment.rgb;
    } else {
      const SurfaceHit s = surface_at(hit, ray.dir);
      const GpuMaterial m = load_material(s.material);
      const vec3 wo = -ray.dir;
      if ((path.depth == 0u || path.specular != 0u) && (kEmissiveTriangles))
        radiance += path.throughput * m.emission;
      vec3 albedo = m.base_color;
      if (kTextures && m.texture >= 0) albedo *= sample_texture(m.texture, s.uv);
      uint rng = rng_init(path.pixel, path.sample_index, path.depth, params.seed);
      uint lobe = kLobeDiffuse;
      const float u_lobe = rng_next(rng);
      if (kGlass && m.transmission > 0.5) lobe = kLobeGlass;
      else if (kMetal && u_lobe < m.metallic) lobe = kLobeMetal;
      const float alpha = max(m.roughness * m.roughness, 1e-4);
      const bool delta = lobe == kLobeGlass || (lobe == kLobeMetal && m.roughness < kMirrorRoughness);

      // Next-event estimation: one light, one shadow ray.
      const float u_light = rng_next(rng), u_l1 = rng_next(rng), u_l2 = rng_next(rng);
      if (!delta && params.light_count > 0u) {
        float prob;
        const LightSample ls = sample_light(load_light(pick_light(u_light, prob)), s, u_l1, u_l2);
        const vec3 contribution =
            path.throughput * eval_lobe_cos(lobe, s, wo, ls.wi, albedo, alpha) * ls.li / prob;
        // A shadow ray turned away from the light (offsets crossed, or p on the light): none.
        if (max(contribution.r, max(contribution.g, contribution.b)) > 0.0 &&
            dot(ls.shadow.dir, ls.wi) > 0.0) {
          const uint slot = atomicAdd(queues.shadow_rays, 1u);
          shadow_end = slot + 1u;
          shadow_rays[slot] = ls.shadow;
          shadows[slot] = ShadowRecord(contribution, path.pixel);
        }
      }

      // Continuation.
      const float u1 = rng_next(rng), u2 = rng_next(rng), u_rr = rng_next(rng);
      if (path.depth + 1u < params.max_depth) {
        vec3 wi = vec3(0.0);
        vec3 weight = vec3(0.0);
        vec3 leave_normal = s.ng;
        if (kGlass && lobe == kLobeGlass) {
          const float eta = s.front ? 1.0 / m.ior : m.ior;
          const float cos_i = dot(s.ns, wo);
          const float f = fresnel_dielectric(abs(cos_i), eta);
          if (u1 < f) {
            wi = reflect(-wo, s.ns);
            weight = vec3(1.0);
          } else {
            wi = refract(-wo, s.ns, eta);
            weight = albedo;
            leave_normal = -s.ng;
          }
        } else if (kMetal && lobe == kLobeMetal) {
          if (delta) {
            wi = reflect(-wo, s.ns);
            weight = fresnel_schlick(albedo, max(dot(s.ns, wi), 0.0));
          } else {
            weight = ggx_sample(s.ns, wo, albedo, alpha, u1, u2, wi);
          }
        } else {
          wi = cosine_hemisphere(s.ns, u1, u2);
          weight = albedo;
        }
        // A direction on the wrong side of the geometric surface ends the path.
        if (dot(wi, leave_normal) <= 0.0) weight = vec3(0.0);
        vec3 throughput = path.throughput * weight;
        bool alive = max(throughput.r, max(throughput.g, throughput.b)) > 0.0;
        if (alive && path.depth + 1u >= params.rr_depth) {
          const float q = min(max(throughput.r, max(throughput.g, throughput.b)), 0.95);
          alive = u_rr < q;
          throughput /= q;
        }
        if (alive) {
          const uint slot = atomicAdd(queues.next_rays, 1u);
          next_rays[slot] = Ray(offset_ray_origin(s.p, leave_normal), 0.0, wi, HRPP_RAY_TMAX_FAR);
          next_paths[slot] = PathState(throughput, path.pixel, path.sample_index, path.depth + 1u,
                                       delta ? 1u : 0u, 0u);
        }
      }
    }
    if (radiance != vec3(0.0)) image[path.pixel].xyz += radiance;
  }
  queue_dispatch_args(shadow_end);
  report_done(HRPP_RENDER_DONE_SHADE, finished);
}
