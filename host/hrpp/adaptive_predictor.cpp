#include "hrpp/adaptive_predictor.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace hrpp {

namespace {

bool is_trace_kernel(Kernel k) {
  return k == Kernel::trace_closest || k == Kernel::trace_any ||
         k == Kernel::trace_closest_indexed || k == Kernel::trace_any_indexed ||
         k == Kernel::trace_closest_skipping || k == Kernel::trace_any_skipping ||
         k == Kernel::trace_rayquery_closest || k == Kernel::trace_rayquery_any;
}

}  // namespace

void add_kernel_times(ClassFrameCost& cost, const std::map<TimerLabel, double>& kernels_ms) {
  for (const auto& [label, ms] : kernels_ms) {
    const bool predict = label.kernel == Kernel::hrpp_predict;
    const bool resolve = label.kernel == Kernel::hrpp_resolve;
    if (!predict && !resolve && !is_trace_kernel(label.kernel))
      throw std::logic_error(std::string("kernel ") + kernel_name(label.kernel) +
                             " timed for a ray class");
    switch (label.phase) {
      case Phase::kSampleEmpty:
        cost.empty_dispatch_ms += ms;
        break;
      case Phase::kSample:
        cost.sample_ms += ms;
        if (predict || resolve) cost.sample_stage_ms += ms;
        break;
      case Phase::kRun:
        (predict ? cost.predict_ms : resolve ? cost.resolve_ms : cost.trace_ms) += ms;
        break;
    }
  }
}

AdaptivePredictor::AdaptivePredictor(const PredictorConfig& config)
    : adaptive_(config.adapts()),
      passes_(config.pilot >= 2 ? 2 : 1),
      min_stride_(std::max(config.sample, 1u)) {
  for (RayClass c : kRayClasses) {
    State& s = state_[c];
    s.stride = min_stride_;
    s.enabled = config.predicts(c);
    if (s.enabled) s.mode = adaptive_ ? Probe::kSample : Probe::kAll;
  }
}

namespace {

double per_ray(double ms, std::uint64_t rays) {
  return rays > 0 ? ms / static_cast<double>(rays) : 0.0;
}

}  // namespace

// A sample frame: the stage's cost per sampled ray against the plain trace's per ray, measured
// in the same frame, each dispatch's fixed cost counted once (not once per sampled ray share).
void AdaptivePredictor::judge_sample(State& s, const ClassFrameCost& cost,
                                     ClassDecision& d) const {
  const double off = s.off_ms_per_ray;
  const double rounds = static_cast<double>(cost.rounds);
  d.dispatch_ms = cost.rounds > 0 ? cost.empty_dispatch_ms / rounds : 0.0;
  // Per round the sample ran 3 dispatches (predict, trace of the queue, resolve), 2 of them the
  // stage's; a predicted frame runs 3 per pass. (A pass sized on the device runs hrpp_pass_args
  // first, timed as predict's: its fixed cost stays in, a slight overstatement.)
  const auto variable = [&](double ms, int dispatches) {
    return per_ray(std::max(ms - dispatches * rounds * d.dispatch_ms, 0.0), cost.sampled);
  };
  const double predicted_ms = variable(cost.sample_ms, 3) * static_cast<double>(cost.rays) +
                              3.0 * passes_ * rounds * d.dispatch_ms;
  s.stride = stride_for(s, variable(cost.sample_ms, 3));
  d.gain_ms = off * static_cast<double>(cost.rays) - predicted_ms;
  const bool hopeless = cost.sampled > 0 && variable(cost.sample_stage_ms, 2) >= off;
  const bool warming = !s.warmed;
  s.warmed = true;
  if (!hopeless && warming) {
    d.reason = Reason::kWarming;  // the table was empty: sample again
    return;
  }
  if (!hopeless && d.gain_ms > 0.0) {
    d.reason = Reason::kGain;
    s.mode = Probe::kAll;
    s.confidence = kConfidenceOn;
    s.losses = 0;
    return;
  }
  d.reason = hopeless ? Reason::kHopeless : Reason::kLoss;
  s.mode = Probe::kOff;
  s.retry_after = std::min(kRetryEvery << std::min(s.losses, 8), kRetryMax);
  ++s.losses;
}

