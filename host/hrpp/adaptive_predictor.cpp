#include "hrpp/adaptive_predictor.h"

#include <algorithm>
#include <utility>

namespace hrpp {

AdaptivePredictor::AdaptivePredictor(const PredictorConfig& config) : adaptive_(config.adaptive) {
  for (RayClass c : kRayClasses) {
    state_[c].enabled = config.predicts(c);
    state_[c].probing = state_[c].enabled;
  }
}

// A probing frame: its gain against the last trace cost measured without prediction.
void AdaptivePredictor::judge(State& s, const ClassFrameCost& cost, ClassDecision& d) const {
  const bool trial = s.confidence < kConfidenceOn;
  // Hopeless whatever the table holds: predict + resolve alone cost more than tracing every ray
  // would (the trace's cost per ray of this frame's queue if none was measured: the queued rays
  // are the harder ones, so this errs toward probing).
  const double off_rate = s.off_ms_per_ray > 0.0 ? s.off_ms_per_ray
                          : cost.traced > 0 ? cost.trace_ms / static_cast<double>(cost.traced)
                                            : 0.0;
  const double stage_ms = cost.predict_ms + cost.resolve_ms;
  if (off_rate > 0.0 && stage_ms >= off_rate * static_cast<double>(cost.rays)) {
    ++s.frames_probed;
    d.gain_ms = off_rate * static_cast<double>(cost.rays) - cost.cost_ms();
    d.reason = "hopeless";
    s.confidence = std::min(s.confidence, kConfidenceOn) - 1;
    if (trial) s.retry_after = std::min(2 * s.retry_after, kRetryMax);
  } else if (s.frames_probed++ == 0) {
    d.reason = "warming";
  } else if (s.off_ms_per_ray <= 0.0) {
    d.reason = "unmeasured";  // the next frame traces without prediction to measure it
    s.measure_next = true;
  } else {
    d.gain_ms = s.off_ms_per_ray * static_cast<double>(cost.rays) - cost.cost_ms();
    const bool gain = d.gain_ms > 0.0;
    d.reason = gain ? "gain" : "loss";
    s.confidence = std::clamp(s.confidence + (gain ? 1 : -1), 0, kConfidenceMax);
    if (trial && gain) s.confidence = kConfidenceOn;
    if (trial) s.retry_after = gain ? kRetryEvery : std::min(2 * s.retry_after, kRetryMax);
  }
}

ClassDecision AdaptivePredictor::end_frame(RayClass c, const ClassFrameCost& cost) {
  State& s = state_[c];
  ClassDecision d;
  d.probed = cost.probed;
  // Nearly every ray traced (off, or a probing frame whose predictions missed): the trace time
  // per ray is what a trace without prediction costs.
  if (cost.traced > 0 &&
      static_cast<double>(cost.traced) >= kTracedForOffCost * static_cast<double>(cost.rays))
    s.off_ms_per_ray = cost.trace_ms / static_cast<double>(cost.traced);
  if (!s.enabled) {
    d.reason = "disabled";
  } else if (!adaptive_) {
    d.reason = "fixed";
  } else if (cost.probed) {
    judge(s, cost, d);
    s.frames_off = 0;
  } else {
    d.reason = "off";
    ++s.frames_off;
  }
  if (s.enabled && adaptive_) {
    s.probing = s.confidence >= kConfidenceOn || s.frames_off >= s.retry_after;
    if (s.probing && s.confidence < kConfidenceOn) d.reason = "retry";
    if (std::exchange(s.measure_next, false)) s.probing = false;
  }
  d.off_ms_per_ray = s.off_ms_per_ray;
  d.confidence = s.confidence;
  d.probe_next = s.probing;
  return d;
}

}  // namespace hrpp
