// host/harness/validation: the benchmark harness's check of a tracer's hits against a
// reference's, on hand-made answers whose verdicts are known: the same hit, a tie (another
// triangle at the same t within the tolerance), a mismatch (another t, a hit for a miss), and
// any-hit answers judged by occlusion alone; and the evenly spread subset it checks.
#include <gtest/gtest.h>

#include "harness/validation.h"

namespace hrpp {
namespace {

TEST(Validation, SortsAnswersIntoExactTiesAndMismatches) {
  const std::vector<gpu::Ray> rays(6, gpu::Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, 1e30f});
  const std::vector<gpu::Hit> ref = {{3, 2.0f, 0.1f, 0.2f}, {3, 2.0f, 0.1f, 0.2f},
                                     {3, 2.0f, 0.1f, 0.2f}, {-1, 0, 0, 0},
                                     {3, 2.0f, 0.1f, 0.2f}, {5, 1e-9f, 0, 0}};
  const std::vector<gpu::Hit> got = {{3, 2.0f, 0.1f, 0.2f},        // exact
                                     {4, 2.00001f, 0.3f, 0.3f},    // tie: 5e-6 relative
                                     {3, 2.001f, 0.1f, 0.2f},      // mismatch: 5e-4 relative
                                     {7, 1.0f, 0, 0},              // mismatch: a hit for a miss
                                     {3, 2.0000002f, 0.1f, 0.2f},  // same triangle, t rounds
                                     {5, 5e-8f, 0, 0}};            // t near 0: within 1e-7 of 1
  const std::vector<std::size_t> all = spread_subset(rays.size(), 0);
  const Validation v = validate(rays, ref, got, all, QueryKind::kClosest, 1.0f);
  EXPECT_EQ(v.checked, 6u);
  EXPECT_EQ(v.exact, 1u);
  EXPECT_EQ(v.ties, 1u);
  EXPECT_EQ(v.mismatches, 2u);
  ASSERT_EQ(v.examples.size(), 2u);
  EXPECT_NE(v.examples[0].find("ray 2 "), std::string::npos) << v.examples[0];
  EXPECT_NE(v.examples[1].find("ray 3 "), std::string::npos) << v.examples[1];
}

TEST(Validation, AnyHitAnswersAreJudgedByOcclusion) {
  const std::vector<gpu::Ray> rays(3, gpu::Ray{{0, 0, 0}, 0.0f, {1, 0, 0}, 1.0f});
  const std::vector<gpu::Hit> ref = {{0, 0, 0, 0}, {-1, 0, 0, 0}, {0, 0, 0, 0}};
  const std::vector<gpu::Hit> got = {{9, 0.5f, 0, 0}, {-1, 0, 0, 0}, {-1, 0, 0, 0}};
  const Validation v = validate(rays, ref, got, spread_subset(3, 0), QueryKind::kAny, 1.0f);
  EXPECT_EQ(v.exact, 2u);
  EXPECT_EQ(v.mismatches, 1u);
}

TEST(Validation, ChecksOnlyTheSubset) {
  EXPECT_EQ(spread_subset(10, 5), (std::vector<std::size_t>{0, 2, 4, 6, 8}));
  EXPECT_EQ(spread_subset(3, 7), (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_TRUE(spread_subset(0, 4).empty());
  const std::vector<gpu::Ray> rays(4, gpu::Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, 1e30f});
  const std::vector<gpu::Hit> ref(4, gpu::Hit{1, 1.0f, 0, 0});
  std::vector<gpu::Hit> got = ref;
  got[1].prim = -1;  // outside the subset {0, 2}
  const Validation v = validate(rays, ref, got, spread_subset(4, 2), QueryKind::kClosest, 1.0f);
  EXPECT_EQ(v.checked, 2u);
  EXPECT_EQ(v.mismatches, 0u);
}

}  // namespace
}  // namespace hrpp
