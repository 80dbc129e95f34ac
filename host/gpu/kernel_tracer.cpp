#include "gpu/kernel_tracer.h"

#include <algorithm>
#include <string>
#include <vector>

#include "common/error.h"
#include "gpu/resident_rays.h"
#include "kernels/trace_counters.h"
#include "kernels/trace_lanes.h"
#include "vk/compute_pipeline.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"
#include "vk/vulkan_context.h"

namespace hrpp {

GpuTracerConfig GpuTracerConfig::resolved_for(const DeviceInfo& device) const {
  GpuTracerConfig c = *this;
  if (c.rays_per_invocation == 0)
    c.rays_per_invocation = device.type == VK_PHYSICAL_DEVICE_TYPE_CPU ? kCpuDeviceRaysPerInvocation
                                                                       : kGpuRaysPerInvocation;
  return c;
}

namespace {

// The resident arrays of one query kind (hit-all: camera and bounce rays; hit-any: shadow
// rays), its trace kernels and their counters. (ResidentRays: the rays the kernels read by
// ray_view, the hits they write by hit_view.)
struct QueryArrays : ResidentRays {
  StorageBuffer counters;  // gpu::TraceCounters
  QueueTraceKernel kernel;
  std::optional<ComputePipeline> indexed;

  QueryArrays(VulkanContext& c, QueryKind kind, const std::string& counters_name,
              QueueTraceKernel k, std::optional<ComputePipeline> ix)
      : counters(c, sizeof(gpu::TraceCounters),
                 std::string(query_kind_label(kind)) + " " + counters_name, BufferBinding::kStorage,
                 MemoryRole::kHostShared),
        kernel(std::move(k)),
        indexed(std::move(ix)) {
    for (ComputePipeline* p : pipelines()) p->bind(kernel.counters, counters);
  }

  std::vector<ComputePipeline*> pipelines() {
    std::vector<ComputePipeline*> p{&kernel.pipeline};
    if (indexed) p.push_back(&*indexed);
    return p;
  }
};

}  // namespace

struct KernelTracer::State {
  VulkanContext* ctx;
  GpuTracerConfig config;
  std::unique_ptr<QueryArrays> queries[2];  // [index_of(QueryKind)]
  KernelTimer timer;
  std::vector<gpu::Ray> probes;  // warm-up rays: through the scene's centre

  State(VulkanContext& c, const GpuTracerConfig& cfg, const Aabb& bounds)
      : ctx(&c),
        config(cfg.resolved_for(c.info())),
        timer(c, 16),  // HRPP's pilot schedule: two rounds of 3 dispatches; a sort: 7
        probes(warm_up_rays(bounds)) {}

  QueryArrays& query(RayClass c) { return *queries[index_of(query_kind(c))]; }
  const QueryArrays& query(RayClass c) const { return *queries[index_of(query_kind(c))]; }

