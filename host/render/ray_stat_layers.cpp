#include "render/ray_stat_layers.h"

#include <string>
#include <utility>

namespace hrpp {

RayStatLayers::RayStatLayers(std::uint32_t pixels) : sums_(pixels) {}

void RayStatLayers::add(std::uint32_t pixel, RayClass c, const Counts& before,
                        const Counts& after) {
  Sums& s = sums_[pixel][c];
  const auto predictor = [&](std::uint32_t i) {
    return after.predictor.c[i] - before.predictor.c[i];
  };
  s[kRaySum] += after.trace.rays - before.trace.rays;
  s[kInteriorSum] += after.trace.interior_visited - before.trace.interior_visited;
  s[kProbes] += predictor(HRPP_PC_PROBES);
  s[kPredictorHits] += predictor(HRPP_PC_PREDICTOR_HITS);
  s[kTruePositives] += predictor(HRPP_PC_TRUE_POSITIVES);
  s[kBaseline] += predictor(HRPP_PC_BASELINE_INTERIOR);
}

namespace {

float ratio(double num, double den) { return den == 0.0 ? 0.0f : static_cast<float>(num / den); }

}  // namespace

std::vector<ImageChannel> RayStatLayers::channels(std::uint32_t samples,
                                                  const PerClass<bool>& predicting,
                                                  bool baseline) const {
  // A stat's value from a pixel's sums. skipped: what full traversals of the probed rays visit
  // minus the class's work, verification included (every valid ray of a predicting class probes).
  const auto value = [samples](RayStat stat, const Sums& s) {
    const auto d = [&s](Sum i) { return static_cast<double>(s[i]); };
    switch (stat) {
      case RayStat::kRays: return ratio(d(kRaySum), samples);
      case RayStat::kPredicted: return ratio(d(kPredictorHits), d(kProbes));
      case RayStat::kVerified: return ratio(d(kTruePositives), d(kProbes));
      case RayStat::kInterior: return ratio(d(kInteriorSum), d(kRaySum));
      case RayStat::kSkipped: return ratio(d(kBaseline) - d(kInteriorSum), d(kRaySum));
    }
    return 0.0f;
  };
  std::vector<ImageChannel> out;
  for (RayClass c : kRayClasses)
    for (const Named<RayStat>& stat : kRayStatNames) {
      const bool predictor_stat = stat.value != RayStat::kRays && stat.value != RayStat::kInterior;
      if (predictor_stat && !predicting[c]) continue;
      if (stat.value == RayStat::kSkipped && !baseline) continue;
      ImageChannel ch{std::string(ray_class_name(c)) + "." + stat.name,
                      std::vector<float>(sums_.size())};
      for (std::size_t p = 0; p < sums_.size(); ++p) ch.values[p] = value(stat.value, sums_[p][c]);
      out.push_back(std::move(ch));
    }
  return out;
}

}  // namespace hrpp
