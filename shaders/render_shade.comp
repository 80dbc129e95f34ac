// render_shade: one path vertex per item of the wavefront. Misses add the environment; hits add
// emission with its multiple importance sampling weight (emission_weight), sample one light for
// a shadow ray (render_accumulate adds its payload, MIS-weighted, when trace_any finds it
// unoccluded), and sample the material for the continuation ray, with Russian roulette. The
// decisions are shaders/shared/path_vertex.h, which the CPU reference renderer runs too; this
// kernel reads the scene's arrays and fills the queues. Outputs are compacted with atomicAdd;
// every path owns its random stream, so the order in the queues does not change the image. The
// shadow queue's size also becomes the indirect dispatch arguments of trace_any and
// render_accumulate here (queue_dispatch_args), so no kernel runs between them.
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require

#include "lib/render_bindings.glsl"
#include "path_vertex.h"

// Bilinear, repeat wrap, texels decoded from sRGB (glTF's colours) or linear (its data).
vec3 sample_texture(int index, vec2 uv, bool srgb) {
  const GpuTexture t = textures[index];
  const TextureFootprint f = texture_footprint(t, uv);
  return bilerp(decode_texel(texels[f.i00], srgb), decode_texel(texels[f.i10], srgb),
                decode_texel(texels[f.i01], srgb), decode_texel(texels[f.i11], srgb), f.f);
}

// Material m at uv: its metallic-roughness and emissive textures applied.
GpuMaterial textured_material(GpuMaterial m, vec2 uv) {
  if (m.metallic_roughness_texture >= 0)
    m = with_metallic_roughness(m, sample_texture(m.metallic_roughness_texture, uv, false));
  if (m.emissive_texture >= 0) m.emission *= sample_texture(m.emissive_texture, uv, true);
  return m;
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

// Next-event estimation: one light, one shadow ray. Returns its slot + 1 (0: none queued).
uint queue_shadow_ray(PathState path, Lobe lobe, SurfaceHit s, vec3 wo, VertexSamples u) {
  if (lobe.delta || params.light_count == 0u) return 0u;
  float prob;
  const GpuLight light = load_light(pick_light(u.light, prob));
  const LightSample ls = sample_light(light, s, u.light_u1, u.light_u2);
  const vec3 contribution = light_contribution(path, lobe, s, wo, ls, prob, params.light_strategy);
  if (!traces_shadow_ray(contribution, ls)) return 0u;
  const uint slot = atomicAdd(queues.shadow_rays, 1u);
  shadow_rays[slot] = ls.shadow;
  shadows[slot] = ShadowRecord(contribution, path.pixel);
  return slot + 1u;
}

void queue_continuation(PathState path, Lobe lobe, GpuMaterial m, SurfaceHit s, vec3 wo,
                        VertexSamples u) {
  const Bounce b = sample_bounce(lobe, m, s, wo, u.u1, u.u2);
  vec3 throughput = path.throughput * b.weight;
  if (!survives(throughput, path.depth + 1u, params.rr_depth, u.rr)) return;
  const uint slot = atomicAdd(queues.next_rays, 1u);
  next_rays[slot] = continuation_ray(s, b);
  next_paths[slot] = continuation_path(path, throughput, lobe, b);
}

// The emission the path's ray finds on triangle t, MIS-weighted.
vec3 hit_emission(Ray ray, Hit hit, PathState path, ShadeTriangle t, vec3 emission) {
  if (!kEmissiveTriangles || emission == vec3(0.0)) return vec3(0.0);
  const float pick = t.light > 0u ? light_pick_prob(t.light - 1u) : 0.0;
  const float light_pdf = hit_light_pdf(t, pick, ray.dir, hit.t);
  const bool bsdf_sees = bsdf_sees_light_at(ray.origin, hit.t);
  return path.throughput * emission *
         emission_weight(params.light_strategy, path, bsdf_sees, light_pdf);
}

// A path vertex at a hit: queues its shadow and continuation rays, returns the emission it
// sees; shadow_end as queue_shadow_ray returns it.
vec3 shade_hit(Ray ray, Hit hit, PathState path, out uint shadow_end) {
  const ShadeTriangle t = load_shade_triangle(uint(hit.prim));
  const SurfaceHit s = make_surface_hit(t, hit, ray.dir);
  GpuMaterial m = load_material(s.material);
  if (kMaterialTextures) m = textured_material(m, s.uv);
  const vec3 wo = -ray.dir;
  vec3 radiance = hit_emission(ray, hit, path, t, emission_toward(m, t, ray.dir));
  shadow_end = 0u;
  if (closes_path(path, params.max_depth)) return radiance;
  vec3 albedo = m.base_color * s.color;
  if (kTextures && m.texture >= 0) albedo *= sample_texture(m.texture, s.uv, true);
  const VertexSamples u = vertex_samples(path, params.seed, params.sampler_kind);
  const Lobe lobe = choose_lobe(m, albedo, ieee_dot(s.ns, wo), u.lobe);
  shadow_end = queue_shadow_ray(path, lobe, s, wo, u);
  queue_continuation(path, lobe, m, s, wo, u);
  return radiance;
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
      radiance = shade_hit(ray, hit, path, shadow_end);
    }
    if (radiance != vec3(0.0)) image[path.pixel].xyz += radiance;
  }
  queue_dispatch_args(shadow_end);
  report_done(HRPP_RENDER_DONE_SHADE, finished);
}
