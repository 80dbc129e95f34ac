// The adaptive predictor: per ray class, a branch predictor's confidence counter applied to the
// question "does probing this class save time?", decided once per frame from the frame's
// kernel times and counters. A class is in one of three modes each frame (Probe):
//   - sample: every PredictorConfig::sample-th ray runs the HRPP stage (predict, trace of its
//     queue, resolve), then the plain trace kernel traces every ray, the sample included, so the
//     frame's answers are HRPP off's. One frame thus measures both costs per ray under the same
//     load: the stage's on the sample and the plain trace's on all rays. A dispatch's fixed cost
//     (measured each sample by a dispatch over no ray) is taken out of the sample's time before
//     it is divided by the sampled rays, and put back once per dispatch of a predicted frame:
//     spread over 1/sample of the rays it would otherwise count `sample` times too much. The
//     estimated gain over the class's rays decides: a gain turns the class to `all`, a loss (or
//     a "hopeless" sample, whose predict + resolve alone cost more per ray than a plain trace)
//     turns it off. The first sample only fills the empty table (warming).
//   - all: every ray runs the HRPP stage. The frame's gain is what its rays cost traced without
//     prediction (the last plain trace's cost per ray) minus predict + trace + resolve. A gain
//     raises the 2-bit confidence, a loss lowers it; the class stays at `all` while the
//     confidence is >= 2 and is off below.
//   - off: the plain trace (which measures the cost per ray without prediction). After
//     retry_after frames off the class samples again; each losing sample doubles the wait (up
//     to kRetryMax frames).
// A class starts by sampling, so a class that loses costs its samples only (a sample frame pays
// the stage on 1/sample of the rays on top of a plain trace), never a whole predicted frame.
// Sampling budget: a class samples only while its samples have cost at most kSampleBudget of its
// plain trace time. Each frame credits kSampleBudget × (plain cost per ray × the frame's rays);
// each sample debits what it added (the stage on the sample with its queue's trace, and the
// empty dispatches). A sample is due (warming, retry) only when the credit covers the last
// sample's cost; until then the class stays off (reason `budget`). So on a device where a
// sample's dispatches weigh much against the trace (a GPU: fixed costs of tens of microseconds
// beside traces of a few milliseconds) the samples are spaced out, and where they are cheap
// (lavapipe) the schedule is the retry schedule above. The first sample is free: nothing is
// measured before it. The sample's size follows from its measured cost too: after each sample
// the stride (every stride-th block of rays; PredictorConfig::sample at first) becomes the
// smallest power of two, at least PredictorConfig::sample and at most kStrideMax, at which the
// sample's per-ray part costs at most kSampleBudget of the frame's plain trace, so one frame's
// credit pays for it; what remains is its dispatches' fixed cost, which the spacing covers.
// Adaptive off (adaptive false): every enabled class is at `all` every frame. The
// decisions are reported per frame in the render stats.
#pragma once

#include <cstdint>
#include <map>

#include "common/name_table.h"
#include "hrpp/predictor_config.h"
#include "vk/timer_label.h"
#include "trace/ray_class.h"

namespace hrpp {

// How a class runs the HRPP stage in a frame.
enum class Probe : std::uint8_t { kOff, kSample, kAll };
inline constexpr NameTable<Probe, 3> kProbeNames = {
    {{Probe::kOff, "off"}, {Probe::kSample, "sample"}, {Probe::kAll, "all"}}};
constexpr const char* probe_name(Probe p) { return name_in(kProbeNames, p); }

// Why a class runs as it does in the next frame.
enum class Reason : std::uint8_t {
  kDisabled,    // the class does not predict (--hrpp-rays)
  kFixed,       // not adaptive: every ray predicts, every frame
  kIdle,        // no ray of the class this frame: nothing to judge
  kWarming,     // the sample found an empty table: sample again
  kUnmeasured,  // the plain trace's cost is not known yet: a sample frame measures it
  kHopeless,    // even a perfect predictor could not pay at this cost
  kGain,        // prediction saved time
  kLoss,        // prediction cost time
  kOff,         // off, waiting before the next retry
  kRetry,       // off long enough: sample again
  kBudget,      // a sample is due but the sampling budget has not covered its cost yet
};
inline constexpr NameTable<Reason, 11> kReasonNames = {{{Reason::kDisabled, "disabled"},
                                                        {Reason::kFixed, "fixed"},
                                                        {Reason::kIdle, "idle"},
                                                        {Reason::kWarming, "warming"},
                                                        {Reason::kUnmeasured, "unmeasured"},
                                                        {Reason::kHopeless, "hopeless"},
                                                        {Reason::kGain, "gain"},
                                                        {Reason::kLoss, "loss"},
                                                        {Reason::kOff, "off"},
                                                        {Reason::kRetry, "retry"},
                                                        {Reason::kBudget, "budget"}}};
constexpr const char* reason_name(Reason r) { return name_in(kReasonNames, r); }

// What one frame of a ray class did and cost on the device.
struct ClassFrameCost {
  Probe mode = Probe::kOff;
  std::uint64_t rays = 0;    // rays of the class
  std::uint64_t traced = 0;  // rays the plain trace traced (all: the queue; else every ray)
  double predict_ms = 0.0, trace_ms = 0.0, resolve_ms = 0.0;  // all: the stage; else 0, trace, 0
  std::uint64_t rounds = 0;   // traces of the class (one per bounce and wavefront)
  std::uint64_t sampled = 0;  // sample: rays that ran the HRPP stage
  double sample_ms = 0.0;     // sample: predict + trace of the queue + resolve over them
  double sample_stage_ms = 0.0;  // sample: predict + resolve alone
  double empty_dispatch_ms = 0.0;  // sample: one dispatch over no ray per round, summed

