#include "gpu/gpu_tracer.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <string>

#include "common/error.h"
#include "common/free_array.h"
#include "vk/compute_pipeline.h"
#include "kernels/device_bvh.h"
#include "vk/embedded_shaders.h"
#include "kernels/kernel_bindings.h"
#include "hrpp/gpu_predictor.h"
#include "gpu/ray_sorter.h"
#include "gpu/resident_rays.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"
#include "kernels/trace_counters.h"
#include "vk/vulkan_context.h"
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
// shaders/lib/texel_fetch.glsl reads these records as 4 (4, 7), 1, 3 and 2 16-byte texels.
static_assert(sizeof(gpu::BvhNode) == 4 * TexelView::kTexelBytes);
static_assert(sizeof(gpu::WideNode) == 4 * TexelView::kTexelBytes);
static_assert(sizeof(gpu::WideFloatNode) == 7 * TexelView::kTexelBytes);
static_assert(sizeof(gpu::BvhLeaf) == 1 * TexelView::kTexelBytes);
static_assert(sizeof(gpu::Ray) == 2 * TexelView::kTexelBytes);

namespace {

// HRPP_SPEC_NODE_FORMAT's value for `f`.
std::uint32_t spec_value(NodeFormat f) {
  switch (f) {
    case NodeFormat::kBinary: return HRPP_NODES_BINARY;
    case NodeFormat::kWide4: return HRPP_NODES_WIDE;
    case NodeFormat::kWide4Float: return HRPP_NODES_WIDE_FLOAT;
  }
  return HRPP_NODES_BINARY;
}

// Before anything is allocated: the tracer's buffers against the device (vk/memory_plan.h),
// and HRPP's need for binary nodes.
void check_tracer_fits(const VulkanContext& ctx, const GpuBvh& bvh,
                       const PredictorConfig& predictor) {
  if (predictor.enabled && bvh.format() != NodeFormat::kBinary)
    throw Error(std::string("--bvh-nodes ") + node_format_name(bvh.format()) +
                " traces with HRPP off only: HRPP's predictor tests binary nodes");
  check_fits("the BVH of " + std::to_string(bvh.triangles.size()) + " triangles",
             GpuTracer::buffer_needs(bvh, predictor, 0), memory_limits(ctx.info()));
}

}  // namespace

std::vector<BufferNeed> GpuTracer::buffer_needs(const GpuBvh& bvh, const PredictorConfig& predictor,
                                                std::size_t resident_rays) {
  std::vector<BufferNeed> needs = DeviceBvh::buffer_needs(bvh);
  if (predictor.enabled)
    for (BufferNeed& n : GpuPredictor::buffer_needs(bvh, predictor, resident_rays))
      needs.push_back(std::move(n));
  for (BufferNeed& n : ResidentRays::needs(resident_rays)) needs.push_back(std::move(n));
  return needs;
}

// The resident arrays of one query kind (hit-all: camera and bounce rays; hit-any: shadow
// rays), its trace kernels (HRPP off, or a class that does not probe) and their counters.
// (ResidentRays: the rays the kernels read by ray_view, the hits the HRPP stage reads and
// writes by hit_view.)
struct QueryArrays : ResidentRays {
  StorageBuffer counters;    // TraceCounters of the plain trace
  ComputePipeline kernel;
  // The same kernel over a ray index list (trace_*_indexed.comp), timed under the same label.
  ComputePipeline indexed;

  // `count_steps`: the kernels count the interior loop's subgroup iterations
  // (GpuTracerConfig::count_steps); `nodes`: the node array holds them (--bvh-nodes).
  QueryArrays(VulkanContext& c, QueryKind kind, bool count_steps, NodeFormat nodes)
      : QueryArrays(c, kind,
                    std::array{SpecializationConstant{HRPP_SPEC_COUNT_STEPS, count_steps ? 1u : 0u},
                               SpecializationConstant{HRPP_SPEC_NODE_FORMAT, spec_value(nodes)}}) {}

