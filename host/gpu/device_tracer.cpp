#include "gpu/device_tracer.h"

#include <string>

#include "common/error.h"
#include "gpu/ray_sorter.h"
#include "gpu/resident_rays.h"
#include "vk/compute_pipeline.h"
#include "vk/timer_label.h"
#include "vk/vulkan_context.h"

namespace hrpp {

GpuTraceResult DeviceTracer::trace(std::span<const gpu::Ray> rays, RayClass c, RaySorter* sorter) {
  check_rays(rays);
  return trace_in_chunks(
      rays, c, chunk_rays(),
      [&](std::size_t n) -> ResidentRays& {
        ray_buffer(c, n);
        return resident(c);
      },
      [&](std::size_t n) { return trace_resident(n, c, sorter); });
}

GpuTraceResult DeviceTracer::trace_resident(std::size_t count, RayClass c, RaySorter* sorter) {
  if (count == 0) return {};
  begin(c);
  const auto n = static_cast<std::uint32_t>(count);
  const bool sorted = sorter && takes_ray_order(c);
  if (sorted) sorter->bind_rays(resident(c).ray_view);
  KernelTimer& t = timer();
  context().submit_and_wait(
      [&](VkCommandBuffer cmd) {
        t.reset(cmd);
        if (sorted) sorter->record(cmd, n, &t);
        record(cmd, c, n, &t, sorted ? &sorter->order_view() : nullptr);
      },
      kernel_label(c));
  if (sorted) sorter->finish(n);
  GpuTraceResult out = finish(c);
  for (const auto& [label, ms] : t.read_ms()) {
    out.kernel_ms += ms;
    if (is_ray_sort(label.kernel)) out.sort_ms += ms;
  }
  return out;
}

void check_resident(const DeviceTracer& tracer, RayClass c, std::size_t count) {
  if (count * sizeof(gpu::Ray) > tracer.resident(c).rays.size() || count > tracer.chunk_rays())
    throw Error("trace: " + std::to_string(count) +
                " rays exceed the device-resident ray array or one dispatch");
}

void check_sized(const DeviceTracer& tracer, RayClass c) {
  if (tracer.resident(c).rays.size() == 0)
    throw Error("trace: record_indirect before ray_buffer() sized the resident arrays");
}

std::vector<gpu::Ray> warm_up_rays(const Aabb& bounds) {
  gpu::Ray probe{};
  probe.origin = bounds.center() - glm::vec3(bounds.hi.x - bounds.lo.x + 1.0f, 0.0f, 0.0f);
  probe.tmin = 0.0f;
  probe.dir = {1.0f, 0.0f, 0.0f};
  probe.tmax = 1e30f;
  return std::vector<gpu::Ray>(HRPP_TRACE_WORKGROUP_SIZE, probe);
}

}  // namespace hrpp
