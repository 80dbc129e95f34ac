#include "front/predicting_tracer.h"

#include <string>

#include "common/error.h"
#include "gpu/resident_rays.h"
#include "vk/vulkan_context.h"

namespace hrpp {

PredictingTracer::PredictingTracer(VulkanContext& ctx, const GpuBvh& bvh,
                                   const PredictorConfig& config,
                                   const std::function<std::unique_ptr<DeviceTracer>()>& make_inner)
    : probes(warm_up_rays(bvh.bounds)) {
  if (bvh.format() != NodeFormat::kBinary)
    throw Error(std::string("--bvh-nodes ") + node_format_name(bvh.format()) +
                " traces with HRPP off only: HRPP's predictor tests binary nodes");
  predictor_ = std::make_unique<GpuPredictor>(ctx, bvh, config);  // reads the host's arrays
  inner_ = make_inner();
  const DeviceBvh* verify_on = inner_->device_bvh();
  if (!verify_on) {
    own_bvh_ = DeviceBvh(ctx, bvh);
    own_bvh_.upload(bvh);
    verify_on = &own_bvh_;
  }
  predictor_->connect(*verify_on, [&](QueryKind kind, bool skip_lists) {
    return inner_->queue_kernel(kind, skip_lists);
  });
}

PredictingTracer::~PredictingTracer() = default;

void PredictingTracer::bind_resident(RayClass c) {
  const ResidentRays& r = inner_->resident(c);
  std::size_t& bound = bound_bytes_[index_of(query_kind(c))];
  if (r.rays.size() == bound) return;
  predictor_->bind_rays(query_kind(c), r.ray_view, r.hit_view, r.rays.size() / sizeof(gpu::Ray));
  bound = r.rays.size();
}

StorageBuffer& PredictingTracer::ray_buffer(RayClass c, std::size_t rays) {
  StorageBuffer& b = inner_->ray_buffer(c, rays);
  bind_resident(c);
  return b;
}

void PredictingTracer::begin(RayClass c) {
  predictor_->begin(c);
  inner_->begin(c);
}

void PredictingTracer::record(VkCommandBuffer cmd, RayClass c, std::uint32_t count,
                              KernelTimer* timer, const TexelView* ray_indices) {
  if (ray_indices && !inner_->takes_ray_order(c))  // the inner tracer refuses the list
    return inner_->record(cmd, c, count, timer, ray_indices);
  check_resident(*this, c, count);
  if (predictor_->record_trace(cmd, c, RayCountSource{&count}, push_constants(), timer)) return;
  inner_->record(cmd, c, count, timer, ray_indices);
}

void PredictingTracer::record_indirect(VkCommandBuffer cmd, RayClass c, const StorageBuffer& queue,
                                       VkDeviceSize count_offset, VkDeviceSize args_offset,
                                       KernelTimer* timer) {
  if (!records_indirect(c))
    throw Error("trace: HRPP's batched mode (batch) needs the ray count on the host");
  check_sized(*this, c);
  const RayCountSource source{nullptr, &queue, count_offset, args_offset};
  if (predictor_->record_trace(cmd, c, source, push_constants(), timer)) return;
  inner_->record_indirect(cmd, c, queue, count_offset, args_offset, timer);
}

// The stage's result when it traced class `c` (Probe::kAll), else the inner tracer's, with a
// sample's predictor counters beside it; then the class's clock advances.
GpuTraceResult PredictingTracer::finish(RayClass c) {
  const Probe ran = predictor_->recorded(c);
  GpuTraceResult out;
  if (ran == Probe::kAll) {
    const PredictedTrace p = predictor_->finish(c);
    out.counters = p.counters;
    out.predictor = p.predictor;
    out.traced = p.queued;
    out.predicted = true;
  } else {
    out = inner_->finish(c);
  }
  if (ran == Probe::kSample) {
    const PredictedTrace p = predictor_->finish(c);
    out.predictor = p.predictor;
    out.sampled = p.counters.rays;
  }
  predictor_->advance_clock(c, out.counters.rays);
  return out;
}

bool PredictingTracer::records_indirect(RayClass c) const {
  return predictor_->records_indirect(c) && inner_->records_indirect(c);
}

bool PredictingTracer::takes_ray_order(RayClass c) const {
  return inner_->takes_ray_order(c) && predictor_->probing(c) != Probe::kAll;
}

std::uint32_t PredictingTracer::rays_per_workgroup() const {
  return predictor_->rays_per_workgroup(push_constants().rays_per_invocation);
}

void PredictingTracer::warm_up() {
  for (RayClass c : kRayClasses) {
    trace(probes, c);
    if (predictor_->probing(c) != Probe::kAll) continue;
    for (Probe p : {Probe::kOff, Probe::kSample, Probe::kAll}) {
      predictor_->set_probing(c, p);
      if (p != Probe::kAll) trace(probes, c);
    }
  }
  predictor_->clear();  // the warm-up rays leave nothing behind
}

}  // namespace hrpp
