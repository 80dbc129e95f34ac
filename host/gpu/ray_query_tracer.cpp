#include "gpu/ray_query_tracer.h"

#include <algorithm>
#include <array>
#include <limits>
#include <string>

#include "common/error.h"
#include "gpu/kernel_bindings.h"
#include "gpu/trace_counters.h"
#include "vk/compute_pipeline.h"
#include "vk/embedded_shaders.h"
#include "vk/storage_buffer.h"
#include "vk/texel_view.h"
#include "vk/vulkan_context.h"

namespace hrpp {
namespace {

constexpr std::uint32_t kCanaryIterations = 2;

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
struct RayQueryArrays {
  StorageBuffer rays, hits;  // grown on demand
  TexelView ray_view, hit_view;
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
  AccelerationStructure structure;
  std::unique_ptr<RayQueryArrays> queries[2];  // [index_of(QueryKind)]
  KernelTimer timer;
  gpu::Ray probe{};  // warm-up ray: through the scene's centre

  State(VulkanContext& c, const GpuBvh& bvh)
      : ctx(&c), structure(c, triangle_vertices(bvh)), timer(c, 4) {
    for (QueryKind kind : kQueryKinds)
      queries[index_of(kind)] = std::make_unique<RayQueryArrays>(c, kind, structure.top());
    const glm::vec3 centre = 0.5f * (bvh.bounds.lo + bvh.bounds.hi);
    probe.origin = centre - glm::vec3(bvh.bounds.hi.x - bvh.bounds.lo.x + 1.0f, 0.0f, 0.0f);
    probe.dir = {1.0f, 0.0f, 0.0f};
    probe.tmax = 1e30f;
  }

  RayQueryArrays& query(RayClass c) { return *queries[index_of(query_kind(c))]; }

  void ensure_capacity(RayClass c, std::size_t n) {
    RayQueryArrays& a = query(c);
    if (a.rays.size() >= n * sizeof(gpu::Ray)) return;
    a.ray_view = TexelView();
    a.hit_view = TexelView();
    a.rays = StorageBuffer();  // free first: one at a time in the heap
    a.hits = StorageBuffer();
    const std::string which = query_kind_label(query_kind(c));
    a.rays = StorageBuffer(*ctx, n * sizeof(gpu::Ray), which + " ray array");
    a.hits = StorageBuffer(*ctx, n * sizeof(gpu::Hit), which + " hit array");
    a.ray_view = TexelView(*ctx, a.rays);
    a.hit_view = TexelView(*ctx, a.hits);
    a.kernel.bind(HRPP_RAY_QUERY_BINDING_RAYS, a.ray_view);
    a.kernel.bind(HRPP_RAY_QUERY_BINDING_HITS, a.hit_view);
  }

  static gpu::TracePushConstants push_constants() {
    gpu::TracePushConstants pc{};
    pc.rays_per_invocation = 1;
    pc.canary_iterations = kCanaryIterations;
    return pc;
  }

  static TimerLabel label(const ComputePipeline& p, RayClass c) {
    return {p.kernel(), Phase::kRun, c};
  }

  GpuTraceResult finish(RayClass c) {
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
                  "subgroup) ended the kernel's loops");
    out.traced = out.counters.rays;
    return out;
  }

  GpuTraceResult trace_resident(std::uint32_t n, RayClass c) {
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
        count > RayQueryTracer::max_dispatch_rays(ctx->info()))
      throw Error("trace: " + std::to_string(count) +
                  " rays exceed the device-resident ray array or one dispatch");
    record_counters_start(cmd, a.counters, &count, nullptr, 0);
    const gpu::TracePushConstants pc = push_constants();
    record_dispatch(cmd, a.kernel, &pc, (count + HRPP_TRACE_WORKGROUP_SIZE - 1) /
                                            HRPP_TRACE_WORKGROUP_SIZE,
                    t, label(a.kernel, c));
  }
};

