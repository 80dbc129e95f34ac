#include "render/render_config.h"

namespace hrpp {

std::map<std::string, double> times_by_name(const std::map<TimerLabel, double>& kernels_ms) {
  std::map<std::string, double> named;
  for (const auto& [label, ms] : kernels_ms) named[label_name(label)] += ms;
  return named;
}

RayClassStats& RayClassStats::operator+=(const RayClassStats& o) {
  counters += o.counters;
  predictor += o.predictor;
  traces += o.traces;
  predicted_traces += o.predicted_traces;
  traced += o.traced;
  sampled += o.sampled;
  for (const auto& [k, ms] : o.kernels_ms) kernels_ms[k] += ms;
  return *this;
}

RayClassStats FrameStats::closest() const {
  RayClassStats s = classes[RayClass::kCamera];
  s += classes[RayClass::kBounce];
  return s;
}

FrameStats& FrameStats::operator+=(const FrameStats& o) {
  for (const auto& [k, ms] : o.kernels_ms) kernels_ms[k] += ms;
  for (RayClass c : kRayClasses) classes[c] += o.classes[c];
  wall_s += o.wall_s;
  return *this;
}

}  // namespace hrpp
