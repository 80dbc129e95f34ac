#include "render/wavefront_renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>

#include "common/error.h"
#include "common/free_array.h"
#include "vk/compute_pipeline.h"
#include "gpu/device_tracer.h"
#include "front/gpu_predictor.h"
#include "front/make_device_tracer.h"
#include "vk/embedded_shaders.h"
#include "gpu/ray_sorter.h"
#include "vk/memory_plan.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"
#include "vk/vulkan_context.h"
#include "render/render_params.h"
#include "render/render_result.h"
#include "render_interface.h"

namespace hrpp {

namespace {

// check_render_config, and what the GPU renderer cannot do: per-pixel ray statistics need each
// ray's counters, which the GPU stage does not keep.
const RenderConfig& checked(const RenderConfig& config, const Scene& scene) {
  check_render_config(config, scene);
  if (config.ray_stats)
    throw Error("--ray-stats: the CPU backend's (--backend cpu); the GPU stage keeps no per-ray "
                "counters");
  return config;
}

constexpr auto kBindingTypes = [] {
  std::array<VkDescriptorType, HRPP_RENDER_BINDING_COUNT> t{};
  t.fill(VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  for (int b :
       {HRPP_RENDER_BINDING_SHADE_TRIANGLES, HRPP_RENDER_BINDING_SHADE_VERTICES,
        HRPP_RENDER_BINDING_SHADE_ATTRIBUTES, HRPP_RENDER_BINDING_HITS,
        HRPP_RENDER_BINDING_MATERIALS, HRPP_RENDER_BINDING_LIGHTS, HRPP_RENDER_BINDING_RAY_TEXELS,
        HRPP_RENDER_BINDING_PATH_TEXELS, HRPP_RENDER_BINDING_SHADOW_HITS})
    t[b] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  return t;
}();

// A scene array as a buffer (at least one element: Vulkan has no empty buffers).
template <class T>
BufferNeed array_need(const std::vector<T>& items, const char* name, BufferBinding binding) {
  return {name, std::max<std::size_t>(items.size(), 1) * sizeof(T), binding};
}

template <class T>
StorageBuffer upload_array(VulkanContext& ctx, const BufferNeed& need, const std::vector<T>& items) {
  StorageBuffer b(ctx, need);
  if (!items.empty()) b.upload(items.data(), items.size() * sizeof(T));
  return b;
}

// The host arrays WavefrontRenderer's consuming constructor frees (null: the caller keeps them).
struct HostCopies {
  Scene* scene = nullptr;
  GpuBvh* bvh = nullptr;
};

// upload_array, then frees `items` when `free`.
template <class T>
StorageBuffer upload_then_free(VulkanContext& ctx, const BufferNeed& need, std::vector<T>& items,
                               bool free) {
  StorageBuffer b = upload_array(ctx, need, items);
  if (free) free_array(items);
  return b;
}

// The render's own buffers (the tracer's are device_tracer_needs): the scene's shading data
// (triangles, materials and lights read through texel views only), the image and the wavefront's
// arrays.
struct RenderBufferNeeds {
  BufferNeed params, paths, next_paths, next_rays, shadows, image, queues;
  BufferNeed shade_triangles, shade_vertices, shade_attributes, materials, lights, textures, texels;

  RenderBufferNeeds(const RenderScene& rs, const RenderConfig& c, std::uint32_t wave)
      : params{"render parameters", sizeof(gpu::RenderParams)},
        paths{"path states", std::size_t{wave} * sizeof(gpu::PathState)},
        next_paths{"continuation path states", std::size_t{wave} * sizeof(gpu::PathState)},
        next_rays{"continuation rays", std::size_t{wave} * sizeof(gpu::Ray)},
        shadows{"shadow records", std::size_t{wave} * sizeof(gpu::ShadowRecord)},
        image{"image", std::size_t{c.width} * c.height * sizeof(glm::vec4)},
        queues{"render queues", sizeof(gpu::RenderQueues)},
        shade_triangles(array_need(rs.shading.triangles, IndexedShading::kTriangleBuffer,
                                   BufferBinding::kTexelOnly)),
        shade_vertices(array_need(rs.shading.vertices, IndexedShading::kVertexBuffer,
                                  BufferBinding::kTexelOnly)),
        shade_attributes(array_need(rs.shading.attributes, IndexedShading::kAttributeBuffer,
                                    BufferBinding::kTexelOnly)),
        materials(array_need(rs.materials, "materials", BufferBinding::kTexelOnly)),
        lights(array_need(rs.lights, "lights", BufferBinding::kTexelOnly)),
        textures(array_need(rs.textures, "texture table", BufferBinding::kStorage)),
        texels(array_need(rs.texels, "texels", BufferBinding::kStorage)) {}

  std::vector<BufferNeed> all() const {
    return {params,    paths,  next_paths,      next_rays,      shadows,
            image,     queues, shade_triangles, shade_vertices, shade_attributes,
            materials, lights, textures,        texels};
  }
};

// Paths per wavefront: one dispatch per kernel and wavefront reaches at most
// max_workgroup_count_x workgroups, and the tracer's ray arrays hold them.
std::uint32_t wavefront_paths(const VulkanContext& c, const RenderConfig& config) {
  return static_cast<std::uint32_t>(std::min<std::size_t>(
      {config.wavefront_paths, std::size_t{config.width} * config.height,
       std::size_t{c.info().max_workgroup_count_x} * HRPP_RENDER_WORKGROUP_SIZE,
       device_tracer_dispatch_rays(config.device_tracer, c.info(), config.tracer)}));
}

// Before anything is allocated: every buffer of the render against the device's limits and
// heap, naming the scene (vk/memory_plan.h).
const RenderBufferNeeds& check_render_fits(const VulkanContext& c, const Scene& scene,
                                           const GpuBvh& bvh, const RenderConfig& config,
                                           std::uint32_t wave, const RenderBufferNeeds& needs) {
  std::vector<BufferNeed> all =
      device_tracer_needs(config.device_tracer, bvh, config.predictor, wave);
  for (BufferNeed& n : needs.all()) all.push_back(std::move(n));
  check_fits("scene '" + scene.name + "' (" + std::to_string(scene.triangles.size()) +
                 " triangles)",
             all, memory_limits(c.info()));
  return needs;
}

std::array<SpecializationConstant, HRPP_FEATURE_COUNT> specialization(const RenderFeatures& f) {
  std::array<SpecializationConstant, HRPP_FEATURE_COUNT> s{};
  for (std::uint32_t i = 0; i < HRPP_FEATURE_COUNT; ++i) s[i] = {i, f.on[i] ? 1u : 0u};
  return s;
}

// The queues at the start of a bounce: empty, indirect dispatches of (0, 1, 1) workgroups.
constexpr gpu::RenderQueues kRenderQueuesStart = [] {
  gpu::RenderQueues q{};
  q.trace_any_groups[1] = q.trace_any_groups[2] = 1;
  q.accumulate_groups[1] = q.accumulate_groups[2] = 1;
  return q;
}();

// The device tracer (front/make_device_tracer.h). With `host` set, the scene's triangles and
// shading are freed before the upload and (the BVH kernels) each of the BVH's arrays once
// uploaded.
std::unique_ptr<DeviceTracer> make_tracer(VulkanContext& c, const GpuBvh& bvh,
                                          const RenderConfig& config, HostCopies host) {
  if (host.scene) {
    free_array(host.scene->triangles);
    free_array(host.scene->shading);
  }
  GpuBvh* release = config.device_tracer == DeviceTracerKind::kCompute ? host.bvh : nullptr;
  return make_device_tracer(c, config.device_tracer, bvh, config.tracer, config.predictor,
                            release);
}

// The tracer's hit array of a ray class, sized for `rays` resident rays.
const StorageBuffer& resident_hits(DeviceTracer& tracer, RayClass c, std::size_t rays) {
  tracer.ray_buffer(c, rays);
  return tracer.hit_buffer(c);
}

// What one frame of a class cost, for the adaptive predictor.
ClassFrameCost frame_cost(const RayClassStats& s, Probe mode) {
  ClassFrameCost c;
  c.mode = mode;
  c.rays = s.counters.rays;
  c.traced = s.traced;
  c.sampled = s.sampled;
  c.rounds = s.traces;
  add_kernel_times(c, s.kernels_ms);
  return c;
}

}  // namespace

struct WavefrontRenderer::State {
  VulkanContext& ctx;
  RenderConfig cfg;
  RenderScene rs;
  std::uint32_t wave;  // paths per wavefront
  RenderBufferNeeds needs;
  std::unique_ptr<DeviceTracer> device;
  DeviceTracer& tracer;
  GpuPredictor* hrpp;  // HRPP on: the tracer's stage, which routes each class (else nullptr)
  StorageBuffer params, paths, next_paths, next_rays, shadows, image, queues;
  StorageBuffer shade_triangles, shade_vertices, shade_attributes, materials, lights, textures,
      texels;
  TexelView shade_view, shade_vertex_view, shade_attribute_view, material_view, light_view;
  TexelView ray_view, hit_view, shadow_hit_view, path_view;  // over the tracer's arrays, `paths`
  std::unique_ptr<RaySorter> sorter;  // --reorder: the bounce rays' order (a ray index list)
  std::array<SpecializationConstant, HRPP_FEATURE_COUNT> spec;
  ComputePipeline generate, shade, accumulate;
  KernelTimer timer;
  AdaptivePredictor adaptive;