std::vector<BufferNeed> RayQueryTracer::buffer_needs(const GpuBvh& bvh,
                                                     std::size_t resident_rays) {
  std::uint64_t ids = 0;
  for (const gpu::TriangleRecord& t : bvh.triangles) ids = std::max<std::uint64_t>(ids, t.prim + 1);
  std::vector<BufferNeed> needs = {{"acceleration structure vertices", ids * 3 * sizeof(glm::vec3),
                                    BufferBinding::kAddressOnly}};
  for (QueryKind kind : kQueryKinds) {
    const std::string label = query_kind_label(kind);
    needs.push_back({label + " ray array", resident_rays * sizeof(gpu::Ray)});
    needs.push_back({label + " hit array", resident_rays * sizeof(gpu::Hit)});
  }
  return needs;
}

RayQueryTracer::RayQueryTracer(VulkanContext& ctx, const GpuBvh& bvh)
    : s_(std::make_unique<State>(ctx, bvh)) {}
RayQueryTracer::~RayQueryTracer() = default;
RayQueryTracer::RayQueryTracer(RayQueryTracer&&) noexcept = default;
RayQueryTracer& RayQueryTracer::operator=(RayQueryTracer&&) noexcept = default;

const AccelerationStructureStats& RayQueryTracer::structure() const {
  return s_->structure.stats();
}

std::size_t RayQueryTracer::max_dispatch_rays(const DeviceInfo& d) {
  const std::uint64_t by_range =
      std::min<std::uint64_t>(d.max_storage_buffer_range / sizeof(gpu::Ray),
                              std::uint64_t{d.max_texel_buffer_elements} * TexelView::kTexelBytes /
                                  sizeof(gpu::Ray));
  const std::uint64_t by_groups =
      static_cast<std::uint64_t>(d.max_workgroup_count_x) * HRPP_TRACE_WORKGROUP_SIZE;
  return static_cast<std::size_t>(std::min<std::uint64_t>({by_range, by_groups, 0xFFFFFFFFu}));
}

GpuTraceResult RayQueryTracer::trace(std::span<const gpu::Ray> rays, RayClass c) {
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (rays[i].tmin < 0.0f)
      throw Error("--tracer rayquery: ray " + std::to_string(i) + " has tmin " +
                  std::to_string(rays[i].tmin) +
                  " < 0; Vulkan's ray queries start at tmin >= 0 (--tracer compute takes it)");
  GpuTraceResult out;
  out.hits.resize(rays.size());
  const std::size_t chunk = max_dispatch_rays(s_->ctx->info());
  for (std::size_t first = 0; first < rays.size(); first += chunk) {
    const std::size_t n = std::min(chunk, rays.size() - first);
    s_->ensure_capacity(c, n);
    RayQueryArrays& a = s_->query(c);
    a.rays.upload(rays.data() + first, n * sizeof(gpu::Ray));
    const GpuTraceResult r = s_->trace_resident(static_cast<std::uint32_t>(n), c);
    a.hits.download(out.hits.data() + first, n * sizeof(gpu::Hit));
    out.counters += r.counters;
    out.kernel_ms += r.kernel_ms;
    out.traced += r.traced;
  }
  if (query_kind(c) == QueryKind::kAny) to_occlusion_records(out.hits);
  return out;
}

StorageBuffer& RayQueryTracer::ray_buffer(RayClass c, std::size_t rays) {
  s_->ensure_capacity(c, std::max<std::size_t>(rays, 1));
  return s_->query(c).rays;
}

StorageBuffer& RayQueryTracer::hit_buffer(RayClass c) { return s_->query(c).hits; }

void RayQueryTracer::begin(RayClass) {}

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
  RayQueryArrays& a = s_->query(c);
  if (a.rays.size() == 0)
    throw Error("trace: record_indirect before ray_buffer() sized the resident arrays");
  record_counters_start(cmd, a.counters, nullptr, &queue, count_offset);
  const gpu::TracePushConstants pc = State::push_constants();
  record_dispatch_indirect(cmd, a.kernel, &pc, queue, args_offset, timer,
                           State::label(a.kernel, c));
}

GpuTraceResult RayQueryTracer::finish(RayClass c) { return s_->finish(c); }

std::uint32_t RayQueryTracer::rays_per_workgroup() const { return HRPP_TRACE_WORKGROUP_SIZE; }

void RayQueryTracer::warm_up() {
  const std::vector<gpu::Ray> rays(HRPP_TRACE_WORKGROUP_SIZE, s_->probe);
  for (QueryKind kind : kQueryKinds) trace(rays, kind);
}

}  // namespace hrpp
