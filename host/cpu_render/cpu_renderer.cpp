#include "cpu_render/cpu_renderer.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "common/error.h"
#include "common/task_pool.h"
#include "cpu_render/scene_lookups.h"
#include "hrpp/reference_predictor.h"
#include "path_vertex.h"
#include "render/ray_stat_layers.h"
#include "render/render_params.h"
#include "render/render_result.h"
#include "trace/cpu_traversal.h"

namespace hrpp {
namespace {

using gpu::vec3;

// Pixels per task of a sample pass: consecutive pixels, handed out to the pool's threads
// dynamically (paths differ in length).
constexpr std::uint32_t kPixelBlock = 256;

struct PathTracer {
  const GpuBvh& bvh;
  const RenderScene& rs;
  const gpu::RenderParams& params;
  PerClass<RayClassStats>& stats;
  ReferencePredictor* hrpp;  // this thread's tables; nullptr: HRPP off
  const PredictorConfig& predictor;
  const OutsideTracer& outside;
  RayStatLayers* layers;         // nullptr: no per-pixel statistics
  std::uint32_t path_pixel = 0;  // the pixel of the path being traced (layers)

  // trace_ray, its counters added to the path's pixel in `layers`.
  gpu::Hit trace(const gpu::Ray& ray, RayClass c) {
    if (!layers) return trace_ray(ray, c);
    const RayClassStats& s = stats[c];
    const RayStatLayers::Counts before{s.counters, s.predictor};
    const gpu::Hit hit = trace_ray(ray, c);
    layers->add(path_pixel, c, before, {s.counters, s.predictor});
    return hit;
  }

  // trace_closest / trace_any (or the outside tracer's), or with HRPP on for a predicting class,
  // HRPP inline (the reference predictor's code: probe, verify, fall back, insert) before it.
  gpu::Hit trace_ray(const gpu::Ray& ray, RayClass c) {
    RayClassStats& s = stats[c];
    if (hrpp && predictor.predicts(c)) return hrpp->trace_one(ray, c, s.counters, s.predictor);
    if (outside.closest) return trace_outside(ray, c, s.counters);
    return query_kind(c) == QueryKind::kAny
               ? (trace_any(bvh, ray, &s.counters) ? gpu::Hit{0, 0.0f, 0.0f, 0.0f} : kMiss)
               : trace_closest(bvh, ray, &s.counters);
  }

  gpu::Hit trace_outside(const gpu::Ray& ray, RayClass c, TraversalCounters& counters) const {
    ++counters.rays;
    const gpu::Hit h = query_kind(c) == QueryKind::kAny
                           ? (outside.occluded(ray) ? gpu::Hit{0, 0.0f, 0.0f, 0.0f} : kMiss)
                           : outside.closest(ray);
    if (h.prim >= 0) ++counters.hits;
    return h;
  }

  // render_shade's next-event estimation: the payload render_accumulate adds when trace_any
  // finds the shadow ray unoccluded.
  void add_light(const gpu::PathState& path, const gpu::Lobe& lobe, const gpu::SurfaceHit& s,
                 vec3 wo, const gpu::VertexSamples& u, glm::vec4& pixel) {
    if (lobe.delta || params.light_count == 0u) return;
    float prob = 0.0f;
    const gpu::GpuLight& light = rs.lights[pick_light(rs, u.light, prob)];
    const gpu::LightSample ls = gpu::sample_light(light, s, u.light_u1, u.light_u2);
    const vec3 contribution =
        gpu::light_contribution(path, lobe, s, wo, ls, prob, params.light_strategy);
    if (!gpu::traces_shadow_ray(contribution, ls)) return;
    if (trace(ls.shadow, RayClass::kShadow).prim < 0)
      pixel += glm::vec4(contribution, 0.0f);
  }

  // One path vertex at a hit (render_shade): adds what it sees to `pixel`; false when the path
  // ends, otherwise ray and path become the continuation's.
  bool shade_hit(gpu::Ray& ray, const gpu::Hit& hit, gpu::PathState& path, glm::vec4& pixel) {
    const gpu::ShadeTriangle t = rs.shading.triangle(static_cast<std::size_t>(hit.prim));
    const gpu::SurfaceHit s = gpu::make_surface_hit(t, hit, ray.dir);
    gpu::GpuMaterial m = rs.materials[s.material];
    if (gpu::kMaterialTextures) m = textured_material(rs, m, s.uv);
    const vec3 wo = -ray.dir;
    vec3 radiance(0.0f);
    const vec3 emission = gpu::emission_toward(m, t, ray.dir);
    if (gpu::kEmissiveTriangles && emission != vec3(0.0f)) {
      const float pick = t.light > 0u ? pick_prob(rs, t.light - 1u) : 0.0f;
      const float light_pdf = gpu::hit_light_pdf(t, pick, ray.dir, hit.t);
      const bool bsdf_sees = gpu::bsdf_sees_light_at(ray.origin, hit.t);
      radiance += path.throughput * emission *
                  gpu::emission_weight(params.light_strategy, path, bsdf_sees, light_pdf);
    }
    if (radiance != vec3(0.0f)) pixel += glm::vec4(radiance, 0.0f);
    if (gpu::closes_path(path, params.max_depth)) return false;
    vec3 albedo = m.base_color * s.color;
    if (gpu::kTextures && m.texture >= 0) albedo *= sample_texture(rs, m.texture, s.uv, true);
    const gpu::VertexSamples u = gpu::vertex_samples(path, params.seed, params.sampler_kind);
    const gpu::Lobe lobe = gpu::choose_lobe(m, albedo, gpu::ieee_dot(s.ns, wo), u.lobe);
    add_light(path, lobe, s, wo, u, pixel);
    const gpu::Bounce b = gpu::sample_bounce(lobe, m, s, wo, u.u1, u.u2);
    vec3 throughput = path.throughput * b.weight;
    if (!gpu::survives(throughput, path.depth + 1u, params.rr_depth, u.rr)) return false;
    ray = gpu::continuation_ray(s, b);
    path = gpu::continuation_path(path, throughput, lobe, b);
    return true;
  }

