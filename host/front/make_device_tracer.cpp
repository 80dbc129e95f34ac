#include "front/make_device_tracer.h"

#include <string>

#include "front/predicting_tracer.h"
#include "gpu/gpu_tracer.h"
#include "gpu/ray_query_tracer.h"
#include "kernels/device_bvh.h"
#include "vk/vulkan_context.h"

namespace hrpp {

std::vector<BufferNeed> device_tracer_needs(DeviceTracerKind kind, const GpuBvh& bvh,
                                            const PredictorConfig& predictor,
                                            std::size_t resident_rays) {
  const bool driver = kind == DeviceTracerKind::kRayQuery;
  std::vector<BufferNeed> needs = driver ? RayQueryTracer::buffer_needs(bvh, resident_rays)
                                         : GpuTracer::buffer_needs(bvh, resident_rays);
  if (!predictor.enabled) return needs;
  if (driver)
    for (BufferNeed& n : DeviceBvh::buffer_needs(bvh)) needs.push_back(std::move(n));
  for (BufferNeed& n : GpuPredictor::buffer_needs(bvh, predictor, resident_rays))
    needs.push_back(std::move(n));
  return needs;
}

std::size_t device_tracer_dispatch_rays(DeviceTracerKind kind, const DeviceInfo& device,
                                        const GpuTracerConfig& config) {
  return kind == DeviceTracerKind::kRayQuery ? RayQueryTracer::max_dispatch_rays(device, config)
                                             : GpuTracer::max_dispatch_rays(device, config);
}

namespace {

std::unique_ptr<DeviceTracer> make_plain(VulkanContext& ctx, DeviceTracerKind kind,
                                         const GpuBvh& bvh, const GpuTracerConfig& tracer,
                                         GpuBvh* release) {
  if (kind == DeviceTracerKind::kRayQuery)
    return std::make_unique<RayQueryTracer>(ctx, bvh, tracer);
  if (!release) return std::make_unique<GpuTracer>(ctx, bvh, tracer);
  return std::make_unique<GpuTracer>(ctx, *release, tracer, GpuTracer::FreeHostArrays{});
}

}  // namespace

std::unique_ptr<DeviceTracer> make_device_tracer(VulkanContext& ctx, DeviceTracerKind kind,
                                                 const GpuBvh& bvh, const GpuTracerConfig& tracer,
                                                 const PredictorConfig& predictor,
                                                 GpuBvh* release) {
  if (!predictor.enabled) return make_plain(ctx, kind, bvh, tracer, release);
  if (kind == DeviceTracerKind::kCompute)
    check_fits("the BVH of " + std::to_string(bvh.triangles.size()) + " triangles",
               device_tracer_needs(kind, bvh, predictor, 0), memory_limits(ctx.info()));
  GpuTracerConfig inner = tracer;
  inner.serial = predictor.serial && kind == DeviceTracerKind::kCompute;
  return std::make_unique<PredictingTracer>(
      ctx, bvh, predictor, [&] { return make_plain(ctx, kind, bvh, inner, release); });
}

}  // namespace hrpp
