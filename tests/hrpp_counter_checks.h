// The identities HRPP's counters of one ray class must satisfy (shaders/shared/hrpp_types.h),
// for the predictor suites (tests/hrpp_predictor_test.cpp, tests/hrpp_render_test.cpp).
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "hrpp_types.h"

namespace hrpp::test {

// predictor hits + negatives = probes; true + false positives = predictor hits; requests =
// inserts + present + drops; wrong closest hits <= true positives.
inline void expect_predictor_counters_add_up(const gpu::PredictorCounters& pc,
                                             const std::string& what) {
  const auto& c = pc.c;
  EXPECT_EQ(c[HRPP_PC_PREDICTOR_HITS] + c[HRPP_PC_NEGATIVES], c[HRPP_PC_PROBES]) << what;
  EXPECT_EQ(c[HRPP_PC_TRUE_POSITIVES] + c[HRPP_PC_FALSE_POSITIVES], c[HRPP_PC_PREDICTOR_HITS])
      << what;
  EXPECT_EQ(c[HRPP_PC_INSERTS] + c[HRPP_PC_INSERT_PRESENT] + c[HRPP_PC_INSERT_DROPS],
            c[HRPP_PC_INSERT_REQUESTS])
      << what;
  EXPECT_LE(c[HRPP_PC_WRONG_CLOSEST] + c[HRPP_PC_GATED], c[HRPP_PC_TRUE_POSITIVES]) << what;
}

}  // namespace hrpp::test