  static TimerLabel label(const ComputePipeline& p, RayClass c) {
    return {p.kernel(), Phase::kRun, c};
  }
};

KernelTracer::KernelTracer(VulkanContext& ctx, const GpuTracerConfig& config, const Aabb& bounds)
    : s_(std::make_unique<State>(ctx, config, bounds)) {}
KernelTracer::~KernelTracer() = default;
KernelTracer::KernelTracer(KernelTracer&&) noexcept = default;
KernelTracer& KernelTracer::operator=(KernelTracer&&) noexcept = default;

void KernelTracer::set_kernels(QueryKind kind, const std::string& counters_name,
                               QueueTraceKernel kernel, std::optional<ComputePipeline> indexed) {
  s_->queries[index_of(kind)] = std::make_unique<QueryArrays>(
      *s_->ctx, kind, counters_name, std::move(kernel), std::move(indexed));
}

const GpuTracerConfig& KernelTracer::config() const { return s_->config; }

StorageBuffer& KernelTracer::ray_buffer(RayClass c, std::size_t rays) {
  QueryArrays& a = s_->query(c);
  if (a.reserve(*s_->ctx, query_kind(c), std::max<std::size_t>(rays, 1)))
    for (ComputePipeline* k : a.pipelines()) {
      k->bind(a.kernel.rays, a.ray_view);
      k->bind(a.kernel.hits, a.hit_view);
    }
  return a.rays;
}

StorageBuffer& KernelTracer::hit_buffer(RayClass c) { return s_->query(c).hits; }

ResidentRays& KernelTracer::resident(RayClass c) { return s_->query(c); }

const ResidentRays& KernelTracer::resident(RayClass c) const { return s_->query(c); }

void KernelTracer::begin(RayClass) {}

void KernelTracer::record(VkCommandBuffer cmd, RayClass c, std::uint32_t count, KernelTimer* timer,
                          const TexelView* ray_indices) {
  QueryArrays& a = s_->query(c);
  if (ray_indices && !a.indexed)
    throw Error(std::string("--reorder: ") + a.kernel.pipeline.name() +
                " traces rays in their order (--tracer compute traces a ray order)");
  check_resident(*this, c, count);
  ComputePipeline& k = ray_indices ? *a.indexed : a.kernel.pipeline;
  if (ray_indices) k.bind(HRPP_TRACE_BINDING_RAY_INDICES, *ray_indices);
  const gpu::TracePushConstants pc = push_constants();
  record_counters_start(cmd, a.counters, &count, nullptr, 0);
  const std::uint32_t per_group = rays_per_workgroup();
  record_dispatch(cmd, k, &pc, (count + per_group - 1) / per_group, timer, State::label(k, c));
}

void KernelTracer::record_indirect(VkCommandBuffer cmd, RayClass c, const StorageBuffer& queue,
                                   VkDeviceSize count_offset, VkDeviceSize args_offset,
                                   KernelTimer* timer) {
  check_sized(*this, c);
  QueryArrays& a = s_->query(c);
  const gpu::TracePushConstants pc = push_constants();
  record_counters_start(cmd, a.counters, nullptr, &queue, count_offset);
  record_dispatch_indirect(cmd, a.kernel.pipeline, &pc, queue, args_offset, timer,
                           State::label(a.kernel.pipeline, c));
}

// After the submit: the trace's counters, checked (every ray finished).
GpuTraceResult KernelTracer::finish(RayClass c) {
  const QueryArrays& a = s_->query(c);
  gpu::TraceCounters k{};
  a.counters.download(&k, sizeof k);
  GpuTraceResult out;
  out.counters = traversal_counters(k);
  const std::uint64_t done = out.counters.rays;
  if (done != k.ray_count || k.aborted != 0)
    throw Error(std::string(a.kernel.pipeline.name()) + ": only " + std::to_string(done) + " of " +
                std::to_string(k.ray_count) + " rays finished (" + std::to_string(k.aborted) +
                " cut short): the driver's loop limiter (lavapipe: 65,535 loop iterations per "
                "subgroup) ended the kernel's loops at " +
                std::to_string(s_->config.rays_per_invocation) +
                " rays per invocation; lower rays_per_invocation");
  out.traced = done;
  return out;
}

bool KernelTracer::records_indirect(RayClass) const { return true; }

bool KernelTracer::takes_ray_order(RayClass c) const { return s_->query(c).indexed.has_value(); }

std::uint32_t KernelTracer::rays_per_workgroup() const {
  return trace_lanes(s_->config.serial, s_->ctx->info().subgroup_size) *
         s_->config.rays_per_invocation;
}

// Rays per dispatch: what one storage buffer and one texel view hold and one dispatch's
// workgroups reach.
std::size_t KernelTracer::max_dispatch_rays(const DeviceInfo& d, const GpuTracerConfig& requested) {
  const GpuTracerConfig config = requested.resolved_for(d);
  const std::uint64_t by_range = std::min<std::uint64_t>(
      d.max_storage_buffer_range / sizeof(gpu::Ray),
      std::uint64_t{d.max_texel_buffer_elements} * TexelView::kTexelBytes / sizeof(gpu::Ray));
  const std::uint64_t by_groups = static_cast<std::uint64_t>(d.max_workgroup_count_x) *
                                  HRPP_TRACE_WORKGROUP_SIZE * config.rays_per_invocation;
  return static_cast<std::size_t>(std::min<std::uint64_t>({by_range, by_groups, 0xFFFFFFFFu}));
}

std::size_t KernelTracer::chunk_rays() const {
  return max_dispatch_rays(s_->ctx->info(), s_->config);
}

void KernelTracer::warm_up() {
  for (RayClass c : kRayClasses) trace(s_->probes, c);
}

VulkanContext& KernelTracer::context() const { return *s_->ctx; }

KernelTimer& KernelTracer::timer() { return s_->timer; }

gpu::TracePushConstants KernelTracer::push_constants() const {
  gpu::TracePushConstants pc{};
  pc.rays_per_invocation = s_->config.rays_per_invocation;
  pc.canary_iterations = HRPP_CANARY_ITERATIONS;
  pc.serial = s_->config.serial ? 1u : 0u;
  return pc;
}

const char* KernelTracer::kernel_label(RayClass c) const {
  return s_->query(c).kernel.pipeline.name();
}

}  // namespace hrpp
