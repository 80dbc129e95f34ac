#include "render/ray_stat_layers.h"

#include <string>

namespace hrpp {

RayStatLayers::RayStatLayers(std::uint32_t pixels) : sums_(pixels) {}

void RayStatLayers::add(std::uint32_t pixel, RayClass c, const Counts &before,
                        const Counts &after) {
  Sums &s = sums_[pixel][c];
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

float ratio(std::uint64_t num, std::uint64_t den) {
  return den == 0 ? 0.0f : static_cast<float>(static_cast<double>(num) / static_cast<double>(den));
}

// Net interior visits saved a ray: what full traversals of the probed rays
// visit minus the class's work, verification included (every valid ray of a
// predicting class probes).
float skipped(std::uint64_t baseline, std::uint64_t interior, std::uint64_t rays) {
  if (rays == 0) return 0.0f;
  return static_cast<float>((static_cast<double>(baseline) - static_cast<double>(interior)) /
                            static_cast<double>(rays));
}

}  // namespace

std::vector<ImageChannel> RayStatLayers::channels(std::uint32_t samples,
                                                  const PerClass<bool> &predicting,
                                                  bool baseline) const {
  std::vector<ImageChannel> out;
  const std::size_t pixels = sums_.size();
  for (RayClass c : kRayClasses)
    for (const Named<RayStat> &stat : kRayStatNames) {
      const bool predictor_stat = stat.value != RayStat::kRays && stat.value != RayStat::kInterior;
      if (predictor_stat && !predicting[c]) continue;
      if (stat.value == RayStat::kSkipped && !baseline) continue;
      ImageChannel ch{std::string(ray_class_name(c)) + "." + stat.name, std::vector<float>(pixels)};
      for (std::size_t p = 0; p < pixels; ++p) {
        const Sums &s = sums_[p][c];
        switch (stat.value) {
          case RayStat::kRays:
            ch.values[p] = ratio(s[kRaySum], samples);
            break;
          case RayStat::kPredicted:
            ch.values[p] = ratio(s[kPredictorHits], s[kProbes]);
            break;
          case RayStat::kVerified:
            ch.values[p] = ratio(s[kTruePositives], s[kProbes]);
            break;
          case RayStat::kInterior:
            ch.values[p] = ratio(s[kInteriorSum], s[kRaySum]);
            break;
          case RayStat::kSkipped:
            ch.values[p] = skipped(s[kBaseline], s[kInteriorSum], s[kRaySum]);
            break;
        }
      }
      out.push_back(std::move(ch));
    }
  return out;
}

}  // namespace hrpp
