#include "gpu/gpu_tracer.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <string>

#include "common/error.h"
#include "gpu/compute_pipeline.h"
#include "gpu/embedded_shaders.h"
#include "gpu/gpu_predictor.h"
#include "gpu/storage_buffer.h"
#include "gpu/texel_view.h"
#include "gpu/vulkan_context.h"
#include "trace/slab_test.h"
#include "hrpp_interface.h"
#include "trace_interface.h"

namespace hrpp {

static_assert(sizeof(gpu::TraceCounters) == 64);
static_assert(offsetof(gpu::TraceCounters, wide) == 16);
static_assert(sizeof(gpu::TracePushConstants) == 16);
static_assert(HRPP_STACK_SIZE == 64, "shaders/shared/trace_interface.h and host/bvh/gpu_layout.h");
static_assert(std::bit_cast<std::uint32_t>(kSlabFarScale) == HRPP_SLAB_FAR_SCALE_BITS);
static_assert(std::bit_cast<std::uint32_t>(0x1p-80f) == HRPP_TWO_POW_M80_BITS);
static_assert(std::bit_cast<std::uint32_t>(0x1p80f) == HRPP_TWO_POW_80_BITS);
// shaders/lib/texel_fetch.glsl reads these records as 4, 1, 3 and 2 16-byte texels.
static_assert(sizeof(gpu::BvhNode) == 4 * TexelView::kTexelBytes);
static_assert(sizeof(gpu::BvhLeaf) == 1 * TexelView::kTexelBytes);
static_assert(sizeof(gpu::TriangleRecord) == 3 * TexelView::kTexelBytes);
static_assert(sizeof(gpu::Ray) == 2 * TexelView::kTexelBytes);

namespace {

constexpr std::uint32_t kCanaryIterations = 2;

// The trace kernels' bindings; the HRPP variants add the predictor's storage buffers after them.
template <std::size_t N>
constexpr std::array<VkDescriptorType, N> binding_types() {
  std::array<VkDescriptorType, N> t{};
  t.fill(VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
  t[HRPP_TRACE_BINDING_NODES] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  t[HRPP_TRACE_BINDING_LEAVES] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  t[HRPP_TRACE_BINDING_TRIANGLES] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  t[HRPP_TRACE_BINDING_RAYS] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
  return t;
}
constexpr auto kBindingTypes = binding_types<HRPP_TRACE_BINDING_COUNT>();
constexpr auto kPredictBindingTypes = binding_types<HRPP_PREDICT_BINDING_COUNT>();
static_assert(HRPP_PREDICT_BINDING_FIRST == HRPP_TRACE_BINDING_COUNT);

std::uint64_t wide(const gpu::TraceCounters& c, int counter) {
  return static_cast<std::uint64_t>(c.wide[2 * counter]) |
         (static_cast<std::uint64_t>(c.wide[2 * counter + 1]) << 32);
}

}  // namespace

// The resident arrays and counters of one ray class (hit-all or hit-any).
struct ClassArrays {
  StorageBuffer rays, hits;  // grown on demand
  TexelView ray_view;        // how the kernels read the rays
  StorageBuffer counters;    // TraceCounters of the class's last trace
  std::uint32_t clock = 0;   // HRPP use stamps: rays of the class traced so far
};

struct GpuTracer::State {
  VulkanContext* ctx = nullptr;
  GpuTracerConfig config;
  StorageBuffer nodes, leaves, triangles;
  TexelView node_view, leaf_view, triangle_view;  // how the kernels read the BVH arrays
  ClassArrays classes[2];                         // [any_hit]
  ComputePipeline closest, any;
  KernelTimer timer;
  std::unique_ptr<GpuPredictor> predictor;  // HRPP on
  std::unique_ptr<ComputePipeline> closest_hrpp, any_hrpp;  // HRPP on
  gpu::Ray probe{};  // warm-up ray: through the scene's centre

