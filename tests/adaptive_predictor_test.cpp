// The adaptive predictor (host/hrpp/adaptive_predictor.h) on forced costs: a class whose
// prediction saves time keeps probing, one that loses stops after its warming frame and one
// judged loss, is retried after kRetryEvery frames (twice as long after each losing trial), and
// comes back when a trial gains; a class that does not predict never probes; adaptive off
// probes every frame.
#include <vector>

#include <gtest/gtest.h>

#include "hrpp/adaptive_predictor.h"

namespace hrpp {
namespace {

PredictorConfig on(bool adaptive = true) {
  PredictorConfig c;
  c.enabled = true;
  c.adaptive = adaptive;
  return c;
}

// A frame of 1000 rays: traced without prediction it costs 1 ms per 100 rays (10 ms).
ClassFrameCost off_frame() {
  ClassFrameCost c;
  c.rays = c.traced = 1000;
  c.trace_ms = 10.0;
  return c;
}

// A probing frame costing `ms` in all, with `traced` rays left to the trace kernel.
ClassFrameCost probing_frame(double ms, std::uint64_t traced) {
  ClassFrameCost c;
  c.probed = true;
  c.rays = 1000;
  c.traced = traced;
  c.predict_ms = 0.2 * ms;
  c.trace_ms = 0.7 * ms;
  c.resolve_ms = 0.1 * ms;
  return c;
}

TEST(AdaptivePredictor, KeepsProbingAClassThatSavesTime) {
  AdaptivePredictor a(on());
  EXPECT_TRUE(a.probing(RayClass::kCamera));
  // Warming: an empty table, every ray traced (10 ms of trace: the cost without prediction).
  ClassFrameCost warm = probing_frame(14.3, 1000);
  ClassDecision d = a.end_frame(RayClass::kCamera, warm);
  EXPECT_STREQ(d.reason, "warming");
  EXPECT_TRUE(d.probe_next);
  EXPECT_DOUBLE_EQ(d.off_ms_per_ray, warm.trace_ms / 1000.0);
  for (int f = 0; f < 6; ++f) {
    d = a.end_frame(RayClass::kCamera, probing_frame(6.0, 400));
    EXPECT_STREQ(d.reason, "gain");
    EXPECT_NEAR(d.gain_ms, 1000 * (14.3 * 0.7 / 1000) - 6.0, 1e-9);
    EXPECT_TRUE(d.probe_next);
    EXPECT_TRUE(a.probing(RayClass::kCamera));
  }
  EXPECT_EQ(d.confidence, AdaptivePredictor::kConfidenceMax);
}

TEST(AdaptivePredictor, StopsALosingClassAndRetriesIt) {
  AdaptivePredictor a(on());
  a.end_frame(RayClass::kShadow, probing_frame(13.0, 1000));  // warming: trace 9.1 ms / 1000
  ClassDecision d = a.end_frame(RayClass::kShadow, probing_frame(13.0, 990));
  EXPECT_STREQ(d.reason, "loss");
  EXPECT_LT(d.gain_ms, 0.0);
  EXPECT_FALSE(d.probe_next);
  EXPECT_FALSE(a.probing(RayClass::kShadow));
  // Off: the trace time per ray is measured; a trial every kRetryEvery frames.
  int frames_off = 0;
  while (!a.probing(RayClass::kShadow)) {
    d = a.end_frame(RayClass::kShadow, off_frame());
    ++frames_off;
    ASSERT_LE(frames_off, AdaptivePredictor::kRetryEvery);
  }
  EXPECT_EQ(frames_off, AdaptivePredictor::kRetryEvery);
  EXPECT_STREQ(d.reason, "retry");
  EXPECT_DOUBLE_EQ(d.off_ms_per_ray, 0.01);
  // A losing trial: off again, twice as long.
  d = a.end_frame(RayClass::kShadow, probing_frame(12.0, 950));
  EXPECT_STREQ(d.reason, "loss");
  EXPECT_FALSE(d.probe_next);
  for (int f = 1; f < 2 * AdaptivePredictor::kRetryEvery; ++f)
    EXPECT_FALSE(a.end_frame(RayClass::kShadow, off_frame()).probe_next);
  EXPECT_TRUE(a.end_frame(RayClass::kShadow, off_frame()).probe_next);
  // The costs change: a trial that gains turns the class back on.
  d = a.end_frame(RayClass::kShadow, probing_frame(5.0, 300));
  EXPECT_STREQ(d.reason, "gain");
  EXPECT_TRUE(d.probe_next);
  EXPECT_TRUE(a.probing(RayClass::kShadow));
}

// A warming frame whose true positives left too few rays to the trace measures no cost without
// prediction: the next frame runs without it, then probing resumes and is judged.
TEST(AdaptivePredictor, MeasuresTheCostWithoutPredictionFirst) {
  AdaptivePredictor a(on());
  EXPECT_STREQ(a.end_frame(RayClass::kCamera, probing_frame(8.0, 600)).reason, "warming");
  ClassDecision d = a.end_frame(RayClass::kCamera, probing_frame(8.0, 500));
  EXPECT_STREQ(d.reason, "unmeasured");
  EXPECT_FALSE(d.probe_next);
  d = a.end_frame(RayClass::kCamera, off_frame());
  EXPECT_STREQ(d.reason, "off");
  EXPECT_TRUE(d.probe_next);  // confidence unchanged: back on
  d = a.end_frame(RayClass::kCamera, probing_frame(14.0, 500));
  EXPECT_STREQ(d.reason, "loss");
  EXPECT_FALSE(d.probe_next);
}

// Predict + resolve alone cost more than a trace of every ray: off after the first frame.
TEST(AdaptivePredictor, AHopelessClassStopsAtOnce) {
  AdaptivePredictor a(on());
  ClassFrameCost c = probing_frame(20.0, 1000);  // trace 14 ms for all: predict + resolve 6 ms
  c.predict_ms = 12.0;                           // now 14 ms: hopeless
  const ClassDecision d = a.end_frame(RayClass::kBounce, c);
  EXPECT_STREQ(d.reason, "hopeless");
  EXPECT_FALSE(d.probe_next);
  EXPECT_LT(d.gain_ms, 0.0);
}

TEST(AdaptivePredictor, ClassesAreIndependent) {
  AdaptivePredictor a(on());
  for (int f = 0; f < 3; ++f) {
    a.end_frame(RayClass::kCamera, probing_frame(f == 0 ? 14.0 : 5.0, f == 0 ? 1000 : 300));
    a.end_frame(RayClass::kBounce, probing_frame(14.0, 1000));
  }
  EXPECT_TRUE(a.probing(RayClass::kCamera));
  EXPECT_FALSE(a.probing(RayClass::kBounce));
}

TEST(AdaptivePredictor, DisabledClassesAndFixedMode) {
  PredictorConfig c = on();
  c.classes[RayClass::kShadow] = false;
  AdaptivePredictor a(c);
  EXPECT_FALSE(a.probing(RayClass::kShadow));
  EXPECT_STREQ(a.end_frame(RayClass::kShadow, off_frame()).reason, "disabled");
  EXPECT_FALSE(a.probing(RayClass::kShadow));

  AdaptivePredictor fixed(on(false));
  for (int f = 0; f < 8; ++f) {
    const ClassDecision d = fixed.end_frame(RayClass::kBounce, probing_frame(100.0, 1000));
    EXPECT_STREQ(d.reason, "fixed");
    EXPECT_TRUE(d.probe_next);
  }
  PredictorConfig off;
  AdaptivePredictor none(off);
  for (RayClass k : kRayClasses) EXPECT_FALSE(none.probing(k));
}

}  // namespace
}  // namespace hrpp
