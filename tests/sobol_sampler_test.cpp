// shaders/shared/sobol_sampler.h on the host: the Owen-scrambled Sobol pairs the path tracer
// draws with --sampler sobol. Dimension 1 equals Sobol's own recurrence; every pixel's first
// 2^k samples of a pair form a (0,k,2)-net (one point in each elementary interval); pixels and
// pairs are decorrelated; and a smooth integral converges faster than with independent samples.
#include <cmath>
#include <cstdio>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "sobol_sampler.h"

namespace hrpp {
namespace {

// Sobol dimension 1 from its direction numbers: v_1 = 2^31, v_k = v_(k-1) ^ (v_(k-1) >> 1).
std::uint32_t sobol_dim1_by_recurrence(std::uint32_t i) {
  std::uint32_t v = 0x80000000u, x = 0;
  for (; i != 0; i >>= 1, v ^= v >> 1)
    if (i & 1u) x ^= v;
  return x;
}

TEST(SobolSampler, DimensionOneIsSobols) {
  for (std::uint32_t i = 0; i < 200000; ++i)
    ASSERT_EQ(gpu::sobol_dim1(i), sobol_dim1_by_recurrence(i)) << i;
  for (std::uint32_t i : {0xFFFFFFFFu, 0x80000000u, 0x12345678u})
    EXPECT_EQ(gpu::sobol_dim1(i), sobol_dim1_by_recurrence(i)) << i;
  EXPECT_EQ(gpu::reverse_bits(1u), 0x80000000u);
  EXPECT_EQ(gpu::reverse_bits(0x12345678u), 0x1E6A2C48u);
}

// The first 2^k samples of a stream: exactly one in every 2^-a × 2^-(k-a) interval.
TEST(SobolSampler, EachPixelsPairsAreZeroKTwoNets) {
  for (std::uint32_t pixel : {0u, 1u, 77u, 65535u})
    for (std::uint32_t pair = 0; pair < 4; ++pair)
      for (std::uint32_t k : {4u, 6u}) {
        const std::uint32_t stream = gpu::sobol_stream(pixel, 2, pair, 9);
        const std::uint32_t n = 1u << k;
        for (std::uint32_t a = 0; a <= k; ++a) {
          std::set<std::pair<std::uint32_t, std::uint32_t>> cells;
          for (std::uint32_t i = 0; i < n; ++i) {
            const glm::vec2 p = gpu::sobol_pair(i, stream);
            ASSERT_TRUE(p.x >= 0.0f && p.x < 1.0f && p.y >= 0.0f && p.y < 1.0f);
            cells.insert({static_cast<std::uint32_t>(p.x * static_cast<float>(1u << a)),
                          static_cast<std::uint32_t>(p.y * static_cast<float>(1u << (k - a)))});
          }
          EXPECT_EQ(cells.size(), n)
              << "pixel " << pixel << " pair " << pair << " k " << k << " a " << a;
        }
      }
}

TEST(SobolSampler, PixelsAndPairsAreDecorrelated) {
  // Sample 0 of many pixels: spread over [0, 1) like independent draws, never repeated.
  std::set<float> firsts;
  double sum = 0.0;
  const int pixels = 4096;
  for (int p = 0; p < pixels; ++p) {
    const glm::vec2 s =
        gpu::sobol_pair(0, gpu::sobol_stream(static_cast<std::uint32_t>(p), 0, 0, 1));
    firsts.insert(s.x);
    sum += s.x;
  }
  EXPECT_GT(firsts.size(), static_cast<std::size_t>(pixels * 0.99));
  EXPECT_NEAR(sum / pixels, 0.5, 4.0 * std::sqrt(1.0 / 12.0 / pixels));
  // Two pairs of one pixel: uncorrelated x coordinates over 1024 samples.
  double sxy = 0.0;
  for (std::uint32_t i = 0; i < 1024; ++i)
    sxy += (gpu::sobol_pair(i, gpu::sobol_stream(5, 1, 0, 1)).x - 0.5) *
           (gpu::sobol_pair(i, gpu::sobol_stream(5, 1, 1, 1)).x - 0.5);
  EXPECT_LT(std::abs(sxy / 1024.0) / (1.0 / 12.0), 0.1);
}

// ∫∫ over [0,1)² of a smooth function and of a disk's indicator, 256 samples per pixel over
// 256 pixels: the RMS error of the Sobol pairs against independent PCG samples.
TEST(SobolSampler, IntegratesFasterThanIndependentSamples) {
  auto smooth = [](glm::vec2 p) { return std::exp(p.x) * std::sin(3.0f * p.y); };
  const double smooth_exact = (std::exp(1.0) - 1.0) * (1.0 - std::cos(3.0)) / 3.0;
  auto disk = [](glm::vec2 p) {
    return (p.x - 0.5f) * (p.x - 0.5f) + (p.y - 0.5f) * (p.y - 0.5f) < 0.16f ? 1.0f : 0.0f;
  };
  const double disk_exact = 3.14159265358979 * 0.16;
  for (int f = 0; f < 2; ++f) {
    double err_sobol = 0.0, err_indep = 0.0;
    for (std::uint32_t pixel = 0; pixel < 256; ++pixel) {
      double s = 0.0, r = 0.0;
      std::uint32_t rng = gpu::rng_init(pixel, 0, 0, 4);
      for (std::uint32_t i = 0; i < 256; ++i) {
        const glm::vec2 p = gpu::sobol_pair(i, gpu::sobol_stream(pixel, 0, 0, 4));
        const float x = gpu::rng_next(rng);
        const glm::vec2 q(x, gpu::rng_next(rng));
        s += f == 0 ? smooth(p) : disk(p);
        r += f == 0 ? smooth(q) : disk(q);
      }
      const double exact = f == 0 ? smooth_exact : disk_exact;
      err_sobol += (s / 256 - exact) * (s / 256 - exact);
      err_indep += (r / 256 - exact) * (r / 256 - exact);
    }
    const double ratio = std::sqrt(err_sobol / err_indep);
    std::printf("%s: RMS error sobol / independent = %.4f\n", f == 0 ? "smooth" : "disk", ratio);
    EXPECT_LT(ratio, f == 0 ? 0.1 : 0.5);
  }
}

}  // namespace
}  // namespace hrpp