  State(VulkanContext& c, const GpuBvh& bvh, const GpuTracerConfig& cfg,
        const PredictorConfig& predictor_config)
      : ctx(&c),
        config(cfg),
        nodes(c, bvh.nodes.size() * sizeof(gpu::BvhNode), "BVH node array"),
        leaves(c, bvh.leaves.size() * sizeof(gpu::BvhLeaf), "BVH leaf array"),
        triangles(c, bvh.triangles.size() * sizeof(gpu::TriangleRecord), "BVH triangle array"),
        node_view(c, nodes),
        leaf_view(c, leaves),
        triangle_view(c, triangles),
        closest(c, "trace_closest", embedded_spirv("trace_closest"), kBindingTypes,
                sizeof(gpu::TracePushConstants)),
        any(c, "trace_any", embedded_spirv("trace_any"), kBindingTypes,
            sizeof(gpu::TracePushConstants)),
        timer(c, 4) {
    if (predictor_config.enabled) {
      predictor = std::make_unique<GpuPredictor>(c, bvh, predictor_config);
      closest_hrpp = std::make_unique<ComputePipeline>(
          c, "trace_closest_hrpp", embedded_spirv("trace_closest_hrpp"), kPredictBindingTypes,
          sizeof(gpu::TracePushConstants));
      any_hrpp = std::make_unique<ComputePipeline>(c, "trace_any_hrpp",
                                                   embedded_spirv("trace_any_hrpp"),
                                                   kPredictBindingTypes,
                                                   sizeof(gpu::TracePushConstants));
    }
    if (config.rays_per_invocation == 0) throw Error("rays per invocation must be at least 1");
    nodes.upload(std::span<const gpu::BvhNode>(bvh.nodes));
    leaves.upload(std::span<const gpu::BvhLeaf>(bvh.leaves));
    triangles.upload(std::span<const gpu::TriangleRecord>(bvh.triangles));
    for (bool any_hit : {false, true}) {
      classes[any_hit].counters =
          StorageBuffer(c, sizeof(gpu::TraceCounters),
                        any_hit ? "hit-any trace counters" : "hit-all trace counters");
      for (ComputePipeline* p : pipelines(any_hit)) {
        p->bind(HRPP_TRACE_BINDING_NODES, node_view);
        p->bind(HRPP_TRACE_BINDING_LEAVES, leaf_view);
        p->bind(HRPP_TRACE_BINDING_TRIANGLES, triangle_view);
        p->bind(HRPP_TRACE_BINDING_COUNTERS, classes[any_hit].counters);
      }
    }
    const glm::vec3 centre = 0.5f * (bvh.bounds.lo + bvh.bounds.hi);
    probe.origin = centre - glm::vec3(bvh.bounds.hi.x - bvh.bounds.lo.x + 1.0f, 0.0f, 0.0f);
    probe.tmin = 0.0f;
    probe.dir = {1.0f, 0.0f, 0.0f};
    probe.tmax = 1e30f;
  }

  // The kernels of one ray class: plain, and with HRPP the predicting one.
  std::vector<ComputePipeline*> pipelines(bool any_hit) {
    std::vector<ComputePipeline*> p{any_hit ? &any : &closest};
    if (predictor) p.push_back(any_hit ? any_hrpp.get() : closest_hrpp.get());
    return p;
  }

  bool predicts(bool any_hit) const { return predictor && predictor->config().predicts(any_hit); }

  ComputePipeline& kernel(bool any_hit) {
    if (predicts(any_hit)) return *(any_hit ? any_hrpp : closest_hrpp);
    return any_hit ? any : closest;
  }

  std::uint32_t rays_per_workgroup(bool any_hit) const {
    if (predicts(any_hit)) return predictor->rays_per_workgroup(config.rays_per_invocation);
    return HRPP_TRACE_WORKGROUP_SIZE * config.rays_per_invocation;
  }

  // Rays per dispatch: what one storage buffer and one texel view hold and one dispatch's
  // workgroups reach.
  std::size_t chunk_rays() const {
    const DeviceInfo& d = ctx->info();
    const std::uint64_t by_range =
        std::min<std::uint64_t>(d.max_storage_buffer_range / sizeof(gpu::Ray),
                                std::uint64_t{d.max_texel_buffer_elements} * TexelView::kTexelBytes /
                                    sizeof(gpu::Ray));
    const std::uint64_t by_groups = static_cast<std::uint64_t>(d.max_workgroup_count_x) *
                                    HRPP_TRACE_WORKGROUP_SIZE * config.rays_per_invocation;
    return static_cast<std::size_t>(std::min<std::uint64_t>({by_range, by_groups, 0xFFFFFFFFu}));
  }

  void ensure_capacity(bool any_hit, std::size_t n) {
    ClassArrays& a = classes[any_hit];
    if (a.rays.size() >= n * sizeof(gpu::Ray)) return;
    a.ray_view = TexelView();
    a.rays = StorageBuffer();  // free first: one at a time in the heap
    a.hits = StorageBuffer();
    const char* which = any_hit ? "hit-any" : "hit-all";
    a.rays = StorageBuffer(*ctx, n * sizeof(gpu::Ray), std::string(which) + " ray array");
    a.hits = StorageBuffer(*ctx, n * sizeof(gpu::Hit), std::string(which) + " hit array");
    a.ray_view = TexelView(*ctx, a.rays);
    for (ComputePipeline* p : pipelines(any_hit)) {
      p->bind(HRPP_TRACE_BINDING_RAYS, a.ray_view);
      p->bind(HRPP_TRACE_BINDING_HITS, a.hits);
    }
    if (predictor) predictor->bind(any_hit ? *any_hrpp : *closest_hrpp, any_hit, n);
  }

