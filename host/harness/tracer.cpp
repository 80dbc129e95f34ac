#include "harness/tracer.h"

#include <chrono>

#include "trace/ray_batches.h"

namespace hrpp {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

// The CPU tracers' wall clock covers the trace alone: the hit array is allocated and touched
// before it starts, as the GPU's device timestamps leave out its host work.
TracerRun CpuReferenceTracer::trace(std::span<const gpu::Ray> rays, QueryKind kind) {
  TracerRun r;
  r.hits.resize(rays.size());
  const auto start = Clock::now();
  trace_batch_cpu(bvh_, rays, kind, r.hits, threads_);
  r.ms = ms_since(start);
  return r;
}

CpuHrppTracer::CpuHrppTracer(const GpuBvh& bvh, const PredictorConfig& config, int threads,
                             TableSharing sharing, const EmbreeTracer* embree)
    : predictor_(bvh, config, threads, sharing), embree_(embree != nullptr) {
  if (embree) predictor_.set_full_trace([embree](const gpu::Ray& r) { return embree->closest(r); });
}

// Cold tables per run, as the GPU predictor's; emptying them is outside the clock.
TracerRun CpuHrppTracer::trace(std::span<const gpu::Ray> rays, QueryKind kind) {
  predictor_.clear();
  TracerRun r;
  r.hits.resize(rays.size());
  const auto start = Clock::now();
  const PredictorTraceResult p = predictor_.trace(rays, ray_file_class(kind), r.hits);
  r.ms = ms_since(start);
  r.predictor = p.predictor;
  return r;
}

TracerRun EmbreeBackend::trace(std::span<const gpu::Ray> rays, QueryKind kind) {
  TracerRun r;
  r.hits.resize(rays.size());
  const auto start = Clock::now();
  embree_.trace(rays, kind, r.hits, threads_);
  r.ms = ms_since(start);
  return r;
}

const char* GpuBackend::timing() const {
  return hrpp_ && batched_ ? "none (batched HRPP dispatches are not timed)"
                           : "device timestamps around the trace dispatches";
}

TracerRun GpuBackend::trace(std::span<const gpu::Ray> rays, QueryKind kind) {
  if (hrpp_) tracer_.predictor()->clear();
  GpuTraceResult g = tracer_.trace(rays, kind, sorter_);
  return TracerRun{std::move(g.hits), g.kernel_ms, g.counters, std::nullopt};
}

std::optional<PredictorSummary> count_savings(DeviceTracer& tracer, bool visible,
                                              std::span<const gpu::Ray> rays, QueryKind kind) {
  const RayClass c = ray_file_class(kind);
  GpuPredictor* hrpp = tracer.predictor();
  if (!hrpp || !hrpp->config().predicts(c)) return std::nullopt;
  hrpp->clear();
  hrpp->set_count_baseline(visible);
  const GpuTraceResult counted = tracer.trace(rays, kind);
  hrpp->set_count_baseline(false);
  return summarize(counted.predictor, counted.counters, hrpp->occupancy(c), visible);
}

TracerRun RayQueryBackend::trace(std::span<const gpu::Ray> rays, QueryKind kind) {
  if (hrpp_) tracer_.predictor()->clear();
  GpuTraceResult g = tracer_.trace(rays, kind);
  std::optional<gpu::PredictorCounters> predictor;
  if (g.predicted) predictor = g.predictor;
  return TracerRun{std::move(g.hits), g.kernel_ms, g.counters, predictor};
}

}  // namespace hrpp