  State(VulkanContext& c, const Scene& scene, RenderScene render_scene, const GpuBvh& bvh,
        const RenderConfig& config, HostCopies host = {})
      : ctx(c),
        cfg(checked(config, scene)),
        rs(std::move(render_scene)),
        wave(wavefront_paths(c, config)),
        needs(check_render_fits(c, scene, bvh, config, wave, RenderBufferNeeds(rs, config, wave))),
        device(make_tracer(c, bvh, config, host)),
        tracer(*device),
        hrpp(tracer.predictor()),
        params(c, needs.params),
        paths(c, needs.paths),
        next_paths(c, needs.next_paths),
        next_rays(c, needs.next_rays),
        shadows(c, needs.shadows),
        image(c, needs.image),
        queues(c, needs.queues, MemoryRole::kHostShared),  // read after every bounce
        shade_triangles(
            upload_then_free(c, needs.shade_triangles, rs.shading.triangles, host.bvh != nullptr)),
        shade_vertices(
            upload_then_free(c, needs.shade_vertices, rs.shading.vertices, host.bvh != nullptr)),
        shade_attributes(upload_then_free(c, needs.shade_attributes, rs.shading.attributes,
                                          host.bvh != nullptr)),
        materials(upload_array(c, needs.materials, rs.materials)),
        lights(upload_array(c, needs.lights, rs.lights)),
        textures(upload_array(c, needs.textures, rs.textures)),
        texels(upload_array(c, needs.texels, rs.texels)),
        shade_view(c, shade_triangles),
        shade_vertex_view(c, shade_vertices),
        shade_attribute_view(c, shade_attributes),
        material_view(c, materials),
        light_view(c, lights),
        ray_view(c, tracer.ray_buffer(RayClass::kCamera, wave)),
        hit_view(c, resident_hits(tracer, RayClass::kCamera, wave)),
        shadow_hit_view(c, resident_hits(tracer, RayClass::kShadow, wave)),
        path_view(c, paths),
        spec(specialization(rs.features)),
        generate(c, Kernel::render_generate, embedded_spirv(Kernel::render_generate), kBindingTypes,
                 sizeof(gpu::RenderPushConstants), spec),
        shade(c, Kernel::render_shade, embedded_spirv(Kernel::render_shade), kBindingTypes,
              sizeof(gpu::RenderPushConstants), spec),
        accumulate(c, Kernel::render_accumulate, embedded_spirv(Kernel::render_accumulate),
                   kBindingTypes, sizeof(gpu::RenderPushConstants), spec),
        timer(c, 48),  // up to 16 HRPP dispatches, 7 of the sort, the render kernels
        adaptive(config.predictor) {
    if (cfg.reorder != RayOrder::kOff) make_sorter(bvh.bounds);
    for (ComputePipeline* p : {&generate, &shade, &accumulate}) {
      p->bind(HRPP_RENDER_BINDING_PARAMS, params);
      p->bind(HRPP_RENDER_BINDING_PATHS, paths);
      p->bind(HRPP_RENDER_BINDING_NEXT_PATHS, next_paths);
      p->bind(HRPP_RENDER_BINDING_RAYS, tracer.ray_buffer(RayClass::kCamera, wave));
      p->bind(HRPP_RENDER_BINDING_HITS, hit_view);
      p->bind(HRPP_RENDER_BINDING_RAY_TEXELS, ray_view);
      p->bind(HRPP_RENDER_BINDING_PATH_TEXELS, path_view);
      p->bind(HRPP_RENDER_BINDING_NEXT_RAYS, next_rays);
      p->bind(HRPP_RENDER_BINDING_SHADOW_RAYS, tracer.ray_buffer(RayClass::kShadow, wave));
      p->bind(HRPP_RENDER_BINDING_SHADOW_HITS, shadow_hit_view);
      p->bind(HRPP_RENDER_BINDING_SHADOWS, shadows);
      p->bind(HRPP_RENDER_BINDING_IMAGE, image);
      p->bind(HRPP_RENDER_BINDING_QUEUES, queues);
      p->bind(HRPP_RENDER_BINDING_SHADE_TRIANGLES, shade_view);
      p->bind(HRPP_RENDER_BINDING_SHADE_VERTICES, shade_vertex_view);
      p->bind(HRPP_RENDER_BINDING_SHADE_ATTRIBUTES, shade_attribute_view);
      p->bind(HRPP_RENDER_BINDING_MATERIALS, material_view);
      p->bind(HRPP_RENDER_BINDING_LIGHTS, light_view);
      p->bind(HRPP_RENDER_BINDING_TEXTURES, textures);
      p->bind(HRPP_RENDER_BINDING_TEXELS, texels);
    }
    upload_params(scene.cameras[cfg.camera]);
  }

