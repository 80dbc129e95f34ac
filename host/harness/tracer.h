// A tracer: one backend that answers a batch of rays with one hit per ray (closest or any hit),
// behind `hrpp bench` (the benchmark harness, host/harness/). A new backend is one class here:
// a TracerKind, a name, what its times measure and trace(). `hrpp trace` runs the device
// tracers through it too.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "bvh/gpu_layout.h"
#include "gpu/device_tracer.h"
#include "front/gpu_predictor.h"
#include "gpu/ray_sorter.h"
#include "gpu_types.h"
#include "hrpp/inline_predictor.h"
#include "hrpp/predictor_stats.h"
#include "reference/embree_tracer.h"
#include "trace/traversal_counters.h"

namespace hrpp {

enum class TracerKind {
  kCpuReference,  // trace/cpu_traversal.h on all threads: the ground truth
  kCpuHrpp,       // the same with HRPP inline (hrpp/inline_predictor.h); tables emptied per run
  kEmbreeHrpp,    // HRPP inline in front of Embree: a prediction that does not answer calls it
  kEmbree,        // Embree 3 or 4 (reference/embree_tracer.h)
  kGpu,           // the Vulkan trace kernels (gpu/gpu_tracer.h)
  kGpuHrpp,       // the same with the HRPP predictor; tables cleared before every run
  kRayQuery,      // the driver's traversal (gpu/ray_query_tracer.h)
  kRayQueryHrpp,  // the same with the HRPP stage in front; tables cleared before every run
};

struct TracerRun {
  std::vector<gpu::Hit> hits;
  double ms = 0.0;
  std::optional<TraversalCounters> counters;          // the GPU's work
  std::optional<gpu::PredictorCounters> predictor;  // cpu-hrpp, rq-hrpp: HRPP_PC_*
};

class Tracer {
 public:
  virtual ~Tracer() = default;
  virtual TracerKind kind() const = 0;
  virtual const char* name() const = 0;    // "cpu-ref", "embree", "gpu", "gpu-hrpp", ...
  virtual const char* timing() const = 0;  // what TracerRun::ms measures
  virtual TracerRun trace(std::span<const gpu::Ray> rays, QueryKind kind) = 0;
};

class CpuReferenceTracer final : public Tracer {
 public:
  CpuReferenceTracer(const GpuBvh& bvh, int threads) : bvh_(bvh), threads_(threads) {}
  TracerKind kind() const override { return TracerKind::kCpuReference; }
  const char* name() const override { return "cpu-ref"; }
  const char* timing() const override { return "wall"; }
  TracerRun trace(std::span<const gpu::Ray> rays, QueryKind kind) override;

 private:
  const GpuBvh& bvh_;
  int threads_;
};

// HRPP inline on the CPU, on the same threads as the CPU reference: in front of the CPU
// traversal (cpu-hrpp), or with `embree` in front of Embree (emb-hrpp): probe and verify with
// the project's BVH and leaf test; a verified hit-any prediction skips Embree, a verified
// closest hit answers (speculative) or bounds rtcIntersect1's tfar (exact); the other rays call
// rtcIntersect1 (hit-any too: the insert needs the occluder's triangle, which rtcOccluded1 does
// not report).
class CpuHrppTracer final : public Tracer {
 public:
  CpuHrppTracer(const GpuBvh& bvh, const PredictorConfig& config, int threads,
                TableSharing sharing, const EmbreeTracer* embree = nullptr);
  TracerKind kind() const override {
    return embree_ ? TracerKind::kEmbreeHrpp : TracerKind::kCpuHrpp;
  }
  const char* name() const override { return embree_ ? "emb-hrpp" : "cpu-hrpp"; }
  const char* timing() const override { return "wall"; }
  TracerRun trace(std::span<const gpu::Ray> rays, QueryKind kind) override;

 private:
  InlinePredictor predictor_;
  bool embree_;
};

class EmbreeBackend final : public Tracer {
 public:
  EmbreeBackend(const EmbreeTracer& embree, int threads) : embree_(embree), threads_(threads) {}
  TracerKind kind() const override { return TracerKind::kEmbree; }
  const char* name() const override { return "embree"; }
  const char* timing() const override { return "wall"; }
  TracerRun trace(std::span<const gpu::Ray> rays, QueryKind kind) override;

 private:
  const EmbreeTracer& embree_;
  int threads_;
};

// kGpu: the BVH kernels (a GpuTracer), or kGpuHrpp: HRPP's stage in front of them (a
// PredictingTracer, front/make_device_tracer.h).
class GpuBackend final : public Tracer {
 public:
  // `sorter`: sort the rays on the device before each trace and trace them through the order
  // (its time counted; the hits are in the rays' order; DeviceTracer::trace).
  explicit GpuBackend(DeviceTracer& tracer, RaySorter* sorter = nullptr)
      : tracer_(tracer),
        hrpp_(tracer.predictor() != nullptr),
        batched_(hrpp_ && tracer.predictor()->config().batch > 0),
        sorter_(sorter) {}
  TracerKind kind() const override { return hrpp_ ? TracerKind::kGpuHrpp : TracerKind::kGpu; }
  const char* name() const override { return hrpp_ ? "gpu-hrpp" : "gpu"; }
  const char* timing() const override;
  TracerRun trace(std::span<const gpu::Ray> rays, QueryKind kind) override;

 private:
  DeviceTracer& tracer_;
  bool hrpp_;
  bool batched_;  // HRPP batches: not timed
  RaySorter* sorter_;
};

// kRayQuery: the driver's traversal (a RayQueryTracer), or kRayQueryHrpp: HRPP's stage in
// front of it.
class RayQueryBackend final : public Tracer {
 public:
  explicit RayQueryBackend(DeviceTracer& tracer)
      : tracer_(tracer), hrpp_(tracer.predictor() != nullptr) {}
  TracerKind kind() const override {
    return hrpp_ ? TracerKind::kRayQueryHrpp : TracerKind::kRayQuery;
  }
  const char* name() const override { return hrpp_ ? "rq-hrpp" : "rayquery"; }
  const char* timing() const override { return "device timestamps around the trace dispatches"; }
  TracerRun trace(std::span<const gpu::Ray> rays, QueryKind kind) override;

 private:
  DeviceTracer& tracer_;
  bool hrpp_;
};

// HRPP: one more run from empty tables that also counts what full traversals of the project's
// BVH would visit (outside the timings); nothing when `tracer` has no predictor or it does not
// predict the query's ray class. `visible`: the tracer behind the stage shows its node visits
// (the BVH kernels); the driver's ray queries hide them: there the run counts no baseline and
// the summary has no savings.
std::optional<PredictorSummary> count_savings(DeviceTracer& tracer, bool visible,
                                              std::span<const gpu::Ray> rays, QueryKind kind);

}  // namespace hrpp