  double cost_ms() const { return predict_ms + trace_ms + resolve_ms; }
};

// Books one frame's device times of a class (labels without the class) into `cost`: by phase
// (the frame's own work, the sample, the sample's empty dispatch) and by kernel (hrpp_predict,
// hrpp_resolve, the trace kernels). Throws std::logic_error for a kernel that no class runs.
void add_kernel_times(ClassFrameCost& cost, const std::map<TimerLabel, double>& kernels_ms);

// One frame's decision for one class.
struct ClassDecision {
  Probe mode = Probe::kOff;   // this frame
  double off_ms_per_ray = 0;  // trace cost per ray without prediction (0: not measured yet)
  double gain_ms = 0;         // sample and all frames: estimated time saved over the class's
                              // rays (negative: lost)
  double dispatch_ms = 0;     // sample frames: the fixed cost of one dispatch
  std::uint32_t sample_stride = 0;  // the stride of the class's next sample
  int confidence = 0;         // 0..3 after this frame
  Probe next = Probe::kOff;
  Reason reason = Reason::kIdle;
};

class AdaptivePredictor {
 public:
  static constexpr int kRetryEvery = 4;  // frames off before the first retry
  static constexpr int kRetryMax = 64;   // the longest wait after losing samples
  static constexpr int kConfidenceMax = 3;
  static constexpr int kConfidenceOn = 2;
  // The share of a class's plain trace time its samples may cost (kSampleBudget, above).
  static constexpr double kSampleBudget = 0.02;
  static constexpr std::uint32_t kStrideMax = 1024;  // a sample's sparsest stride

  explicit AdaptivePredictor(const PredictorConfig& config);

  // How the class runs the HRPP stage in the coming frame.
  Probe mode(RayClass c) const { return state_[c].mode; }
  // Every how many blocks of rays the class's next sample takes one (GpuPredictor::set_probing).
  std::uint32_t sample_stride(RayClass c) const { return state_[c].stride; }
  // Takes a frame's cost of the class and decides the next frame.
  ClassDecision end_frame(RayClass c, const ClassFrameCost& cost);

 private:
  struct State {
    bool enabled = false;  // the class predicts at all (--hrpp-rays)
    Probe mode = Probe::kOff;
    int confidence = 0;
    bool warmed = false;  // a sample or a predicted frame has filled the table
    int frames_off = 0;
    int retry_after = kRetryEvery;  // frames off before the next sample
    int losses = 0;                 // losing samples since the last gain
    double off_ms_per_ray = 0.0;
    double credit_ms = 0.0;    // the sampling budget left (negative: spent ahead)
    double sample_ms = 0.0;    // what the last sample cost on top of the plain trace
    std::uint32_t stride = 0;  // the next sample's stride
  };
  // Books the frame's budget credit and, for a sample frame, its cost.
  static void book_budget(State& s, const ClassFrameCost& cost);
  // A sample due next frame waits for the budget: off, retried as soon as it is covered.
  static void defer_unaffordable_sample(State& s, ClassDecision& d);
  // The stride at which a sample's per-ray cost `variable_ms` (per sampled ray) fits the budget.
  std::uint32_t stride_for(const State& s, double variable_ms) const;
  void judge_sample(State& s, const ClassFrameCost& cost, ClassDecision& d) const;
  void judge_all(State& s, const ClassFrameCost& cost, ClassDecision& d) const;

  bool adaptive_;
  int passes_;
  std::uint32_t min_stride_;  // PredictorConfig::sample  // HRPP stage passes per trace in a
                              // predicted frame (2 with the pilot schedule)
  PerClass<State> state_;
};

}  // namespace hrpp