  // The sorter reads the bounce rays where the tracer reads them; the trace reads them through
  // the sort's order, so rays, hits and paths stay in queue order.
  void make_sorter(const Aabb& bounds) {
    sorter = std::make_unique<RaySorter>(ctx, bounds, wave);
    sorter->bind_rays(ray_view);
  }

  // At the start of a bounce after the first: the continuation rays and their paths into place.
  void record_continuations(VkCommandBuffer cmd, std::uint32_t n) {
    record_copy(cmd, next_rays, 0, tracer.ray_buffer(RayClass::kCamera, wave), 0,
                std::size_t{n} * sizeof(gpu::Ray));
    record_copy(cmd, next_paths, 0, paths, 0, std::size_t{n} * sizeof(gpu::PathState));
  }

  // --reorder: the order the bounce's trace reads its rays in (after the copies), or nullptr
  // when there is none: no sorter, camera rays, or HRPP's predicted trace (its stage keeps
  // queue order).
  const TexelView* record_order(VkCommandBuffer cmd, RayClass c, std::uint32_t n) {
    if (!sorter || c != RayClass::kBounce || probing(c) == Probe::kAll) return nullptr;
    sorter->record(cmd, n, &timer);
    return &sorter->order_view();
  }

  Probe probing(RayClass c) const { return hrpp ? hrpp->probing(c) : Probe::kOff; }