  // The path of one pixel and sample, from the camera to its end (render_generate, then
  // trace_closest and render_shade per bounce).
  void trace_path(std::uint32_t pixel_index, std::uint32_t sample, glm::vec4& pixel) {
    path_pixel = pixel_index;
    gpu::Ray ray = gpu::camera_ray(params, pixel_index, sample);
    gpu::PathState path = gpu::camera_path(pixel_index, sample);
    for (;;) {
      const RayClass cls = path.depth == 0 ? RayClass::kCamera : RayClass::kBounce;
      const gpu::Hit hit = trace(ray, cls);
      if (hit.prim < 0) {
        vec3 radiance(0.0f);
        if (gpu::kEnvironment) radiance += path.throughput * vec3(params.environment);
        if (radiance != vec3(0.0f)) pixel += glm::vec4(radiance, 0.0f);
        return;
      }
      if (!shade_hit(ray, hit, path, pixel)) return;
    }
  }
};

}  // namespace

CpuRenderer::CpuRenderer(const Scene& scene, const GpuBvh& bvh, const RenderConfig& config,
                         OutsideTracer outside)
    : bvh_(bvh),
      cfg_((check_render_config(config, scene), config)),
      outside_(std::move(outside)),
      rs_(make_render_scene(scene, config.default_lighting)),
      params_(make_render_params(cfg_, scene.cameras[cfg_.camera], rs_, 0)) {
  if (static_cast<bool>(outside_.closest) != static_cast<bool>(outside_.occluded))
    throw Error("CpuRenderer: an outside tracer needs both its closest and its occluded query");
}

int CpuRenderer::threads() { return resolve_threads(0); }

RenderResult CpuRenderer::render(PassObserver* observer) const {
  const auto start = std::chrono::steady_clock::now();
  RenderResult out = make_render_result(cfg_, rs_);
  const std::uint32_t pixels = cfg_.width * cfg_.height;
  std::vector<glm::vec4> sum(pixels, glm::vec4(0.0f));
  TaskPool pool(threads());
  const std::size_t blocks = chunks(pixels, kPixelBlock);
  // HRPP on: tables per thread, kept from sample to sample (no locks, no sharing).
  std::vector<ReferencePredictor> tables;
  if (cfg_.predictor.enabled)
    for (int t = 0; t < pool.size(); ++t) {
      tables.emplace_back(bvh_, cfg_.predictor);
      if (outside_.closest) tables.back().set_full_trace(outside_.closest);
    }
  const auto first_pass = std::chrono::steady_clock::now();
  std::unique_ptr<RayStatLayers> layers;
  if (cfg_.ray_stats) layers = std::make_unique<RayStatLayers>(pixels);
  PerClass<bool> predicting;
  for (RayClass c : kRayClasses) predicting[c] = cfg_.predictor.predicts(c);
  auto finish = [&](RenderResult& r) {  // the mean image (and layers) of the passes so far
    const auto samples = static_cast<std::uint32_t>(out.stats.frames.size());
    set_mean_image(r, sum, samples);
    if (layers) r.channels = layers->channels(samples, predicting, cfg_.predictor.count_baseline);
  };
  auto mean_so_far = [&] {
    RenderResult r = out;
    finish(r);
    return r;
  };
  for (std::uint32_t sample = 0; sample < cfg_.spp; ++sample) {
    const auto frame_start = std::chrono::steady_clock::now();
    std::vector<PerClass<RayClassStats>> stats(static_cast<std::size_t>(pool.size()));
    pool.parallel_for(blocks, [&](std::size_t block, int thread) {
      const auto t = static_cast<std::size_t>(thread);
      PathTracer tracer{bvh_, rs_, params_, stats[t], tables.empty() ? nullptr : &tables[t],
                        cfg_.predictor, outside_, layers.get()};
      const auto begin = static_cast<std::uint32_t>(block * kPixelBlock);
      const std::uint32_t end = std::min(pixels, begin + kPixelBlock);
      for (std::uint32_t p = begin; p < end; ++p) tracer.trace_path(p, sample, sum[p]);
    });
    FrameStats frame;
    for (const auto& s : stats)
      for (RayClass k : kRayClasses) frame.classes[k] += s[k];
    frame.wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - frame_start).count();
    out.stats += frame;
    out.stats.frames.push_back(std::move(frame));
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - first_pass).count();
    if (observer && !observer->after_pass(sample + 1, elapsed, mean_so_far)) break;
  }
  finish(out);
  out.stats.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace hrpp
