// shaders/shared/path_vertex.h and bsdf.h on the host: the multiple importance sampling weights
// of light and BSDF sampling and the pdfs they are made of. The weights of the two ways a
// direction can be sampled must sum to one under every strategy (a weight that counts emission
// twice, or drops it, fails here); each lobe's pdf must be the density its sampling draws.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "path_vertex.h"

namespace hrpp {
namespace {

using gpu::vec3;

gpu::PathState bounce_path(float pdf, bool specular) {
  return gpu::path_state(vec3(1.0f), 0, 0, 1, specular ? 1u : 0u, pdf);
}

TEST(Mis, WeightsOfTheTwoStrategiesSumToOne) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> exponent(-30.0f, 30.0f);
  for (int i = 0; i < 10000; ++i) {
    const float light = std::exp2(exponent(rng)), bsdf = std::exp2(exponent(rng));
    EXPECT_NEAR(gpu::mis_power(light, bsdf) + gpu::mis_power(bsdf, light), 1.0f, 1e-6f);
    for (std::uint32_t s : {HRPP_LIGHTS_MIS, HRPP_LIGHTS_NEE, HRPP_LIGHTS_BSDF}) {
      const float nee = gpu::nee_weight(s, false, light, bsdf);
      const float hit = gpu::emission_weight(s, bounce_path(bsdf, false), light);
      ASSERT_NEAR(nee + hit, 1.0f, 1e-6f)
          << "strategy " << s << " light " << light << " bsdf " << bsdf;
      EXPECT_GE(nee, 0.0f);
      EXPECT_GE(hit, 0.0f);
    }
  }
  // MIS: the strategy with the larger pdf takes most of the weight.
  EXPECT_GT(gpu::nee_weight(HRPP_LIGHTS_MIS, false, 10.0f, 1.0f), 0.99f);
  EXPECT_LT(gpu::nee_weight(HRPP_LIGHTS_MIS, false, 1.0f, 10.0f), 0.01f);
}

TEST(Mis, EmissionOnlyLightSamplingCannotFindCountsWhole) {
  for (std::uint32_t s : {HRPP_LIGHTS_MIS, HRPP_LIGHTS_NEE, HRPP_LIGHTS_BSDF}) {
    EXPECT_EQ(gpu::emission_weight(s, gpu::camera_path(0, 0), 3.0f), 1.0f);    // camera ray
    EXPECT_EQ(gpu::emission_weight(s, bounce_path(0.0f, true), 3.0f), 1.0f);   // after a mirror
    EXPECT_EQ(gpu::emission_weight(s, bounce_path(2.0f, false), 0.0f), 1.0f);  // not a light
    // The last vertex takes no BSDF sample: light sampling carries it whole.
    EXPECT_EQ(gpu::nee_weight(s, true, 1.0f, 5.0f), 1.0f);
  }
  // Overflow-free: huge and zero pdfs give weights in [0, 1], never NaN.
  EXPECT_EQ(gpu::mis_power(0.0f, 1.0f), 0.0f);
  EXPECT_EQ(gpu::mis_power(1e30f, 1e-30f), 1.0f);
  EXPECT_EQ(gpu::mis_power(1e-30f, 1e30f), 0.0f);
  EXPECT_EQ(gpu::mis_power(INFINITY, 1.0f), 1.0f);
}

// The light pdf a BSDF ray computes at a hit equals the one light sampling used for the same
// point: both are the pick probability times distance² / (|cos| × area).
TEST(Mis, HitLightPdfEqualsTheSamplePdf) {
  gpu::GpuLight l{};
  l.type = HRPP_LIGHT_TRIANGLE;
  l.position = vec3(0, 2, 0);
  l.dir = vec3(1, 0, 0);
  l.edge2 = vec3(0, 0, 1);
  l.color = vec3(1.0f);
  gpu::ShadeTriangle t{};
  t.v0 = l.position;
  t.v1 = l.position + l.dir;
  t.v2 = l.position + l.edge2;
  gpu::SurfaceHit s{};
  s.p = vec3(0.3f, 0.0f, 0.2f);
  s.ng = s.ns = vec3(0, 1, 0);
  const gpu::LightSample ls = gpu::sample_light(l, s, 0.4f, 0.3f);
  const vec3 q = s.p + ls.wi * 0.0f;  // the sampled point lies along wi
  const float dist = (2.0f - q.y) / ls.wi.y;
  EXPECT_NEAR(gpu::hit_light_pdf(t, 0.25f, ls.wi, dist) / (0.25f * ls.pdf), 1.0f, 1e-5f);
  EXPECT_NEAR(ls.pdf, dist * dist / (ls.wi.y * 0.5f), 1e-4f * ls.pdf);
}

// Each lobe's pdf is the density its sampling draws: a sampled direction's Bounce.pdf equals
// lobe_pdf, and ∫ pdf over the directions above the surface equals the share of samples there
// (GGX's visible-normal sampling sends some below the horizon; the diffuse lobe none).
TEST(Mis, LobePdfsAreTheSamplingDensities) {
  const vec3 n(0, 0, 1);
  gpu::SurfaceHit s{};
  s.ng = s.ns = n;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (float roughness : {1.0f, 0.5f, 0.3f}) {
    gpu::GpuMaterial m{};
    m.base_color = vec3(1.0f);
    m.metallic = roughness < 1.0f ? 1.0f : 0.0f;  // 1.0: the diffuse lobe
    m.roughness = roughness;
    const vec3 wo = glm::normalize(vec3(0.5f, 0.1f, 0.8f));
    const gpu::Lobe lobe = gpu::choose_lobe(m, m.base_color, 0.0f);
    // Samples: the share above the horizon, and Bounce.pdf against lobe_pdf.
    int above = 0;
    const int n_samples = 20000;
    for (int i = 0; i < n_samples; ++i) {
      const gpu::Bounce b = gpu::sample_bounce(lobe, m, s, wo, u01(rng), u01(rng));
      if (b.weight == vec3(0.0f)) continue;
      ++above;
      ASSERT_NEAR(b.pdf, gpu::lobe_pdf(lobe, s, wo, b.wi), 1e-3f * b.pdf) << roughness;
    }
    // ∫ lobe_pdf dω over the upper hemisphere: the midpoint rule on a grid uniform in solid
    // angle (z = cos θ and φ).
    double integral = 0.0;
    const int grid = 1500;
    for (int iz = 0; iz < grid; ++iz) {
      const float z = (static_cast<float>(iz) + 0.5f) / static_cast<float>(grid);
      const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
      for (int ip = 0; ip < grid; ++ip) {
        const float phi =
            2.0f * gpu::kPi * (static_cast<float>(ip) + 0.5f) / static_cast<float>(grid);
        integral += gpu::lobe_pdf(lobe, s, wo, vec3(r * std::cos(phi), r * std::sin(phi), z));
      }
    }
    integral *= 2.0 * gpu::kPi / (static_cast<double>(grid) * grid);
    const double share = static_cast<double>(above) / n_samples;
    EXPECT_NEAR(integral, share, 0.005) << "roughness " << roughness;
    std::printf("roughness %.1f: integral of pdf %.4f, samples above %.4f\n", roughness, integral,
                share);
  }
}

}  // namespace
}  // namespace hrpp
