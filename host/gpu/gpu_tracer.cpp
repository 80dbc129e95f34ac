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

struct GpuTracer::State {
  VulkanContext* ctx = nullptr;
  GpuTracerConfig config;
  StorageBuffer nodes, leaves, triangles, counters;
  TexelView node_view, leaf_view, triangle_view;  // how the kernels read the BVH arrays
  StorageBuffer rays, hits;  // grown on demand
  TexelView ray_view;        // how the kernels read the rays
  ComputePipeline closest, any;
  KernelTimer timer;
  std::unique_ptr<GpuPredictor> predictor;  // HRPP on
  std::unique_ptr<ComputePipeline> closest_hrpp, any_hrpp;  // HRPP on
  std::uint32_t clock = 0;                  // HRPP use stamps: rays traced so far
  gpu::Ray probe{};  // warm-up ray: through the scene's centre

  State(VulkanContext& c, const GpuBvh& bvh, const GpuTracerConfig& cfg,
        const PredictorConfig& predictor_config)
      : ctx(&c),
        config(cfg),
        nodes(c, bvh.nodes.size() * sizeof(gpu::BvhNode), "BVH node array"),
        leaves(c, bvh.leaves.size() * sizeof(gpu::BvhLeaf), "BVH leaf array"),
        triangles(c, bvh.triangles.size() * sizeof(gpu::TriangleRecord), "BVH triangle array"),
        counters(c, sizeof(gpu::TraceCounters), "trace counters"),
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
    for (ComputePipeline* p : pipelines()) {
      p->bind(HRPP_TRACE_BINDING_NODES, node_view);
      p->bind(HRPP_TRACE_BINDING_LEAVES, leaf_view);
      p->bind(HRPP_TRACE_BINDING_TRIANGLES, triangle_view);
      p->bind(HRPP_TRACE_BINDING_COUNTERS, counters);
    }
    const glm::vec3 centre = 0.5f * (bvh.bounds.lo + bvh.bounds.hi);
    probe.origin = centre - glm::vec3(bvh.bounds.hi.x - bvh.bounds.lo.x + 1.0f, 0.0f, 0.0f);
    probe.tmin = 0.0f;
    probe.dir = {1.0f, 0.0f, 0.0f};
    probe.tmax = 1e30f;
  }

  std::vector<ComputePipeline*> pipelines() {
    if (predictor) return {&closest, &any, closest_hrpp.get(), any_hrpp.get()};
    return {&closest, &any};
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

  void ensure_capacity(std::size_t n) {
    if (rays.size() >= n * sizeof(gpu::Ray)) return;
    ray_view = TexelView();
    rays = StorageBuffer();  // free first: one at a time in the heap
    hits = StorageBuffer();
    rays = StorageBuffer(*ctx, n * sizeof(gpu::Ray), "ray array");
    hits = StorageBuffer(*ctx, n * sizeof(gpu::Hit), "hit array");
    ray_view = TexelView(*ctx, rays);
    for (ComputePipeline* p : pipelines()) {
      p->bind(HRPP_TRACE_BINDING_RAYS, ray_view);
      p->bind(HRPP_TRACE_BINDING_HITS, hits);
    }
    if (predictor) {
      predictor->bind(*closest_hrpp, false, n);
      predictor->bind(*any_hrpp, true, n);
    }
  }

  // One dispatch over rays[0..n) of the current buffers; adds into `out`.
  void dispatch(std::size_t n, bool any_hit, GpuTraceResult& out, std::size_t first) {
    const bool predicts = predictor && predictor->config().predicts(any_hit);
    ComputePipeline& p =
        predicts ? *(any_hit ? any_hrpp : closest_hrpp) : (any_hit ? any : closest);
    gpu::TraceCounters zero{};
    counters.upload(&zero, sizeof zero);
    gpu::TracePushConstants pc{};
    pc.ray_count = static_cast<std::uint32_t>(n);
    pc.rays_per_invocation = config.rays_per_invocation;
    pc.canary_iterations = kCanaryIterations;
    const std::uint64_t per_group =
        static_cast<std::uint64_t>(HRPP_TRACE_WORKGROUP_SIZE) * config.rays_per_invocation;
    const auto groups = static_cast<std::uint32_t>((n + per_group - 1) / per_group);
    ctx->submit_and_wait(
        [&](VkCommandBuffer cmd) {
          timer.reset(cmd);
          if (predicts)
            predictor->record(cmd, p, pc, config.rays_per_invocation, counters, any_hit, clock,
                              predictor->config().batch == 0 ? &timer : nullptr);
          else
            record_dispatch(cmd, p, &pc, groups, &timer);
        },
        p.name());
    for (const auto& [kernel, ms] : timer.read_ms()) out.kernel_ms += ms;

    gpu::TraceCounters c{};
    counters.download(&c, sizeof c);
    const std::uint64_t done = wide(c, HRPP_COUNTER_RAYS);
    if (done != n || c.aborted != 0)
      throw Error(p.name() + ": only " + std::to_string(done) + " of " + std::to_string(n) +
                  " rays finished (" + std::to_string(c.aborted) +
                  " cut short): the driver's loop limiter (lavapipe: 65,535 loop iterations per "
                  "subgroup) ended the kernel's loops at " +
                  std::to_string(config.rays_per_invocation) +
                  " rays per invocation; lower rays_per_invocation");
    if (!out.hits.empty()) hits.download(out.hits.data() + first, n * sizeof(gpu::Hit));
    out.counters.rays += done;
    out.counters.interior_visited += wide(c, HRPP_COUNTER_INTERIOR);
    out.counters.leaves_visited += wide(c, HRPP_COUNTER_LEAVES);
    out.counters.triangles_tested += wide(c, HRPP_COUNTER_TRIANGLES);
    out.counters.hits += wide(c, HRPP_COUNTER_HITS);
    clock += static_cast<std::uint32_t>(n);
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
  if (s_->predictor) s_->predictor->begin_trace(any_hit);
  const std::size_t chunk = s_->chunk_rays();
  for (std::size_t first = 0; first < rays.size(); first += chunk) {
    const std::size_t n = std::min(chunk, rays.size() - first);
    s_->ensure_capacity(n);
    s_->rays.upload(rays.data() + first, n * sizeof(gpu::Ray));
    s_->dispatch(n, any_hit, out, first);
  }
  if (s_->predictor) out.predictor = s_->predictor->counters(any_hit);
  return out;
}

StorageBuffer& GpuTracer::ray_buffer(std::size_t rays) {
  s_->ensure_capacity(std::max<std::size_t>(rays, 1));
  return s_->rays;
}

StorageBuffer& GpuTracer::hit_buffer() { return s_->hits; }

GpuTraceResult GpuTracer::trace_resident(std::size_t count, bool any_hit) {
  GpuTraceResult out;
  if (count == 0) return out;
  if (count * sizeof(gpu::Ray) > s_->rays.size() || count > s_->chunk_rays())
    throw Error("trace_resident: " + std::to_string(count) +
                " rays exceed the device-resident ray array or one dispatch");
  if (s_->predictor) s_->predictor->begin_trace(any_hit);
  s_->dispatch(count, any_hit, out, 0);
  if (s_->predictor) out.predictor = s_->predictor->counters(any_hit);
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
  s_->clock = 0;
}

}  // namespace hrpp
