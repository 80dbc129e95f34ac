#include "gpu/ray_query_tracer.h"

#include <algorithm>
#include <limits>
#include <string>

#include "common/error.h"
#include "kernels/kernel_bindings.h"
#include "gpu/resident_rays.h"
#include "vk/compute_pipeline.h"
#include "vk/embedded_shaders.h"
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

std::vector<BufferNeed> RayQueryTracer::buffer_needs(const GpuBvh& bvh,
                                                     std::size_t resident_rays) {
  std::uint64_t ids = 0;
  for (const gpu::TriangleRecord& t : bvh.triangles) ids = std::max<std::uint64_t>(ids, t.prim + 1);
  std::vector<BufferNeed> needs = {{"acceleration structure vertices", ids * 3 * sizeof(glm::vec3),
                                    BufferBinding::kAddressOnly}};
  for (BufferNeed& n : ResidentRays::needs(resident_rays)) needs.push_back(std::move(n));
  return needs;
}

RayQueryTracer::RayQueryTracer(VulkanContext& ctx, const GpuBvh& bvh,
                               const GpuTracerConfig& config)
    : KernelTracer(ctx, config, bvh.bounds), structure_(ctx, triangle_vertices(bvh)) {
  for (QueryKind kind : kQueryKinds) set_kernels(kind, "ray-query counters", queue_kernel(kind, false));
}

void RayQueryTracer::check_rays(std::span<const gpu::Ray> rays) const {
  for (std::size_t i = 0; i < rays.size(); ++i)
    if (rays[i].tmin < 0.0f)
      throw Error("--tracer rayquery: ray " + std::to_string(i) + " has tmin " +
                  std::to_string(rays[i].tmin) +
                  " < 0; Vulkan's ray queries start at tmin >= 0 (--tracer compute takes it)");
}

QueueTraceKernel RayQueryTracer::queue_kernel(QueryKind kind, bool skip_lists) const {
  if (skip_lists)
    throw Error("fallback skip: skip lists are the BVH kernels'; in front of the "
                "driver's ray queries use fallback root");
  QueueTraceKernel q{ComputePipeline(context(), ray_query_kernel(kind),
                                     embedded_spirv(ray_query_kernel(kind)), kRayQueryBindingTypes,
                                     sizeof(gpu::TracePushConstants)),
                     HRPP_RAY_QUERY_BINDING_RAYS, HRPP_RAY_QUERY_BINDING_HITS,
                     HRPP_RAY_QUERY_BINDING_COUNTERS};
  q.pipeline.bind(HRPP_RAY_QUERY_BINDING_SCENE, structure_.top());
  return q;
}

}  // namespace hrpp
