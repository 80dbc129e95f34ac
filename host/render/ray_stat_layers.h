// Where prediction works, per pixel: statistics of the rays a render traced, summed per pixel and
// ray class over the samples, written as extra layers of the render's EXR (`hrpp render
// --ray-stats`), one layer per class ("camera", "bounce", "shadow") and one channel per RayStat
// ("camera.verified", ...). The CPU renderer (host/cpu_render/) adds each ray's own counters, the
// difference of its class's counters across the ray's trace; the GPU stage keeps no per-ray
// counters, so the layers are the CPU backend's.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "common/name_table.h"
#include "render/image_output.h"
#include "render/render_config.h"
#include "trace/ray_class.h"

namespace hrpp {

// A channel's value at a pixel:
//   rays: the class's rays a sample (camera 1, bounce the path's continuations, shadow its light
//     samples);
//   predicted: of the class's probes, the share whose key found an entry;
//   verified: of the probes, the share whose predicted nodes held the answer (true positives);
//   interior: interior nodes visited a ray, verification included: the traversal cost;
//   skipped: interior node visits a ray that prediction saved, net of verification: what a full
//     traversal visits minus `interior` (count_baseline on; negative where verification costs).
// predicted, verified and skipped exist for classes that probe, 0 at pixels without probes.
enum class RayStat : std::uint8_t { kRays, kPredicted, kVerified, kInterior, kSkipped };
inline constexpr NameTable<RayStat, 5> kRayStatNames = {{{RayStat::kRays, "rays"},
                                                         {RayStat::kPredicted, "predicted"},
                                                         {RayStat::kVerified, "verified"},
                                                         {RayStat::kInterior, "interior"},
                                                         {RayStat::kSkipped, "skipped"}}};

class RayStatLayers {
 public:
  explicit RayStatLayers(std::uint32_t pixels);

  // A class's counters at one moment.
  struct Counts {
    TraversalCounters trace;
    gpu::PredictorCounters predictor{};
  };
  // The ray's counters: its class's after its trace minus before. A pixel is only ever added to
  // from one thread at a time (the CPU renderer's pixel blocks).
  void add(std::uint32_t pixel, RayClass c, const Counts& before, const Counts& after);

  // The channels after `samples` samples: for every class, rays and interior; for the classes
  // in `predicting`, predicted and verified, and skipped where `baseline`.
  std::vector<ImageChannel> channels(std::uint32_t samples, const PerClass<bool>& predicting,
                                     bool baseline) const;

 private:
  // Per pixel and class: rays, probes, predictor hits, true positives, interior visits, baseline
  // interior visits (144 bytes a pixel).
  enum Sum { kRaySum, kProbes, kPredictorHits, kTruePositives, kInteriorSum, kBaseline, kSums };
  using Sums = std::array<std::uint64_t, kSums>;
  std::vector<PerClass<Sums>> sums_;
};

}  // namespace hrpp
