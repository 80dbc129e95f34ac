#include "gpu/ray_query_tracer.h"

#include <algorithm>
#include <limits>
#include <string>

#include "common/error.h"
#include "kernels/device_bvh.h"
#include "hrpp/gpu_predictor.h"
#include "gpu/gpu_tracer.h"
#include "kernels/kernel_bindings.h"
#include "gpu/resident_rays.h"
#include "kernels/trace_counters.h"
#include "vk/compute_pipeline.h"
#include "vk/embedded_shaders.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"
#include "vk/vulkan_context.h"

namespace hrpp {
namespace {

// Three vertices per triangle id, from the records (an SBVH may hold an id more than once);
// ids no record holds get a NaN first vertex, which makes them inactive.
std::vector<glm::vec3> triangle_vertices(const GpuBvh& bvh) {
  std::uint32_t count = 0;
  for (const gpu::TriangleRecord& t : bvh.triangles) count = std::max(count, t.prim + 1);
  std::vector<glm::vec3> v(std::size_t{count} * 3,
                           glm::vec3(std::numeric_limits<float>::quiet_NaN()));
  for (const gpu::TriangleRecord& t : bvh.triangles) {
    v[3 * std::size_t{t.prim}] = t.v0;
    v[3 * std::size_t{t.prim} + 1] = t.v1;
    v[3 * std::size_t{t.prim} + 2] = t.v2;
  }
  return v;
}

}  // namespace

// The resident arrays of one query kind, its kernel and its counters.
struct RayQueryArrays : ResidentRays {
  StorageBuffer counters;
  ComputePipeline kernel;

  RayQueryArrays(VulkanContext& c, QueryKind kind, VkAccelerationStructureKHR scene)
      : counters(c, sizeof(gpu::TraceCounters),
                 std::string(query_kind_label(kind)) + " ray-query counters",
                 BufferBinding::kStorage, MemoryRole::kHostShared),
        kernel(c, ray_query_kernel(kind), embedded_spirv(kernel_name(ray_query_kernel(kind))),
               kRayQueryBindingTypes, sizeof(gpu::TracePushConstants)) {
    kernel.bind(HRPP_RAY_QUERY_BINDING_SCENE, scene);
    kernel.bind(HRPP_RAY_QUERY_BINDING_COUNTERS, counters);
  }
};

struct RayQueryTracer::State {
  VulkanContext* ctx;
  GpuTracerConfig config;
  AccelerationStructure structure;
  std::unique_ptr<RayQueryArrays> queries[2];  // [index_of(QueryKind)]
  DeviceBvh device_bvh;                        // HRPP on: what the stage verifies on
  std::unique_ptr<GpuPredictor> predictor;     // HRPP on: in front of the ray queries
  KernelTimer timer;
  gpu::Ray probe{};  // warm-up ray: through the scene's centre

  State(VulkanContext& c, const GpuBvh& bvh, const GpuTracerConfig& cfg,
        const PredictorConfig& predictor_config)
      : ctx(&c),
        config(cfg.resolved_for(c.info())),
        structure(c, triangle_vertices(bvh)),
        timer(c, 16) {  // HRPP's pilot schedule: two rounds of 3 dispatches
    for (QueryKind kind : kQueryKinds)
      queries[index_of(kind)] = std::make_unique<RayQueryArrays>(c, kind, structure.top());
    if (predictor_config.enabled) {
      if (bvh.format() != NodeFormat::kBinary)
        throw Error("HRPP's predictor tests binary nodes (--bvh-nodes binary)");
      device_bvh = DeviceBvh(c, bvh);
      predictor = std::make_unique<GpuPredictor>(c, bvh, predictor_config, device_bvh,
                                                 structure.top());
      device_bvh.upload(bvh);
    }
    const glm::vec3 centre = 0.5f * (bvh.bounds.lo + bvh.bounds.hi);
    probe.origin = centre - glm::vec3(bvh.bounds.hi.x - bvh.bounds.lo.x + 1.0f, 0.0f, 0.0f);
    probe.dir = {1.0f, 0.0f, 0.0f};
    probe.tmax = 1e30f;
  }

  RayQueryArrays& query(RayClass c) { return *queries[index_of(query_kind(c))]; }

