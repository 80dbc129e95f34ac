#include "gpu/resident_rays.h"

#include <algorithm>
#include <string>

#include "vk/vulkan_context.h"

namespace hrpp {

bool ResidentRays::reserve(VulkanContext& ctx, QueryKind kind, std::size_t n) {
  if (rays.size() >= n * sizeof(gpu::Ray)) return false;
  ray_view = TexelView();
  hit_view = TexelView();
  rays = StorageBuffer();
  hits = StorageBuffer();
  const std::string which = query_kind_label(kind);
  rays = StorageBuffer(ctx, n * sizeof(gpu::Ray), which + " ray array");
  hits = StorageBuffer(ctx, n * sizeof(gpu::Hit), which + " hit array");
  ray_view = TexelView(ctx, rays);
  hit_view = TexelView(ctx, hits);
  return true;
}

std::vector<BufferNeed> ResidentRays::needs(std::size_t rays) {
  std::vector<BufferNeed> out;
  for (QueryKind kind : kQueryKinds) {
    const std::string label = query_kind_label(kind);
    out.push_back({label + " ray array", rays * sizeof(gpu::Ray)});
    out.push_back({label + " hit array", rays * sizeof(gpu::Hit)});
  }
  return out;
}

GpuTraceResult trace_in_chunks(std::span<const gpu::Ray> rays, RayClass c, std::size_t chunk,
                               const std::function<ResidentRays&(std::size_t)>& resident,
                               const std::function<GpuTraceResult(std::size_t)>& trace) {
  GpuTraceResult out;
  out.hits.resize(rays.size());
  for (std::size_t first = 0; first < rays.size(); first += chunk) {
    const std::size_t n = std::min(chunk, rays.size() - first);
    ResidentRays& a = resident(n);
    a.rays.upload(rays.data() + first, n * sizeof(gpu::Ray));
    const GpuTraceResult r = trace(n);
    a.hits.download(out.hits.data() + first, n * sizeof(gpu::Hit));
    out.counters += r.counters;
    out.kernel_ms += r.kernel_ms;
    out.sort_ms += r.sort_ms;
    out.traced += r.traced;
    out.predicted = r.predicted;
    out.sampled += r.sampled;
    out.predictor += r.predictor;
  }
  if (query_kind(c) == QueryKind::kAny) to_occlusion_records(out.hits);
  return out;
}

}  // namespace hrpp