  QueryArrays(VulkanContext& c, QueryKind kind, std::span<const SpecializationConstant> spec)
      : counters(c, sizeof(gpu::TraceCounters),
                 std::string(query_kind_label(kind)) + " trace counters", BufferBinding::kStorage,
                 MemoryRole::kHostShared),
        kernel(c, trace_kernel(kind), embedded_spirv(trace_kernel(kind)), kTraceBindingTypes,
               sizeof(gpu::TracePushConstants), spec),
        indexed(c, kernel.kernel(), embedded_spirv(trace_indexed_kernel(kind)),
                kTraceListBindingTypes, sizeof(gpu::TracePushConstants), spec) {
    for (ComputePipeline* k : {&kernel, &indexed}) k->bind(HRPP_TRACE_BINDING_COUNTERS, counters);
  }
};

GpuTracerConfig GpuTracerConfig::resolved_for(const DeviceInfo& device) const {
  GpuTracerConfig c = *this;
  if (c.rays_per_invocation == 0)
    c.rays_per_invocation = device.type == VK_PHYSICAL_DEVICE_TYPE_CPU
                                ? kCpuDeviceRaysPerInvocation
                                : kGpuRaysPerInvocation;
  return c;
}

struct GpuTracer::State {
  VulkanContext* ctx = nullptr;
  GpuTracerConfig config;
  DeviceBvh device_bvh;
  std::unique_ptr<QueryArrays> queries[2];        // [index_of(QueryKind)]
  KernelTimer timer;
  std::unique_ptr<GpuPredictor> predictor;  // HRPP on: routes the classes that probe
  gpu::Ray probe{};  // warm-up ray: through the scene's centre

  // With `release` (the same GpuBvh as `bvh`), each host array is freed once uploaded.
  State(VulkanContext& c, const GpuBvh& bvh, const GpuTracerConfig& cfg,
        const PredictorConfig& predictor_config, GpuBvh* release = nullptr)
      : ctx(&c),
        config((check_tracer_fits(c, bvh, predictor_config), cfg.resolved_for(c.info()))),
        device_bvh(c, bvh),
        timer(c, 16) {  // HRPP's pilot schedule: two rounds of 3 dispatches; a sort: 7
    for (QueryKind kind : kQueryKinds) {
      auto& q = queries[index_of(kind)];
      q = std::make_unique<QueryArrays>(c, kind, cfg.count_steps, bvh.format());
      for (ComputePipeline* k : {&q->kernel, &q->indexed}) device_bvh.bind(*k);
    }
    if (predictor_config.enabled)  // reads the host's arrays, not yet the device's
      predictor = std::make_unique<GpuPredictor>(c, bvh, predictor_config, device_bvh);
    const glm::vec3 centre = 0.5f * (bvh.bounds.lo + bvh.bounds.hi);
    probe.origin = centre - glm::vec3(bvh.bounds.hi.x - bvh.bounds.lo.x + 1.0f, 0.0f, 0.0f);
    probe.tmin = 0.0f;
    probe.dir = {1.0f, 0.0f, 0.0f};
    probe.tmax = 1e30f;
    device_bvh.upload(bvh, release);
  }

  QueryArrays& query(RayClass c) { return *queries[index_of(query_kind(c))]; }
  const QueryArrays& query(RayClass c) const { return *queries[index_of(query_kind(c))]; }
  Probe probing(RayClass c) const { return predictor ? predictor->probing(c) : Probe::kOff; }
  bool serial() const { return predictor && predictor->config().serial; }

  std::uint32_t rays_per_workgroup() const {
    if (predictor) return predictor->rays_per_workgroup(config.rays_per_invocation);
    return HRPP_TRACE_WORKGROUP_SIZE * config.rays_per_invocation;
  }

  std::size_t chunk_rays() const { return GpuTracer::max_dispatch_rays(ctx->info(), config); }

  QueryArrays& ensure_capacity(RayClass c, std::size_t n) {
    QueryArrays& a = query(c);
    if (!a.reserve(*ctx, query_kind(c), n)) return a;
    for (ComputePipeline* k : {&a.kernel, &a.indexed}) {
      k->bind(HRPP_TRACE_BINDING_RAYS, a.ray_view);
      k->bind(HRPP_TRACE_BINDING_HITS, a.hit_view);
    }
    if (predictor) predictor->bind_rays(query_kind(c), a.ray_view, a.hit_view, n);
    return a;
  }

  gpu::TracePushConstants push_constants() const {
    gpu::TracePushConstants pc{};
    pc.rays_per_invocation = config.rays_per_invocation;
    pc.canary_iterations = HRPP_CANARY_ITERATIONS;
    pc.serial = serial() ? 1u : 0u;
    return pc;
  }