  RayQueryArrays& ensure_capacity(RayClass c, std::size_t n) {
    RayQueryArrays& a = query(c);
    if (!a.reserve(*ctx, query_kind(c), n)) return a;
    a.kernel.bind(HRPP_RAY_QUERY_BINDING_RAYS, a.ray_view);
    a.kernel.bind(HRPP_RAY_QUERY_BINDING_HITS, a.hit_view);
    if (predictor) predictor->bind_rays(query_kind(c), a.ray_view, a.hit_view, n);
    return a;
  }

  gpu::TracePushConstants push_constants() const {
    gpu::TracePushConstants pc{};
    pc.rays_per_invocation = config.rays_per_invocation;
    pc.canary_iterations = HRPP_CANARY_ITERATIONS;
    return pc;
  }

  std::uint32_t rays_per_workgroup() const {
    if (predictor) return predictor->rays_per_workgroup(config.rays_per_invocation);
    return HRPP_TRACE_WORKGROUP_SIZE * config.rays_per_invocation;
  }

  static TimerLabel label(const ComputePipeline& p, RayClass c) {
    return {p.kernel(), Phase::kRun, c};
  }

  GpuTraceResult finish(RayClass c) {
    return finish_trace(predictor.get(), c, [&] { return finish_plain(c); });
  }

  GpuTraceResult finish_plain(RayClass c) {
    RayQueryArrays& a = query(c);
    gpu::TraceCounters k{};
    a.counters.download(&k, sizeof k);
    GpuTraceResult out;
    out.counters = traversal_counters(k);
    if (out.counters.rays != k.ray_count || k.aborted != 0)
      throw Error(std::string(a.kernel.name()) + ": only " + std::to_string(out.counters.rays) +
                  " of " + std::to_string(k.ray_count) + " rays finished (" +
                  std::to_string(k.aborted) +
                  " cut short): the driver's loop limiter (lavapipe: 65,535 loop iterations per "
                  "subgroup) ended the kernel's loops; lower rays_per_invocation");
    out.traced = out.counters.rays;
    return out;
  }

  GpuTraceResult trace_resident(std::uint32_t n, RayClass c) {
    if (predictor) predictor->begin(c);
    ctx->submit_and_wait(
        [&](VkCommandBuffer cmd) {
          timer.reset(cmd);
          record(cmd, c, n, &timer);
        },
        query(c).kernel.name());
    GpuTraceResult out = finish(c);
    for (const auto& [label, ms] : timer.read_ms()) out.kernel_ms += ms;
    return out;
  }

  void record(VkCommandBuffer cmd, RayClass c, std::uint32_t count, KernelTimer* t) {
    RayQueryArrays& a = query(c);
    if (count * sizeof(gpu::Ray) > a.rays.size() ||
        count > RayQueryTracer::max_dispatch_rays(ctx->info(), config))
      throw Error("trace: " + std::to_string(count) +
                  " rays exceed the device-resident ray array or one dispatch");
    const gpu::TracePushConstants pc = push_constants();
    if (predictor && predictor->record_trace(cmd, c, RayCountSource{&count}, pc, t)) return;
    record_counters_start(cmd, a.counters, &count, nullptr, 0);
    const std::uint32_t per_group = rays_per_workgroup();
    record_dispatch(cmd, a.kernel, &pc, (count + per_group - 1) / per_group, t,
                    label(a.kernel, c));
  }