  void upload_params(const Camera& cam) {
    const gpu::RenderParams p = make_render_params(cfg, cam, rs, tracer.rays_per_workgroup());
    params.upload(&p, sizeof p);
  }

  static std::uint32_t groups(std::uint32_t items) {
    return (items + HRPP_RENDER_WORKGROUP_SIZE - 1) / HRPP_RENDER_WORKGROUP_SIZE;
  }

  // Submits what `record` records (kernels timed with `timer`), adds the kernel times to
  // `stats` and returns the queues.
  gpu::RenderQueues submit(const std::function<void(VkCommandBuffer)>& record, const char* what,
                           FrameStats& stats) {
    ctx.submit_and_wait(
        [&](VkCommandBuffer cmd) {
          timer.reset(cmd);
          record(cmd);
        },
        what);
    for (const auto& [label, ms] : timer.read_ms()) {
      stats.kernels_ms[label.without_class()] += ms;
      if (label.ray_class) stats.classes[*label.ray_class].kernels_ms[label.without_class()] += ms;
    }
    gpu::RenderQueues q{};
    queues.download(&q, sizeof q);
    return q;
  }

  static void check_done(const char* kernel, std::uint32_t done, std::uint32_t submitted) {
    if (done != submitted)
      throw Error(std::string(kernel) + ": only " + std::to_string(done) + " of " +
                  std::to_string(submitted) +
                  " items finished: the driver's loop limiter or a lost dispatch");
  }

  void add_trace(const GpuTraceResult& r, RayClass cls, FrameStats& stats) {
    RayClassStats& c = stats.classes[cls];
    c.counters += r.counters;
    c.predictor += r.predictor;
    ++c.traces;
    c.predicted_traces += r.predicted ? 1 : 0;
    c.traced += r.traced;
    c.sampled += r.sampled;
  }