  gpu::TracePushConstants push_constants() const {
    gpu::TracePushConstants pc{};
    pc.rays_per_invocation = config.rays_per_invocation;
    pc.canary_iterations = kCanaryIterations;
    return pc;
  }

  // Before a recorded trace: zeroes the class's counters and sets their ray count, on the
  // host's word (`count`) or copied from `queue` at `count_offset` (transfers to disjoint bytes,
  // then one barrier), and starts HRPP's use stamps at the class's clock.
  void prepare_trace(VkCommandBuffer cmd, bool any_hit, const std::uint32_t* count,
                      const StorageBuffer* queue, VkDeviceSize count_offset) {
    const VkBuffer c = classes[any_hit].counters.handle();
    gpu::TraceCounters start{};
    if (count) {
      start.ray_count = *count;
      vkCmdUpdateBuffer(cmd, c, 0, sizeof start, &start);
    } else {
      constexpr VkDeviceSize at = offsetof(gpu::TraceCounters, ray_count);
      constexpr VkDeviceSize word = sizeof(std::uint32_t);
      vkCmdUpdateBuffer(cmd, c, 0, at, &start);
      vkCmdUpdateBuffer(cmd, c, at + word, sizeof start - at - word,
                        reinterpret_cast<const char*>(&start) + at + word);
      const VkBufferCopy region{count_offset, at, word};
      vkCmdCopyBuffer(cmd, queue->handle(), c, 1, &region);
    }
    transfer_compute_barrier(cmd);
    if (predicts(any_hit)) predictor->set_clock(any_hit, classes[any_hit].clock);
  }

  void record(VkCommandBuffer cmd, bool any_hit, std::uint32_t count, KernelTimer* t) {
    check_resident(any_hit, count);
    prepare_trace(cmd, any_hit, &count, nullptr, 0);
    ComputePipeline& p = kernel(any_hit);
    const gpu::TracePushConstants pc = push_constants();
    if (predicts(any_hit) && predictor->config().batch > 0) {
      predictor->record_batches(cmd, p, pc, classes[any_hit].counters, any_hit, count,
                                classes[any_hit].clock);
      return;  // many small dispatches: not timed
    }
    const std::uint32_t per_group = rays_per_workgroup(any_hit);
    record_dispatch(cmd, p, &pc, (count + per_group - 1) / per_group, t);
  }

  void record_indirect(VkCommandBuffer cmd, bool any_hit, const StorageBuffer& queue,
                       VkDeviceSize count_offset, VkDeviceSize args_offset, KernelTimer* t) {
    if (!records_indirect(any_hit))
      throw Error("trace: HRPP's batched mode (--hrpp-batch) needs the ray count on the host");
    if (classes[any_hit].rays.size() == 0)
      throw Error("trace: record_indirect before ray_buffer() sized the resident arrays");
    prepare_trace(cmd, any_hit, nullptr, &queue, count_offset);
    ComputePipeline& p = kernel(any_hit);
    const gpu::TracePushConstants pc = push_constants();
    record_dispatch_indirect(cmd, p, &pc, queue, args_offset, t);
  }

  bool records_indirect(bool any_hit) const {
    return !(predicts(any_hit) && predictor->config().batch > 0);
  }

  void check_resident(bool any_hit, std::size_t count) const {
    if (count * sizeof(gpu::Ray) > classes[any_hit].rays.size() || count > chunk_rays())
      throw Error("trace: " + std::to_string(count) +
                  " rays exceed the device-resident ray array or one dispatch");
  }