  // Before a plain recorded trace: the kind's counters zeroed, with their ray count.
  void prepare_trace(VkCommandBuffer cmd, RayClass c, const std::uint32_t* count,
                     const StorageBuffer* queue, VkDeviceSize count_offset) {
    record_counters_start(cmd, query(c).counters, count, queue, count_offset);
  }

  static TimerLabel label(const ComputePipeline& p, RayClass c) {
    return {p.kernel(), Phase::kRun, c};
  }

  // The plain trace kernel, or with `ray_indices` its indexed twin reading them.
  ComputePipeline& plain_kernel(RayClass c, const TexelView* ray_indices) {
    if (!ray_indices) return query(c).kernel;
    query(c).indexed.bind(HRPP_TRACE_BINDING_RAY_INDICES, *ray_indices);
    return query(c).indexed;
  }

  void record(VkCommandBuffer cmd, RayClass c, std::uint32_t count, KernelTimer* t,
              const TexelView* ray_indices) {
    check_resident(c, count);
    const gpu::TracePushConstants pc = push_constants();
    if (predictor && predictor->record_trace(cmd, c, RayCountSource{&count}, pc, t)) return;
    prepare_trace(cmd, c, &count, nullptr, 0);
    ComputePipeline& k = plain_kernel(c, ray_indices);
    const std::uint32_t per_group = rays_per_workgroup();
    record_dispatch(cmd, k, &pc, (count + per_group - 1) / per_group, t, label(k, c));
  }

  void record_indirect(VkCommandBuffer cmd, RayClass c, const StorageBuffer& queue,
                       VkDeviceSize count_offset, VkDeviceSize args_offset, KernelTimer* t) {
    if (!records_indirect(c))
      throw Error("trace: HRPP's batched mode (--hrpp-batch) needs the ray count on the host");
    if (query(c).rays.size() == 0)
      throw Error("trace: record_indirect before ray_buffer() sized the resident arrays");
    const gpu::TracePushConstants pc = push_constants();
    const RayCountSource source{nullptr, &queue, count_offset, args_offset};
    if (predictor && predictor->record_trace(cmd, c, source, pc, t)) return;
    prepare_trace(cmd, c, nullptr, &queue, count_offset);
    ComputePipeline& k = query(c).kernel;
    record_dispatch_indirect(cmd, k, &pc, queue, args_offset, t, label(k, c));
  }

  bool records_indirect(RayClass c) const { return !predictor || predictor->records_indirect(c); }

  void check_resident(RayClass c, std::size_t count) const {
    if (count * sizeof(gpu::Ray) > query(c).rays.size() || count > chunk_rays())
      throw Error("trace: " + std::to_string(count) +
                  " rays exceed the device-resident ray array or one dispatch");
  }

  // After the submit: the plain trace's counters, checked (every ray finished).
  GpuTraceResult finish_plain(RayClass c) const {
    GpuTraceResult out;
    gpu::TraceCounters k{};
    query(c).counters.download(&k, sizeof k);
    out.counters = traversal_counters(k);
    const std::uint64_t done = out.counters.rays;
    if (done != k.ray_count || k.aborted != 0)
      throw Error(std::string(query(c).kernel.name()) + ": only " + std::to_string(done) + " of " +
                  std::to_string(k.ray_count) + " rays finished (" + std::to_string(k.aborted) +
                  " cut short): the driver's loop limiter (lavapipe: 65,535 loop iterations per "
                  "subgroup) ended the kernel's loops at " +
                  std::to_string(config.rays_per_invocation) +
                  " rays per invocation; lower rays_per_invocation");
    out.traced = done;
    return out;
  }

  GpuTraceResult finish(RayClass c) {
    return finish_trace(predictor.get(), c, [&] { return finish_plain(c); });
  }
};

GpuTracer::GpuTracer(VulkanContext& ctx, const GpuBvh& bvh, const GpuTracerConfig& config,
                     const PredictorConfig& predictor)
    : s_(std::make_unique<State>(ctx, bvh, config, predictor)) {}

GpuTracer::GpuTracer(VulkanContext& ctx, GpuBvh& bvh, const GpuTracerConfig& config,
                     const PredictorConfig& predictor, FreeHostArrays)
    : s_(std::make_unique<State>(ctx, bvh, config, predictor, &bvh)) {}

