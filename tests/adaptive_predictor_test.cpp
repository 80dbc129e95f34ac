// The adaptive predictor (host/hrpp/adaptive_predictor.h) on forced costs: a class starts by
// sampling; a sample that gains turns it to every ray, one that loses turns it off; an off class
// samples again after kRetryEvery frames (twice as long after each losing sample); a class at
// every ray that loses goes off; a sample's dispatches count their fixed cost once; a class that
// does not predict never probes; adaptive off probes every ray of every frame; samples cost at
// most AdaptivePredictor::kSampleBudget of the class's plain trace time, however dear they are.
#include <vector>

#include <gtest/gtest.h>

#include "hrpp/adaptive_predictor.h"
#include "hrpp_passes.h"

namespace hrpp {
namespace {

PredictorConfig on(bool adaptive = true) {
  PredictorConfig c;
  c.enabled = true;
  c.adaptive = adaptive;
  return c;
}

// A frame of 1000 rays traced without prediction at 1 ms per 100 rays (10 ms).
ClassFrameCost off_frame(double ms = 10.0) {
  ClassFrameCost c;
  c.rays = c.traced = 1000;
  c.trace_ms = ms;
  return c;
}

// A sample frame: the plain trace of 1000 rays (10 ms) and the stage over 10 of them costing
// `ms` per 100 sampled rays (predict + resolve: half of it), within the sampling budget.
ClassFrameCost sample_frame(double ms) {
  ClassFrameCost c = off_frame();
  c.mode = Probe::kSample;
  c.sampled = 10;
  c.sample_ms = 0.1 * ms;
  c.sample_stage_ms = 0.05 * ms;
  return c;
}

// A frame with every ray predicted, costing `ms` in all.
ClassFrameCost all_frame(double ms, std::uint64_t traced) {
  ClassFrameCost c;
  c.mode = Probe::kAll;
  c.rays = 1000;
  c.traced = traced;
  c.predict_ms = 0.2 * ms;
  c.trace_ms = 0.7 * ms;
  c.resolve_ms = 0.1 * ms;
  return c;
}

TEST(AdaptivePredictor, SamplesThenPredictsAClassThatSavesTime) {
  AdaptivePredictor a(on());
  EXPECT_EQ(a.mode(RayClass::kCamera), Probe::kSample);
  ClassDecision d = a.end_frame(RayClass::kCamera, sample_frame(0.5));
  EXPECT_EQ(d.reason, Reason::kWarming);  // the table was empty
  EXPECT_EQ(d.next, Probe::kSample);
  EXPECT_DOUBLE_EQ(d.off_ms_per_ray, 0.01);
  d = a.end_frame(RayClass::kCamera, sample_frame(0.5));  // 5 us per sampled ray against 10
  EXPECT_EQ(d.reason, Reason::kGain);
  EXPECT_NEAR(d.gain_ms, 1000 * (0.01 - 0.005), 1e-9);
  EXPECT_EQ(d.next, Probe::kAll);
  for (int f = 0; f < 6; ++f) {
    d = a.end_frame(RayClass::kCamera, all_frame(6.0, 400));
    EXPECT_EQ(d.reason, Reason::kGain);
    EXPECT_NEAR(d.gain_ms, 10.0 - 6.0, 1e-9);
    EXPECT_EQ(a.mode(RayClass::kCamera), Probe::kAll);
  }
  EXPECT_EQ(d.confidence, AdaptivePredictor::kConfidenceMax);
  // The costs change: two losing frames bring the confidence under kConfidenceOn.
  d = a.end_frame(RayClass::kCamera, all_frame(12.0, 900));
  EXPECT_EQ(d.reason, Reason::kLoss);
  EXPECT_EQ(d.next, Probe::kAll);
  d = a.end_frame(RayClass::kCamera, all_frame(12.0, 900));
  EXPECT_EQ(d.reason, Reason::kLoss);
  EXPECT_EQ(d.next, Probe::kOff);
}

TEST(AdaptivePredictor, StopsALosingClassAndSamplesItAgain) {
  AdaptivePredictor a(on());
  a.end_frame(RayClass::kShadow, sample_frame(1.5));  // warming
  ClassDecision d = a.end_frame(RayClass::kShadow, sample_frame(1.5));  // 15 us against 10
  EXPECT_EQ(d.reason, Reason::kLoss);
  EXPECT_LT(d.gain_ms, 0.0);
  EXPECT_EQ(d.next, Probe::kOff);
  int frames_off = 0;
  while (a.mode(RayClass::kShadow) == Probe::kOff) {
    d = a.end_frame(RayClass::kShadow, off_frame(8.0));
    ++frames_off;
    ASSERT_LE(frames_off, AdaptivePredictor::kRetryEvery);
  }
  EXPECT_EQ(frames_off, AdaptivePredictor::kRetryEvery);
  EXPECT_EQ(d.reason, Reason::kRetry);
  EXPECT_EQ(d.next, Probe::kSample);
  EXPECT_DOUBLE_EQ(d.off_ms_per_ray, 0.008);  // the last plain trace's
  // A losing sample: off again, twice as long.
  d = a.end_frame(RayClass::kShadow, sample_frame(1.2));
  EXPECT_EQ(d.reason, Reason::kLoss);
  for (int f = 1; f < 2 * AdaptivePredictor::kRetryEvery; ++f)
    EXPECT_EQ(a.end_frame(RayClass::kShadow, off_frame()).next, Probe::kOff);
  EXPECT_EQ(a.end_frame(RayClass::kShadow, off_frame()).next, Probe::kSample);
  // The costs change: a sample that gains turns the class to every ray.
  d = a.end_frame(RayClass::kShadow, sample_frame(0.4));
  EXPECT_EQ(d.reason, Reason::kGain);
  EXPECT_EQ(d.next, Probe::kAll);
}

// Predict + resolve alone cost more per sampled ray than the plain trace per ray: off at once,
// even from the warming sample.
TEST(AdaptivePredictor, AHopelessClassStopsAtOnce) {
  AdaptivePredictor a(on());
  ClassFrameCost c = sample_frame(1.0);
  c.sample_stage_ms = 0.1;  // 10 us per sampled ray: as much as the plain trace
  const ClassDecision d = a.end_frame(RayClass::kBounce, c);
  EXPECT_EQ(d.reason, Reason::kHopeless);
  EXPECT_EQ(d.next, Probe::kOff);
  EXPECT_EQ(a.mode(RayClass::kBounce), Probe::kOff);
}

// A sample over 2 rounds whose dispatches cost `dispatch_ms` each on top of 6 us per sampled ray
// (predict + resolve: 3 us): the fixed cost is measured by one empty dispatch per round.
ClassFrameCost sample_with_dispatches(double dispatch_ms) {
  ClassFrameCost c = off_frame();
  c.mode = Probe::kSample;
  c.rounds = 2;
  c.sampled = 100;
  c.sample_ms = 100 * 0.006 + 3 * 2 * dispatch_ms;
  c.sample_stage_ms = 100 * 0.003 + 2 * 2 * dispatch_ms;
  c.empty_dispatch_ms = 2 * dispatch_ms;
  return c;
}

// The sample's dispatches carry 1/10 of the rays here, so their fixed cost would count 10 times
// too much per ray: it is counted once per dispatch of a predicted frame instead (3 per pass,
// 2 passes with the default pilot schedule, 2 rounds).
TEST(AdaptivePredictor, ASampleCountsEachDispatchOnce) {
  AdaptivePredictor a(on());
  a.end_frame(RayClass::kCamera, sample_with_dispatches(0.2));  // warming
  // Uncorrected: 18 us per sampled ray (11 for predict + resolve) against 10: hopeless. Per
  // ray 6 us, plus 12 dispatches of 0.2 ms: a predicted frame costs 8.4 ms against 10.
  ClassDecision d = a.end_frame(RayClass::kCamera, sample_with_dispatches(0.2));
  EXPECT_EQ(d.reason, Reason::kGain);
  EXPECT_DOUBLE_EQ(d.dispatch_ms, 0.2);
  EXPECT_NEAR(d.gain_ms, 10.0 - (6.0 + 12 * 0.2), 1e-9);
  EXPECT_EQ(d.next, Probe::kAll);
  // Dispatches of 0.5 ms: 12 of them make the predicted frame cost 12 ms: a loss.
  AdaptivePredictor b(on());
  b.end_frame(RayClass::kCamera, sample_with_dispatches(0.5));
  d = b.end_frame(RayClass::kCamera, sample_with_dispatches(0.5));
  EXPECT_EQ(d.reason, Reason::kLoss);
  EXPECT_NEAR(d.gain_ms, 10.0 - (6.0 + 12 * 0.5), 1e-9);
  EXPECT_EQ(d.next, Probe::kOff);
}

TEST(AdaptivePredictor, AFrameWithoutRaysIsNotJudged) {
  AdaptivePredictor a(on());
  ClassFrameCost idle;
  idle.mode = Probe::kSample;
  const ClassDecision d = a.end_frame(RayClass::kBounce, idle);
  EXPECT_EQ(d.reason, Reason::kIdle);
  EXPECT_EQ(d.next, Probe::kSample);
  EXPECT_EQ(a.end_frame(RayClass::kBounce, sample_frame(0.5)).reason, Reason::kWarming);
}

TEST(AdaptivePredictor, ClassesAreIndependent) {
  AdaptivePredictor a(on());
  for (int f = 0; f < 3; ++f) {
    a.end_frame(RayClass::kCamera, f < 2 ? sample_frame(0.5) : all_frame(6.0, 400));
    a.end_frame(RayClass::kBounce, sample_frame(1.5));
  }
  EXPECT_EQ(a.mode(RayClass::kCamera), Probe::kAll);
  EXPECT_EQ(a.mode(RayClass::kBounce), Probe::kOff);
}

TEST(AdaptivePredictor, DisabledClassesAndFixedMode) {
  PredictorConfig c = on();
  c.classes[RayClass::kShadow] = false;
  AdaptivePredictor a(c);
  EXPECT_EQ(a.mode(RayClass::kShadow), Probe::kOff);
  EXPECT_EQ(a.end_frame(RayClass::kShadow, off_frame()).reason, Reason::kDisabled);
  EXPECT_EQ(a.mode(RayClass::kShadow), Probe::kOff);

  AdaptivePredictor fixed(on(false));
  EXPECT_EQ(fixed.mode(RayClass::kBounce), Probe::kAll);
  for (int f = 0; f < 8; ++f) {
    const ClassDecision d = fixed.end_frame(RayClass::kBounce, all_frame(100.0, 1000));
    EXPECT_EQ(d.reason, Reason::kFixed);
    EXPECT_EQ(d.next, Probe::kAll);
  }
  PredictorConfig batched = on();
  batched.batch = 64;  // the deterministic order: no decisions from timings
  AdaptivePredictor in_batches(batched);
  EXPECT_EQ(in_batches.mode(RayClass::kCamera), Probe::kAll);
  EXPECT_EQ(in_batches.end_frame(RayClass::kCamera, all_frame(100.0, 1000)).reason, Reason::kFixed);
  PredictorConfig off;
  AdaptivePredictor none(off);
  for (RayClass k : kRayClasses) EXPECT_EQ(none.mode(k), Probe::kOff);
}

// The HRPP stage's passes (shaders/shared/hrpp_passes.h, also compiled into hrpp_predict): a
// pass's indices are distinct, in range, as many as its count says, and the pilots and the
// others together are every ray once; the sample's blocks are consecutive rays.
TEST(HrppPasses, IndicesCoverWhatTheCountsSay) {
  for (const gpu::uint total : {0u, 1u, 7u, 255u, 256u, 257u, 8191u, 8192u, 8193u, 70000u})
    for (const gpu::uint stride : {1u, 2u, 16u, 32u}) {
      if (stride >= 2) {  // the pilot schedule needs K >= 2
        std::vector<int> seen(total, 0);
        for (const gpu::uint pass : {HRPP_PASS_PILOTS, HRPP_PASS_OTHERS})
          for (gpu::uint j = 0; j < gpu::hrpp_pass_ray_count(total, pass, stride); ++j) {
            const gpu::uint i = gpu::hrpp_pass_ray_index(j, pass, stride);
            ASSERT_LT(i, total);
            ++seen[i];
          }
        for (gpu::uint i = 0; i < total; ++i) ASSERT_EQ(seen[i], 1) << total << " " << stride;
      }
      const gpu::uint n = gpu::hrpp_pass_ray_count(total, HRPP_PASS_SAMPLE, stride);
      gpu::uint expected = 0;  // rays i whose block i / HRPP_SAMPLE_BLOCK is a multiple of stride
      for (gpu::uint i = 0; i < total; ++i) expected += (i / HRPP_SAMPLE_BLOCK) % stride == 0;
      EXPECT_EQ(n, expected) << total << " " << stride;
      for (gpu::uint j = 0; j < n; ++j) {
        const gpu::uint i = gpu::hrpp_pass_ray_index(j, HRPP_PASS_SAMPLE, stride);
        ASSERT_LT(i, total);
        ASSERT_EQ((i / HRPP_SAMPLE_BLOCK) % stride, 0u);
        if (j > 0 && j % HRPP_SAMPLE_BLOCK != 0) {
          ASSERT_EQ(i, gpu::hrpp_pass_ray_index(j - 1, HRPP_PASS_SAMPLE, stride) + 1);
        }
      }
      EXPECT_EQ(gpu::hrpp_pass_ray_count(total, HRPP_PASS_ALL, stride), total);
      EXPECT_EQ(gpu::hrpp_pass_ray_count(total, HRPP_PASS_NONE, stride), 0u);
    }
}

// A sample costing 10% of the class's plain trace (a GPU's fixed dispatch costs beside a short
// trace): the warming sample's successor and every retry wait until the budget has covered it,
// so over a long run the samples cost at most kSampleBudget of the trace time, plus the first
// (free) sample.
TEST(AdaptivePredictor, DearSamplesWaitForTheBudget) {
  AdaptivePredictor a(on());
  ClassFrameCost dear = sample_frame(1.5);  // losing: 15 us per sampled ray against 10
  dear.sample_ms = 1.0;                     // 10% of the 10 ms trace
  dear.sample_stage_ms = 0.075;
  EXPECT_EQ(a.sample_stride(RayClass::kShadow), PredictorConfig{}.sample);
  ClassDecision d = a.end_frame(RayClass::kShadow, dear);
  EXPECT_EQ(d.reason, Reason::kBudget);  // warming, but the next sample is not covered yet
  EXPECT_EQ(d.next, Probe::kOff);
  // 100 us per sampled ray against a budget of 0.2 us per ray of the class: every 512th block
  // (the smallest power of two >= 500) keeps the sample's per-ray part within one frame's credit.
  EXPECT_EQ(d.sample_stride, 512u);
  EXPECT_EQ(a.sample_stride(RayClass::kShadow), 512u);
  double sampling_ms = dear.sample_ms, trace_ms = 10.0;
  int samples = 1;
  for (int f = 1; f < 400; ++f) {
    const bool sampling = a.mode(RayClass::kShadow) == Probe::kSample;
    d = a.end_frame(RayClass::kShadow, sampling ? dear : off_frame());
    samples += sampling ? 1 : 0;
    sampling_ms += sampling ? dear.sample_ms : 0.0;
    trace_ms += 10.0;
    EXPECT_NE(d.next, Probe::kAll) << f;
  }
  EXPECT_GE(samples, 3);  // it does sample again
  EXPECT_LE(sampling_ms - dear.sample_ms, AdaptivePredictor::kSampleBudget * trace_ms);
}

}  // namespace
}  // namespace hrpp