  // After the submit: the class's counters, checked (every ray finished).
  GpuTraceResult finish(bool any_hit) {
    GpuTraceResult out;
    gpu::TraceCounters c{};
    classes[any_hit].counters.download(&c, sizeof c);
    const std::uint64_t done = wide(c, HRPP_COUNTER_RAYS);
    const std::string name = kernel(any_hit).name();
    if (done != c.ray_count || c.aborted != 0)
      throw Error(name + ": only " + std::to_string(done) + " of " +
                  std::to_string(c.ray_count) + " rays finished (" + std::to_string(c.aborted) +
                  " cut short): the driver's loop limiter (lavapipe: 65,535 loop iterations per "
                  "subgroup) ended the kernel's loops at " +
                  std::to_string(config.rays_per_invocation) +
                  " rays per invocation; lower rays_per_invocation");
    out.counters.rays = done;
    out.counters.interior_visited = wide(c, HRPP_COUNTER_INTERIOR);
    out.counters.leaves_visited = wide(c, HRPP_COUNTER_LEAVES);
    out.counters.triangles_tested = wide(c, HRPP_COUNTER_TRIANGLES);
    out.counters.hits = wide(c, HRPP_COUNTER_HITS);
    classes[any_hit].clock += c.ray_count;
    if (predictor) out.predictor = predictor->counters(any_hit);
    return out;
  }
};

GpuTracer::GpuTracer(VulkanContext& ctx, const GpuBvh& bvh, const GpuTracerConfig& config,
                     const PredictorConfig& predictor)
    : s_(std::make_unique<State>(ctx, bvh, config, predictor)) {}

GpuTracer::~GpuTracer() = default;
GpuTracer::GpuTracer(GpuTracer&&) noexcept = default;
GpuTracer& GpuTracer::operator=(GpuTracer&&) noexcept = default;

const GpuTracerConfig& GpuTracer::config() const { return s_->config; }

GpuTraceResult GpuTracer::trace(std::span<const gpu::Ray> rays, bool any_hit) {
  GpuTraceResult out;
  out.hits.resize(rays.size());
  begin(any_hit);
  const std::size_t chunk = s_->chunk_rays();
  for (std::size_t first = 0; first < rays.size(); first += chunk) {
    const std::size_t n = std::min(chunk, rays.size() - first);
    s_->ensure_capacity(any_hit, n);
    s_->classes[any_hit].rays.upload(rays.data() + first, n * sizeof(gpu::Ray));
    const GpuTraceResult r = trace_resident(n, any_hit);
    s_->classes[any_hit].hits.download(out.hits.data() + first, n * sizeof(gpu::Hit));
    out.counters += r.counters;
    out.kernel_ms += r.kernel_ms;
    out.predictor = r.predictor;  // since begin(): the whole call
  }
  return out;
}

StorageBuffer& GpuTracer::ray_buffer(bool any_hit, std::size_t rays) {
  s_->ensure_capacity(any_hit, std::max<std::size_t>(rays, 1));
  return s_->classes[any_hit].rays;
}

StorageBuffer& GpuTracer::hit_buffer(bool any_hit) { return s_->classes[any_hit].hits; }

void GpuTracer::begin(bool any_hit) {
  if (s_->predictor) s_->predictor->begin_trace(any_hit);
}

void GpuTracer::record(VkCommandBuffer cmd, bool any_hit, std::uint32_t count,
                       KernelTimer* timer) {
  s_->record(cmd, any_hit, count, timer);
}

void GpuTracer::record_indirect(VkCommandBuffer cmd, bool any_hit, const StorageBuffer& queue,
                                VkDeviceSize count_offset, VkDeviceSize args_offset,
                                KernelTimer* timer) {
  s_->record_indirect(cmd, any_hit, queue, count_offset, args_offset, timer);
}

GpuTraceResult GpuTracer::finish(bool any_hit) { return s_->finish(any_hit); }

bool GpuTracer::records_indirect(bool any_hit) const { return s_->records_indirect(any_hit); }

std::uint32_t GpuTracer::rays_per_workgroup(bool any_hit) const {
  return s_->rays_per_workgroup(any_hit);
}

std::size_t GpuTracer::max_dispatch_rays() const { return s_->chunk_rays(); }

GpuTraceResult GpuTracer::trace_resident(std::size_t count, bool any_hit) {
  if (count == 0) return {};
  const std::string what = s_->kernel(any_hit).name();
  s_->ctx->submit_and_wait(
      [&](VkCommandBuffer cmd) {
        s_->timer.reset(cmd);
        s_->record(cmd, any_hit, static_cast<std::uint32_t>(count), &s_->timer);
      },
      what);
  GpuTraceResult out = s_->finish(any_hit);
  for (const auto& [kernel, ms] : s_->timer.read_ms()) out.kernel_ms += ms;
  return out;
}

void GpuTracer::warm_up() {
  const std::vector<gpu::Ray> rays(HRPP_TRACE_WORKGROUP_SIZE, s_->probe);
  trace(rays, false);
  trace(rays, true);
  clear_predictor();  // the warm-up rays leave nothing behind
}

TableOccupancy GpuTracer::predictor_occupancy(bool any_hit) const {
  return s_->predictor ? s_->predictor->occupancy(any_hit) : TableOccupancy{};
}

void GpuTracer::set_count_baseline(bool on) {
  if (s_->predictor) s_->predictor->set_count_baseline(on);
}

void GpuTracer::clear_predictor() {
  if (s_->predictor) s_->predictor->clear();
  for (ClassArrays& a : s_->classes) a.clock = 0;
}

}  // namespace hrpp
