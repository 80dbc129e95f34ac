#include "app/tracer.h"

#include <chrono>

#include "trace/ray_batches.h"

namespace hrpp::app {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

TracerRun CpuReferenceTracer::trace(std::span<const gpu::Ray> rays, bool any_hit) {
  TracerRun r;
  const auto start = Clock::now();
  r.hits = trace_batch_cpu(bvh_, rays, any_hit, threads_);
  r.ms = ms_since(start);
  return r;
}

TracerRun EmbreeBackend::trace(std::span<const gpu::Ray> rays, bool any_hit) {
  TracerRun r;
  const auto start = Clock::now();
  r.hits = embree_.trace(rays, any_hit, threads_);
  r.ms = ms_since(start);
  return r;
}

const char* GpuBackend::timing() const {
  return hrpp_ && batched_ ? "none (batched HRPP dispatches are not timed)"
                           : "device timestamps around the trace dispatches";
}

TracerRun GpuBackend::trace(std::span<const gpu::Ray> rays, bool any_hit) {
  if (hrpp_) tracer_.clear_predictor();
  GpuTraceResult g = tracer_.trace(rays, any_hit);
  return TracerRun{std::move(g.hits), g.kernel_ms, g.counters};
}

}  // namespace hrpp::app