  // The shadow half of a bounce: trace_any, then render_accumulate, on the shadow queue's count
  // read on the device (indirect dispatch) or, in HRPP's batched mode, on `host_count`.
  void record_shadows(VkCommandBuffer cmd, const std::uint32_t* host_count, std::uint32_t depth) {
    const gpu::RenderPushConstants pc{0, 0, 0, depth};
    if (host_count) {
      tracer.record(cmd, RayClass::kShadow, *host_count, &timer);
      record_dispatch(cmd, accumulate, &pc, groups(*host_count), &timer);
      return;
    }
    indirect_args_barrier(cmd);  // render_shade's queue count and dispatch arguments
    tracer.record_indirect(cmd, RayClass::kShadow, queues, offsetof(gpu::RenderQueues, shadow_rays),
                           offsetof(gpu::RenderQueues, trace_any_groups), &timer);
    record_dispatch_indirect(cmd, accumulate, &pc, queues,
                             offsetof(gpu::RenderQueues, accumulate_groups), &timer);
  }

  // Paths of pixels [first, first + n) for one sample, to the end. One command buffer per
  // bounce: (generate | move the continuation rays into place) → trace_closest → render_shade
  // → trace_any → render_accumulate, the last two dispatched indirectly from the shadow queue;
  // the host reads the queues once per bounce to check completion and size the next one.
  void trace_wavefront(std::uint32_t first, std::uint32_t n, std::uint32_t sample,
                       FrameStats& stats) {
    const bool indirect = tracer.records_indirect(RayClass::kShadow);
    for (std::uint32_t depth = 0; n > 0; ++depth) {
      if (depth > cfg.max_depth)
        throw Error("render_shade: paths continued past the max depth (kernel bug)");
      const RayClass closest = depth == 0 ? RayClass::kCamera : RayClass::kBounce;
      tracer.begin(closest);
      tracer.begin(RayClass::kShadow);
      const TexelView* order = nullptr;
      const gpu::RenderQueues q = submit(
          [&](VkCommandBuffer cmd) {
            record_update(cmd, queues, 0, sizeof kRenderQueuesStart, &kRenderQueuesStart);
            if (depth > 0) record_continuations(cmd, n);
            transfer_compute_barrier(cmd);
            if (depth == 0) {
              const gpu::RenderPushConstants pc{first, n, sample, 0};
              record_dispatch(cmd, generate, &pc, groups(n), &timer);
            }
            order = record_order(cmd, closest, n);
            tracer.record(cmd, closest, n, &timer, order);
            const gpu::RenderPushConstants pc{0, n, 0, depth};
            record_dispatch(cmd, shade, &pc, groups(n), &timer);
            if (indirect) record_shadows(cmd, nullptr, depth);
          },
          "render bounce", stats);
      if (depth == 0) check_done("render_generate", q.done[HRPP_RENDER_DONE_GENERATE], n);
      if (order) sorter->finish(n);
      check_done("render_shade", q.done[HRPP_RENDER_DONE_SHADE], n);
      if (q.next_rays > n || q.shadow_rays > n)
        throw Error("render_shade: queue overflow (" + std::to_string(q.next_rays) + ", " +
                    std::to_string(q.shadow_rays) + " of " + std::to_string(n) + ")");
      add_trace(tracer.finish(closest), closest, stats);
      std::uint32_t accumulated = q.done[HRPP_RENDER_DONE_ACCUMULATE];
      if (!indirect && q.shadow_rays > 0) {  // HRPP batched mode: a second submit
        accumulated = submit([&](VkCommandBuffer cmd) { record_shadows(cmd, &q.shadow_rays, depth); },
                             "render shadows", stats)
                          .done[HRPP_RENDER_DONE_ACCUMULATE];
      }
      if (indirect || q.shadow_rays > 0) {
        const GpuTraceResult shadow = tracer.finish(RayClass::kShadow);  // checks it finished
        if (q.shadow_rays > 0) add_trace(shadow, RayClass::kShadow, stats);
      }
      check_done("render_accumulate", accumulated, q.shadow_rays);
      n = q.next_rays;
    }
  }
};

WavefrontRenderer::WavefrontRenderer(VulkanContext& ctx, const Scene& scene, const GpuBvh& bvh,
                                     const RenderConfig& config)
    : s_(std::make_unique<State>(ctx, scene, make_render_scene(scene, config.default_lighting), bvh,
                                 config)) {}

WavefrontRenderer::WavefrontRenderer(VulkanContext& ctx, Scene& scene, RenderScene rs, GpuBvh& bvh,
                                     const RenderConfig& config)
    : s_(std::make_unique<State>(ctx, scene, std::move(rs), bvh, config,
                                 HostCopies{&scene, &bvh})) {}

WavefrontRenderer::~WavefrontRenderer() = default;

const RenderScene& WavefrontRenderer::render_scene() const { return s_->rs; }

RenderResult WavefrontRenderer::render(PassObserver* observer) {
  const auto start = std::chrono::steady_clock::now();
  RenderResult out = make_render_result(s_->cfg, s_->rs);
  RenderStats& stats = out.stats;
  const std::uint32_t pixels = out.width * out.height;
  if (s_->cfg.warm_up) {
    FrameStats discard;
    s_->tracer.warm_up();
    s_->trace_wavefront(0, std::min(pixels, 64u), 0, discard);
    if (s_->hrpp) s_->hrpp->clear();  // the warm-up paths leave nothing behind
  }
  s_->image.fill(0);
  const auto first_pass = std::chrono::steady_clock::now();
  auto mean_so_far = [&] {
    RenderResult r = out;
    std::vector<glm::vec4> sum(pixels);
    s_->image.download(sum.data(), sum.size() * sizeof(glm::vec4));
    set_mean_image(r, sum, static_cast<std::uint32_t>(stats.frames.size()));
    return r;
  };
  // The host's copy of the last pass boundary: what a device failure leaves (RenderResult).
  struct Kept {
    std::vector<glm::vec4> sum;
    RenderStats stats;
    std::chrono::steady_clock::time_point at;
  } kept;
  const auto keep = [&](std::chrono::steady_clock::time_point now) {
    kept.sum.resize(pixels);
    s_->image.download(kept.sum.data(), kept.sum.size() * sizeof(glm::vec4));
    kept.stats = stats;
    kept.at = now;
  };
  for (std::uint32_t sample = 0; sample < s_->cfg.spp; ++sample) {
    FrameStats frame;
    try {
      run_pass(sample, frame);
    } catch (const DeviceFailure& e) {
      out.failure = e.what();
      out.passes_before_failure = sample;
      break;
    }
    stats += frame;
    stats.frames.push_back(std::move(frame));
    const auto now = std::chrono::steady_clock::now();
    if (sample == 0 || now - kept.at >= kKeepInterval) keep(now);
    const double elapsed = std::chrono::duration<double>(now - first_pass).count();
    if (observer && !observer->after_pass(sample + 1, elapsed, mean_so_far)) break;
  }
  if (!out.failure.empty())  // the device's arrays may be gone: only what the host kept
    stats = kept.stats;
  else if (kept.stats.frames.size() != stats.frames.size())  // not kept at the last pass
    keep(std::chrono::steady_clock::now());
  set_mean_image(out, kept.sum, static_cast<std::uint32_t>(stats.frames.size()));
  stats.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

void WavefrontRenderer::run_pass(std::uint32_t sample, FrameStats& frame) {
  const auto frame_start = std::chrono::steady_clock::now();
  const std::uint32_t pixels = s_->cfg.width * s_->cfg.height;
  const bool driver = s_->cfg.device_tracer == DeviceTracerKind::kRayQuery;
  for (Kernel k : {Kernel::render_generate,
                   driver ? Kernel::trace_rayquery_closest : Kernel::trace_closest,
                   Kernel::render_shade, driver ? Kernel::trace_rayquery_any : Kernel::trace_any,
                   Kernel::render_accumulate})
    frame.kernels_ms[TimerLabel{k}] = 0.0;
  if (s_->hrpp)
    for (RayClass c : kRayClasses)
      s_->hrpp->set_probing(c, s_->adaptive.mode(c), s_->adaptive.sample_stride(c));
  for (std::uint32_t first = 0; first < pixels; first += s_->wave)
    s_->trace_wavefront(first, std::min(s_->wave, pixels - first), sample, frame);
  frame.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - frame_start).count();
  for (RayClass c : kRayClasses)
    frame.decisions[c] = s_->adaptive.end_frame(c, frame_cost(frame.classes[c], s_->probing(c)));
}

TableOccupancy WavefrontRenderer::predictor_occupancy(RayClass c) const {
  return s_->hrpp ? s_->hrpp->occupancy(c) : TableOccupancy{};
}

}  // namespace hrpp
