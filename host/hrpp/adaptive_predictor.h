// The adaptive predictor: per ray class, a branch predictor's confidence counter applied to the
// question "does probing this class save time?", decided once per frame from the frame's
// kernel times and counters.
//   - While a class probes, a frame's cost is predict + trace + resolve milliseconds. Its gain
//     is what the class's rays would have cost traced without prediction (the last measured
//     trace time per ray with nearly every ray traced: a frame with prediction off, or a
//     probing frame whose predictions almost all missed) minus that cost. A gain raises the
//     2-bit confidence, a loss lowers it; the class probes while the confidence is >= 2.
//   - A probing frame whose predict + resolve time alone exceeds what tracing all its rays
//     without prediction costs is a loss whatever the table holds ("hopeless"), the first frame
//     included.
//   - Otherwise the first probing frame fills an empty table: it is not judged (warming). When no frame
//     has measured the trace cost without prediction yet (the warming frame's true positives
//     left less than kTracedForOffCost of the rays to the trace), the next frame runs without
//     prediction to measure it ("unmeasured"), and probing resumes after it.
//   - A class that stopped probing traces as with HRPP off (which measures the trace cost per
//     ray) and is tried again after kRetryEvery frames; a trial with a gain turns it back on,
//     each losing trial doubles the wait (up to kRetryMax frames).
// The decisions are reported per frame in the render stats.
#pragma once

#include <cstdint>

#include "hrpp/predictor_config.h"
#include "hrpp/ray_class.h"

namespace hrpp {

// What one frame of a ray class did and cost on the device.
struct ClassFrameCost {
  bool probed = false;       // the class ran the HRPP stage this frame
  std::uint64_t rays = 0;    // rays of the class
  std::uint64_t traced = 0;  // rays the trace kernel traced (probing: the queue)
  double predict_ms = 0.0, trace_ms = 0.0, resolve_ms = 0.0;

  double cost_ms() const { return predict_ms + trace_ms + resolve_ms; }
};

// One frame's decision for one class.
struct ClassDecision {
  bool probed = false;        // this frame
  double off_ms_per_ray = 0;  // trace cost per ray without prediction (0: not measured yet)
  double gain_ms = 0;         // probing frames: estimated time saved (negative: lost)
  int confidence = 0;         // 0..3 after this frame
  bool probe_next = false;
  const char* reason = "";    // disabled, fixed, hopeless, warming, unmeasured, gain, loss, off,
                              // retry
};

class AdaptivePredictor {
 public:
  static constexpr int kRetryEvery = 4;  // frames off before the first trial
  static constexpr int kRetryMax = 64;   // the longest wait after losing trials
  static constexpr int kConfidenceMax = 3;
  static constexpr int kConfidenceOn = 2;
  // Nearly every ray traced: the trace time then stands for a trace without prediction.
  static constexpr double kTracedForOffCost = 0.9;

  explicit AdaptivePredictor(const PredictorConfig& config);

  // Whether the class probes in the coming frame.
  bool probing(RayClass c) const { return state_[c].probing; }
  // Takes a frame's cost of the class and decides the next frame.
  ClassDecision end_frame(RayClass c, const ClassFrameCost& cost);

 private:
  struct State {
    bool enabled = false;   // the class predicts at all (--hrpp-rays)
    bool probing = false;
    int confidence = kConfidenceOn;
    int frames_probed = 0;
    int frames_off = 0;
    int retry_after = kRetryEvery;  // frames off before the next trial
    bool measure_next = false;      // a frame without prediction to measure the trace cost
    double off_ms_per_ray = 0.0;
  };
  void judge(State& s, const ClassFrameCost& cost, ClassDecision& d) const;

  bool adaptive_;
  PerClass<State> state_;
};

}  // namespace hrpp
