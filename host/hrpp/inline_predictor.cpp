#include "hrpp/inline_predictor.h"

#include <algorithm>

#include "common/task_pool.h"
#include "trace/ray_batches.h"

namespace hrpp {

InlinePredictor::InlinePredictor(const GpuBvh& bvh, const PredictorConfig& config, int threads,
                                 TableSharing sharing)
    : bvh_(&bvh), config_(config), threads_(resolve_threads(threads)), sharing_(sharing) {
  clear();
}

void InlinePredictor::clear() {
  PerClass<SharedTable*> shared{};
  if (sharing_ == TableSharing::kShared)
    for (RayClass c : kRayClasses) {
      shared_[c] = std::make_unique<SharedTable>(make_predictor_params(config_, c, bvh_->bounds));
      shared[c] = shared_[c].get();
    }
  tables_.clear();
  tables_.reserve(static_cast<std::size_t>(threads_));
  for (int i = 0; i < threads_; ++i) {
    tables_.emplace_back(*bvh_, config_);
    tables_.back().count_work(false);
    tables_.back().set_full_trace(full_trace_);
    tables_.back().share_tables(shared);
  }
}

void InlinePredictor::set_full_trace(ReferencePredictor::FullTrace f) {
  full_trace_ = std::move(f);
  for (ReferencePredictor& t : tables_) t.set_full_trace(full_trace_);
}

PredictorTraceResult InlinePredictor::trace(std::span<const gpu::Ray> rays, RayClass c,
                                            std::span<gpu::Hit> hits) {
  std::vector<PredictorTraceResult> parts(tables_.size());
  TaskPool pool(threads_);
  pool.parallel_for(chunks(rays.size(), kRayChunk), [&](std::size_t task, int thread) {
    const std::size_t begin = task * kRayChunk, count = std::min(kRayChunk, rays.size() - begin);
    const PredictorTraceResult r =
        tables_[thread].trace(rays.subspan(begin, count), c, hits.subspan(begin, count));
    parts[thread].counters += r.counters;
    parts[thread].predictor += r.predictor;
  });
  PredictorTraceResult out;
  for (const PredictorTraceResult& p : parts) {
    out.counters += p.counters;
    out.predictor += p.predictor;
  }
  return out;
}

}  // namespace hrpp
