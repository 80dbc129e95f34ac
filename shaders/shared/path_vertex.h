// One vertex of a path, the decisions render_shade makes at a hit: the random numbers it
// draws, the light it adds through next-event estimation (through the lobe material_lobes.h
// picks), the direction it continues in and Russian roulette, and the multiple importance
// sampling weights of the light it sees; and the camera ray render_generate starts a path with.
// Shared by the render kernels and the CPU reference renderer (glsl_cpp.h): what differs
// between the two is only how they read the scene's arrays and queue the rays.
#ifndef HRPP_PATH_VERTEX_H
#define HRPP_PATH_VERTEX_H

#include "glsl_cpp.h"
#include "light_sample.h"
#include "material_lobes.h"
#include "render_interface.h"
#include "rng.h"
#include "sobol_sampler.h"
#include "surface_hit.h"

#ifdef __cplusplus
namespace hrpp::gpu {
#endif

// The position of sample `sample_index` in its pixel: a Sobol pair, or the path's own stream
// (depth 0xFFFFFFFF, apart from every vertex's).
HRPP_INLINE vec2 pixel_jitter(RenderParams params, uint pixel, uint sample_index) {
  if (params.sampler_kind == HRPP_SAMPLER_SOBOL)
    return sobol_pair(sample_index, sobol_stream(pixel, 0xFFFFFFFFu, 0u, params.seed));
  uint rng = rng_init(pixel, sample_index, 0xFFFFFFFFu, params.seed);
  const float jx = rng_next(rng);
  return vec2(jx, rng_next(rng));
}

// The camera ray of pixel `pixel` for sample `sample_index`: pinhole camera, the position in
// the pixel jittered (pixel_jitter).
HRPP_INLINE Ray camera_ray(RenderParams params, uint pixel, uint sample_index) {
  const uint x = pixel % params.width;
  const uint y = pixel / params.width;
  const vec2 j = pixel_jitter(params, pixel, sample_index);
  const float sx = ieee_div(float(x) + j.x, float(params.width));
  const float sy = ieee_div(float(y) + j.y, float(params.height));
  const float tan_half = params.cam_position.w;
  const float aspect = params.cam_forward.w;
  const vec3 d = vec3(params.cam_forward) +
                 (2.0f * sx - 1.0f) * tan_half * aspect * vec3(params.cam_right) +
                 (1.0f - 2.0f * sy) * tan_half * vec3(params.cam_up);  // image rows top down
  return ray_from(vec3(params.cam_position), ieee_normalize(d), float(HRPP_RAY_TMAX_FAR));
}

// A path of pixel and sample at depth `depth` carrying `throughput`; specular: 1 after a delta
// bounce; pdf: the solid-angle pdf of the BSDF sample that made its ray.
HRPP_INLINE PathState path_state(vec3 throughput, uint pixel, uint sample_index, uint depth,
                                 uint specular, float pdf) {
  PathState p;
  p.throughput = throughput;
  p.pixel = pixel;
  p.sample_index = sample_index;
  p.depth = depth;
  p.specular = specular;
  p.pdf = pdf;
  return p;
}

HRPP_INLINE PathState camera_path(uint pixel, uint sample_index) {
  return path_state(vec3(1.0f), pixel, sample_index, 0u, 0u, 0.0f);
}

// The random numbers of one vertex, drawn from its stream in this order whatever is used.
struct VertexSamples {
  float lobe;
  float light;     // which light
  float light_u1;  // where on it
  float light_u2;
  float u1;  // the continuation direction
  float u2;
  float rr;  // Russian roulette
};

// A vertex's samples from `sampler_kind` (HRPP_SAMPLER_*): Sobol pairs (lobe, light), (light_u1,
// light_u2), (u1, u2), (rr, -), each its own stream, or one independent stream.
HRPP_INLINE VertexSamples vertex_samples(PathState path, uint seed, uint sampler_kind) {
  VertexSamples u;
  if (sampler_kind == HRPP_SAMPLER_SOBOL) {
    const vec2 a = sobol_pair(path.sample_index, sobol_stream(path.pixel, path.depth, 0u, seed));
    const vec2 b = sobol_pair(path.sample_index, sobol_stream(path.pixel, path.depth, 1u, seed));
    const vec2 c = sobol_pair(path.sample_index, sobol_stream(path.pixel, path.depth, 2u, seed));
    const vec2 d = sobol_pair(path.sample_index, sobol_stream(path.pixel, path.depth, 3u, seed));
    u.lobe = a.x;
    u.light = a.y;
    u.light_u1 = b.x;
    u.light_u2 = b.y;
    u.u1 = c.x;
    u.u2 = c.y;
    u.rr = d.x;
    return u;
  }
  uint rng = rng_init(path.pixel, path.sample_index, path.depth, seed);
  u.lobe = rng_next(rng);
  u.light = rng_next(rng);
  u.light_u1 = rng_next(rng);
  u.light_u2 = rng_next(rng);
  u.u1 = rng_next(rng);
  u.u2 = rng_next(rng);
  u.rr = rng_next(rng);
  return u;
}

// Multiple importance sampling (Veach and Guibas 1995): the power heuristic's weight of a sample
// drawn with pdf `a` against the other strategy's pdf `b` for the same direction, written so that
// it neither overflows nor divides by zero; w(a, b) + w(b, a) = 1 for any a, b > 0.
HRPP_INLINE float mis_power(float a, float b) {
  if (!(a > 0.0f)) return 0.0f;
  const float r = ieee_div(b, a);
  return ieee_div(1.0f, 1.0f + r * r);
}

// A BSDF ray leaves from its vertex moved off the surface (offset_ray.glsl: up to 256 ULPs of
// the coordinates, 2^-16 near 0), so it sees an emitter as a point nearer to it would: too
// bright by about the offset's share of the distance (2% of it: +0.7% on the direct light of a
// ceiling 10 cm above a light, 100 units from the origin). Where the offset exceeds
// 1/kBsdfOffsetRatio of the distance to the light point, light sampling, which measures from the
// vertex itself, takes the whole estimate: exact, at the cost of its noise near emitters (the
// closed-form tests in light_transport_test.cpp). Both strategies decide from the same origin
// (the shadow ray's is the BSDF ray's) and distance, so their weights still sum to one.
const float kBsdfOffsetRatio = 64.0f;

HRPP_INLINE bool bsdf_sees_light_at(vec3 origin, float dist) {
  const float coordinate = max(abs(origin.x), max(abs(origin.y), abs(origin.z)));
  const float offset = max(coordinate * (1.0f / 32768.0f), 1.0f / 65536.0f);
  return dist >= kBsdfOffsetRatio * offset;
}

// The weight of a next-event sample of an area light (light_pdf: solid angle, its pick
// included) against the BSDF's pdf of the same direction, under HRPP_LIGHTS_* `strategy`
// (`bsdf_sees`: bsdf_sees_light_at). Every vertex, the last included, also traces its BSDF
// sample (closes_path), so the two strategies always share the estimate.
HRPP_INLINE float nee_weight(uint strategy, bool bsdf_sees, float light_pdf, float bsdf_pdf) {
  if (strategy == HRPP_LIGHTS_NEE || !bsdf_sees) return 1.0f;
  if (strategy == HRPP_LIGHTS_BSDF) return 0.0f;
  return mis_power(light_pdf, bsdf_pdf);
}

// The weight of the emission a path's ray finds at a hit, whose pdf under light sampling is
// `light_pdf` (solid angle, pick included; 0: the emitter is not a light, which only BSDF
// samples find). Camera rays and rays after a delta bounce count it whole (no light sample
// could have found it); the others are nee_weight's complement.
HRPP_INLINE float emission_weight(uint strategy, PathState path, bool bsdf_sees, float light_pdf) {
  if (path.depth == 0u || path.specular != 0u || !(light_pdf > 0.0f)) return 1.0f;
  if (strategy == HRPP_LIGHTS_NEE || !bsdf_sees) return 0.0f;
  if (strategy == HRPP_LIGHTS_BSDF) return 1.0f;
  return mis_power(path.pdf, light_pdf);
}

// Light sampling's pdf of the direction in which a ray found emissive triangle t at distance
// `dist` (solid angle), with `pick` the probability of picking its light (0: not a light).
HRPP_INLINE float hit_light_pdf(ShadeTriangle t, float pick, vec3 dir, float dist) {
  if (!(pick > 0.0f)) return 0.0f;
  const vec3 c = ieee_cross(t.v1 - t.v0, t.v2 - t.v0);
  const float area2 = ieee_length(c);
  return pick * triangle_solid_angle_pdf(area2, ieee_div(ieee_dot(c, dir), area2), dist);
}

// The emission a ray along dir finds on triangle t of material m: a one-sided material emits
// only from its front, the side cross(v1 - v0, v2 - v0) points to.
HRPP_INLINE vec3 emission_toward(GpuMaterial m, ShadeTriangle t, vec3 dir) {
  if ((m.flags & HRPP_MATERIAL_ONE_SIDED) != 0u &&
      !(ieee_dot(ieee_cross(t.v1 - t.v0, t.v2 - t.v0), dir) < 0.0f))
    return vec3(0.0f);
  return m.emission;
}

// Next-event estimation: what light sample ls (of a light picked with probability prob) adds
// through the path's vertex at s when its shadow ray is unoccluded, with its MIS weight
// (nee_weight; delta lights: 1).
HRPP_INLINE vec3 light_contribution(PathState path, Lobe lobe, SurfaceHit s, vec3 wo,
                                    LightSample ls, float prob, uint strategy) {
  const bool bsdf_sees = bsdf_sees_light_at(ls.shadow.origin, ls.dist);
  const float w = ls.pdf > 0.0f ? nee_weight(strategy, bsdf_sees, prob * ls.pdf,
                                             lobe_pdf(lobe, s, wo, ls.wi))
                                : 1.0f;
  return path.throughput * eval_lobe_cos(lobe, s, wo, ls.wi) * ls.li * ieee_div(w, prob);
}

// A shadow ray is traced only when it carries light; one turned away from the light (offsets
// crossed, or the point on the light) is not.
HRPP_INLINE bool traces_shadow_ray(vec3 contribution, LightSample ls) {
  return max(contribution.r, max(contribution.g, contribution.b)) > 0.0f &&
         ieee_dot(ls.shadow.dir, ls.wi) > 0.0f;
}

// A path whose ray left its last interaction (the max depth): that ray was the BSDF sample of
// the last vertex, so its hit adds the emission it finds (MIS-weighted against that vertex's
// light sample, as at every depth) and the environment on a miss, and the path ends there.
HRPP_INLINE bool closes_path(PathState path, uint max_depth) { return path.depth >= max_depth; }

// The throughput after the bounce, divided by the survival probability q when Russian
// roulette applies (from rr_depth interactions on); false: the path ends here. q is the square
// root of the throughput's largest channel, as in Cycles: a dim path lives longer than with q =
// the channel itself, at 0.7x that choice's variance per sample on the Cornell boxes
// (docs/VALIDATION.md, "... Russian roulette").
HRPP_INLINE bool survives(HRPP_INOUT(vec3) throughput, uint next_depth, uint rr_depth, float u_rr) {
  bool alive = max(throughput.r, max(throughput.g, throughput.b)) > 0.0f;
  if (alive && next_depth >= rr_depth) {
    const float q = min(ieee_sqrt(max(throughput.r, max(throughput.g, throughput.b))), 1.0f);
    alive = u_rr < q;
    throughput = ieee_div(throughput, q);
  }
  return alive;
}

HRPP_INLINE Ray continuation_ray(SurfaceHit s, Bounce b) {
  return ray_from(offset_ray_origin(s.p, b.leave_normal), b.wi, float(HRPP_RAY_TMAX_FAR));
}

HRPP_INLINE PathState continuation_path(PathState path, vec3 throughput, Lobe lobe, Bounce b) {
  return path_state(throughput, path.pixel, path.sample_index, path.depth + 1u,
                    lobe.delta ? 1u : 0u, b.pdf);
}

#ifdef __cplusplus
}  // namespace hrpp::gpu
#endif

#endif  // HRPP_PATH_VERTEX_H