GpuTracer::~GpuTracer() = default;
GpuTracer::GpuTracer(GpuTracer&&) noexcept = default;
GpuTracer& GpuTracer::operator=(GpuTracer&&) noexcept = default;

const GpuTracerConfig& GpuTracer::config() const { return s_->config; }

GpuPredictor* GpuTracer::predictor() { return s_->predictor.get(); }

const GpuPredictor* GpuTracer::predictor() const { return s_->predictor.get(); }

GpuTraceResult GpuTracer::trace(std::span<const gpu::Ray> rays, RayClass c, RaySorter* sorter) {
  return trace_in_chunks(
      rays, c, s_->chunk_rays(),
      [&](std::size_t n) -> ResidentRays& { return s_->ensure_capacity(c, n); },
      [&](std::size_t n) { return trace_resident(n, c, sorter); });
}

StorageBuffer& GpuTracer::ray_buffer(RayClass c, std::size_t rays) {
  s_->ensure_capacity(c, std::max<std::size_t>(rays, 1));
  return s_->query(c).rays;
}

StorageBuffer& GpuTracer::hit_buffer(RayClass c) { return s_->query(c).hits; }

void GpuTracer::begin(RayClass c) {
  if (s_->predictor) s_->predictor->begin(c);
}

void GpuTracer::record(VkCommandBuffer cmd, RayClass c, std::uint32_t count, KernelTimer* timer,
                       const TexelView* ray_indices) {
  s_->record(cmd, c, count, timer, ray_indices);
}

void GpuTracer::record_indirect(VkCommandBuffer cmd, RayClass c, const StorageBuffer& queue,
                                VkDeviceSize count_offset, VkDeviceSize args_offset,
                                KernelTimer* timer) {
  s_->record_indirect(cmd, c, queue, count_offset, args_offset, timer);
}

GpuTraceResult GpuTracer::finish(RayClass c) { return s_->finish(c); }

bool GpuTracer::records_indirect(RayClass c) const { return s_->records_indirect(c); }

std::uint32_t GpuTracer::rays_per_workgroup() const { return s_->rays_per_workgroup(); }


// Rays per dispatch: what one storage buffer and one texel view hold and one dispatch's
// workgroups reach.
std::size_t GpuTracer::max_dispatch_rays(const DeviceInfo& d, const GpuTracerConfig& requested) {
  const GpuTracerConfig config = requested.resolved_for(d);
  const std::uint64_t by_range =
      std::min<std::uint64_t>(d.max_storage_buffer_range / sizeof(gpu::Ray),
                              std::uint64_t{d.max_texel_buffer_elements} * TexelView::kTexelBytes /
                                  sizeof(gpu::Ray));
  const std::uint64_t by_groups = static_cast<std::uint64_t>(d.max_workgroup_count_x) *
                                  HRPP_TRACE_WORKGROUP_SIZE * config.rays_per_invocation;
  return static_cast<std::size_t>(std::min<std::uint64_t>({by_range, by_groups, 0xFFFFFFFFu}));
}

GpuTraceResult GpuTracer::trace_resident(std::size_t count, RayClass c, RaySorter* sorter) {
  if (count == 0) return {};
  begin(c);
  const auto n = static_cast<std::uint32_t>(count);
  const bool sorted = sorter && s_->probing(c) != Probe::kAll;  // HRPP's stage keeps queue order
  if (sorted) sorter->bind_rays(s_->query(c).ray_view);
  s_->ctx->submit_and_wait(
      [&](VkCommandBuffer cmd) {
        s_->timer.reset(cmd);
        if (sorted) sorter->record(cmd, n, &s_->timer);
        s_->record(cmd, c, n, &s_->timer, sorted ? &sorter->order_view() : nullptr);
      },
      s_->query(c).kernel.name());
  if (sorted) sorter->finish(n);
  GpuTraceResult out = s_->finish(c);
  for (const auto& [label, ms] : s_->timer.read_ms()) {
    out.kernel_ms += ms;
    if (is_ray_sort(label.kernel)) out.sort_ms += ms;
  }
  return out;
}

void GpuTracer::warm_up() {
  const std::vector<gpu::Ray> rays(HRPP_TRACE_WORKGROUP_SIZE, s_->probe);
  warm_up_stage(s_->predictor.get(), [&](RayClass c) { trace(rays, c); });
}

}  // namespace hrpp