// A frame with every ray predicted: its gain against the last plain trace's cost per ray.
void AdaptivePredictor::judge_all(State& s, const ClassFrameCost& cost, ClassDecision& d) const {
  s.warmed = true;
  const double off = s.off_ms_per_ray;
  if (off <= 0.0) {
    d.reason = Reason::kUnmeasured;  // a sample frame measures the plain trace
    s.mode = Probe::kSample;
    return;
  }
  const double rays = static_cast<double>(cost.rays);
  d.gain_ms = off * rays - cost.cost_ms();
  if (cost.predict_ms + cost.resolve_ms >= off * rays) {
    d.reason = Reason::kHopeless;
    s.confidence = std::min(s.confidence, kConfidenceOn) - 1;
  } else {
    const bool gain = d.gain_ms > 0.0;
    d.reason = gain ? Reason::kGain : Reason::kLoss;
    s.confidence = std::clamp(s.confidence + (gain ? 1 : -1), 0, kConfidenceMax);
  }
  if (s.confidence >= kConfidenceOn) return;
  s.mode = Probe::kOff;
  s.retry_after = kRetryEvery;
}

std::uint32_t AdaptivePredictor::stride_for(const State& s, double variable_ms) const {
  // Sampling every stride-th block takes about 1/stride of the rays: its per-ray part costs
  // variable_ms / stride per ray of the class against a budget of kSampleBudget × off per ray.
  const double budget = kSampleBudget * s.off_ms_per_ray;
  std::uint32_t stride = min_stride_;
  while (stride < kStrideMax && variable_ms > budget * stride) stride *= 2;
  return std::max(stride, min_stride_);
}

void AdaptivePredictor::book_budget(State& s, const ClassFrameCost& cost) {
  s.credit_ms += kSampleBudget * s.off_ms_per_ray * static_cast<double>(cost.rays);
  if (cost.mode == Probe::kSample) {
    s.sample_ms = cost.sample_ms + cost.empty_dispatch_ms;
    s.credit_ms -= s.sample_ms;
  }
  // Saved up for one sample at most: the budget holds over any stretch of frames.
  s.credit_ms = std::min(s.credit_ms, s.sample_ms);
}

void AdaptivePredictor::defer_unaffordable_sample(State& s, ClassDecision& d) {
  if (s.mode != Probe::kSample || s.credit_ms >= s.sample_ms) return;
  s.mode = Probe::kOff;
  s.frames_off = 0;
  s.retry_after = 1;
  d.reason = Reason::kBudget;
}

ClassDecision AdaptivePredictor::end_frame(RayClass c, const ClassFrameCost& cost) {
  State& s = state_[c];
  ClassDecision d;
  d.mode = cost.mode;
  // The plain trace ran over every ray (off and sample frames): its cost per ray is the cost
  // without prediction.
  if (cost.mode != Probe::kAll && cost.traced > 0) s.off_ms_per_ray = per_ray(cost.trace_ms, cost.traced);
  if (s.enabled && adaptive_ && cost.rays > 0) book_budget(s, cost);
  if (!s.enabled) {
    d.reason = Reason::kDisabled;
  } else if (!adaptive_) {
    d.reason = Reason::kFixed;
  } else if (cost.rays == 0) {
    d.reason = Reason::kIdle;  // nothing to judge
  } else if (cost.mode == Probe::kSample) {
    judge_sample(s, cost, d);
    s.frames_off = 0;
  } else if (cost.mode == Probe::kAll) {
    judge_all(s, cost, d);
    s.frames_off = 0;
  } else {
    d.reason = Reason::kOff;
    if (s.mode == Probe::kOff && ++s.frames_off >= s.retry_after) {
      s.mode = Probe::kSample;
      d.reason = Reason::kRetry;
    }
  }
  if (s.enabled && adaptive_) defer_unaffordable_sample(s, d);
  d.off_ms_per_ray = s.off_ms_per_ray;
  d.sample_stride = s.stride;
  d.confidence = s.confidence;
  d.next = s.mode;
  return d;
}

}  // namespace hrpp