  void record_indirect(VkCommandBuffer cmd, RayClass c, const StorageBuffer& queue,
                       VkDeviceSize count_offset, VkDeviceSize args_offset, KernelTimer* t) {
    RayQueryArrays& a = query(c);
    if (a.rays.size() == 0)
      throw Error("trace: record_indirect before ray_buffer() sized the resident arrays");
    if (predictor && !predictor->records_indirect(c))
      throw Error("trace: HRPP's batched mode (--hrpp-batch) needs the ray count on the host");
    const gpu::TracePushConstants pc = push_constants();
    const RayCountSource source{nullptr, &queue, count_offset, args_offset};
    if (predictor && predictor->record_trace(cmd, c, source, pc, t)) return;
    record_counters_start(cmd, a.counters, nullptr, &queue, count_offset);
    record_dispatch_indirect(cmd, a.kernel, &pc, queue, args_offset, t, label(a.kernel, c));
  }
};

std::vector<BufferNeed> RayQueryTracer::buffer_needs(const GpuBvh& bvh,
                                                     const PredictorConfig& predictor,
                                                     std::size_t resident_rays) {
  std::uint64_t ids = 0;
  for (const gpu::TriangleRecord& t : bvh.triangles) ids = std::max<std::uint64_t>(ids, t.prim + 1);
  std::vector<BufferNeed> needs = {{"acceleration structure vertices", ids * 3 * sizeof(glm::vec3),
                                    BufferBinding::kAddressOnly}};
  if (predictor.enabled) {
    for (BufferNeed& n : DeviceBvh::buffer_needs(bvh)) needs.push_back(std::move(n));
    for (BufferNeed& n : GpuPredictor::buffer_needs(bvh, predictor, resident_rays))
      needs.push_back(std::move(n));
  }
  for (BufferNeed& n : ResidentRays::needs(resident_rays)) needs.push_back(std::move(n));
  return needs;
}

RayQueryTracer::RayQueryTracer(VulkanContext& ctx, const GpuBvh& bvh,
                               const GpuTracerConfig& config, const PredictorConfig& predictor)
    : s_(std::make_unique<State>(ctx, bvh, config, predictor)) {}
RayQueryTracer::~RayQueryTracer() = default;
RayQueryTracer::RayQueryTracer(RayQueryTracer&&) noexcept = default;
RayQueryTracer& RayQueryTracer::operator=(RayQueryTracer&&) noexcept = default;

const AccelerationStructureStats& RayQueryTracer::structure() const {
  return s_->structure.stats();
}

std::size_t RayQueryTracer::max_dispatch_rays(const DeviceInfo& d, const GpuTracerConfig& config) {
  return GpuTracer::max_dispatch_rays(d, config);  // the same arrays and workgroups
}

GpuPredictor* RayQueryTracer::predictor() { return s_->predictor.get(); }
const GpuPredictor* RayQueryTracer::predictor() const { return s_->predictor.get(); }

GpuTraceResult RayQueryTracer::trace(std::span<const gpu::Ray> rays, RayClass c) {
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (rays[i].tmin < 0.0f)
      throw Error("--tracer rayquery: ray " + std::to_string(i) + " has tmin " +
                  std::to_string(rays[i].tmin) +
                  " < 0; Vulkan's ray queries start at tmin >= 0 (--tracer compute takes it)");
  return trace_in_chunks(
      rays, c, max_dispatch_rays(s_->ctx->info(), s_->config),
      [&](std::size_t n) -> ResidentRays& { return s_->ensure_capacity(c, n); },
      [&](std::size_t n) { return s_->trace_resident(static_cast<std::uint32_t>(n), c); });
}

StorageBuffer& RayQueryTracer::ray_buffer(RayClass c, std::size_t rays) {
  s_->ensure_capacity(c, std::max<std::size_t>(rays, 1));
  return s_->query(c).rays;
}

StorageBuffer& RayQueryTracer::hit_buffer(RayClass c) { return s_->query(c).hits; }

void RayQueryTracer::begin(RayClass c) {
  if (s_->predictor) s_->predictor->begin(c);
}

void RayQueryTracer::record(VkCommandBuffer cmd, RayClass c, std::uint32_t count,
                            KernelTimer* timer, const TexelView* ray_indices) {
  if (ray_indices)
    throw Error("--reorder: the ray-query tracer traces rays in their order (--tracer compute "
                "traces a ray order)");
  s_->record(cmd, c, count, timer);
}

void RayQueryTracer::record_indirect(VkCommandBuffer cmd, RayClass c, const StorageBuffer& queue,
                                     VkDeviceSize count_offset, VkDeviceSize args_offset,
                                     KernelTimer* timer) {
  s_->record_indirect(cmd, c, queue, count_offset, args_offset, timer);
}

GpuTraceResult RayQueryTracer::finish(RayClass c) { return s_->finish(c); }

bool RayQueryTracer::records_indirect(RayClass c) const {
  return !s_->predictor || s_->predictor->records_indirect(c);
}

std::uint32_t RayQueryTracer::rays_per_workgroup() const { return s_->rays_per_workgroup(); }

void RayQueryTracer::warm_up() {
  const std::vector<gpu::Ray> rays(HRPP_TRACE_WORKGROUP_SIZE, s_->probe);
  warm_up_stage(s_->predictor.get(), [&](RayClass c) { trace(rays, c); });
}

}  // namespace hrpp
