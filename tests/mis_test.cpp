// shaders/shared/path_vertex.h, material_lobes.h and bsdf.h on the host: the multiple importance
// sampling weights of light and BSDF sampling and the pdfs they are made of. The weights of the
// two ways a direction can be sampled must sum to one under every strategy (a weight that counts
// emission twice, or drops it, fails here); each lobe's pdf must be the density its sampling
// draws.
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
    for (std::uint32_t s : {HRPP_LIGHTS_MIS, HRPP_LIGHTS_NEE, HRPP_LIGHTS_BSDF})
      for (bool sees : {true, false}) {
        const float nee = gpu::nee_weight(s, sees, light, bsdf);
        const float hit = gpu::emission_weight(s, bounce_path(bsdf, false), sees, light);
        ASSERT_NEAR(nee + hit, 1.0f, 1e-6f)
            << "strategy " << s << " sees " << sees << " light " << light << " bsdf " << bsdf;
        EXPECT_GE(nee, 0.0f);
        EXPECT_GE(hit, 0.0f);
        if (!sees) {
          EXPECT_EQ(nee, 1.0f);  // too near for the BSDF ray: light sampling alone
        }
      }
  }
  // MIS: the strategy with the larger pdf takes most of the weight.
  EXPECT_GT(gpu::nee_weight(HRPP_LIGHTS_MIS, true, 10.0f, 1.0f), 0.99f);
  EXPECT_LT(gpu::nee_weight(HRPP_LIGHTS_MIS, true, 1.0f, 10.0f), 0.01f);
}

TEST(Mis, EmissionOnlyLightSamplingCannotFindCountsWhole) {
  for (std::uint32_t s : {HRPP_LIGHTS_MIS, HRPP_LIGHTS_NEE, HRPP_LIGHTS_BSDF}) {
    EXPECT_EQ(gpu::emission_weight(s, gpu::camera_path(0, 0), true, 3.0f), 1.0f);  // camera ray
    EXPECT_EQ(gpu::emission_weight(s, bounce_path(0.0f, true), true, 3.0f),
              1.0f);  // after a mirror
    EXPECT_EQ(gpu::emission_weight(s, bounce_path(2.0f, false), true, 0.0f), 1.0f);  // not a light
  }
  // Overflow-free: huge and zero pdfs give weights in [0, 1], never NaN.
  EXPECT_EQ(gpu::mis_power(0.0f, 1.0f), 0.0f);
  EXPECT_EQ(gpu::mis_power(1e30f, 1e-30f), 1.0f);
  EXPECT_EQ(gpu::mis_power(1e-30f, 1e30f), 0.0f);
  EXPECT_EQ(gpu::mis_power(INFINITY, 1.0f), 1.0f);
}

// The last vertex (depth max_depth - 1) takes its BSDF sample like every other, so its light
// sample is MIS-weighted; the ray it leaves on closes the path, which adds only emission.
TEST(Mis, TheRayLeavingTheLastVertexClosesThePath) {
  const std::uint32_t max_depth = 3;
  gpu::PathState path = gpu::camera_path(0, 0);
  for (std::uint32_t depth = 0; depth < max_depth; ++depth) {
    EXPECT_FALSE(gpu::closes_path(path, max_depth)) << depth;
    path.depth += 1;
  }
  EXPECT_TRUE(gpu::closes_path(path, max_depth));
  EXPECT_LT(gpu::nee_weight(HRPP_LIGHTS_MIS, true, 1.0f, 5.0f), 0.1f);
}

// A BSDF ray trusts what it finds from 64 offsets away: the offset scales with the
// coordinates' magnitude (2^-15 of it, 2^-16 near the origin), and so does the distance.
TEST(Mis, BsdfRaysLeaveLightsTooNearTheirOffsetToLightSampling) {
  ASSERT_EQ(gpu::kBsdfOffsetRatio, 64.0f);
  const vec3 origin(0.0f, 0.0f, 0.0f), far(0.0f, 1000.0f, 0.0f);
  EXPECT_TRUE(gpu::bsdf_sees_light_at(origin, 64.0f / 65536.0f));
  EXPECT_FALSE(gpu::bsdf_sees_light_at(origin, 63.0f / 65536.0f));
  EXPECT_TRUE(gpu::bsdf_sees_light_at(far, 1000.0f * 64.0f / 32768.0f));
  EXPECT_FALSE(gpu::bsdf_sees_light_at(far, 1.9f));
  EXPECT_FALSE(gpu::bsdf_sees_light_at(vec3(0.0f, 0.0f, -1000.0f), 1.9f));
}

// The light pdf a BSDF ray computes at a hit equals the one light sampling used for the same
// point: both are the pick probability times distance² / (|cos| × area), measured from the
// offset origin that the shadow ray and the BSDF ray share.
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
  const float r = std::sqrt(0.4f);  // the point sample_triangle_light takes for (0.4, 0.3)
  const vec3 q = l.position + r * 0.7f * l.dir + r * 0.3f * l.edge2;
  const vec3 to = q - ls.shadow.origin;
  const float dist = glm::length(to);
  EXPECT_NEAR(ls.dist, dist, 1e-6f);
  EXPECT_NEAR(gpu::hit_light_pdf(t, 0.25f, to / dist, dist) / (0.25f * ls.pdf), 1.0f, 1e-5f);
  EXPECT_NEAR(ls.pdf, dist * dist / (to.y / dist * 0.5f), 1e-4f * ls.pdf);
}

// A one-sided emitter (pbrt's area lights) lights only the side its winding faces, and a ray
// sees its emission only from there; a two-sided one both ways, with the same radiance.
TEST(Mis, OneSidedLightsEmitFromTheirFrontAlone) {
  gpu::GpuLight l{};
  l.type = HRPP_LIGHT_TRIANGLE;
  l.position = vec3(0, 2, 0);
  l.dir = vec3(1, 0, 0);
  l.edge2 = vec3(0, 0, 1);  // dir × edge2 = -y: the front faces down
  l.color = vec3(3.0f);
  gpu::SurfaceHit below{}, above{};
  below.p = vec3(0.3f, 0.0f, 0.2f);
  below.ng = below.ns = vec3(0, 1, 0);
  above.p = vec3(0.3f, 4.0f, 0.2f);
  above.ng = above.ns = vec3(0, -1, 0);
  const vec3 two_below = gpu::sample_light(l, below, 0.4f, 0.3f).li;
  const vec3 two_above = gpu::sample_light(l, above, 0.4f, 0.3f).li;
  l.cos_inner = 1.0f;  // one-sided
  EXPECT_EQ(gpu::sample_light(l, below, 0.4f, 0.3f).li, two_below);
  EXPECT_GT(two_below.x, 0.0f);
  EXPECT_GT(two_above.x, 0.0f);
  EXPECT_EQ(gpu::sample_light(l, above, 0.4f, 0.3f).li, vec3(0.0f));
  gpu::GpuMaterial m{};
  m.emission = vec3(3.0f);
  gpu::ShadeTriangle t{};
  t.v0 = l.position;
  t.v1 = l.position + l.dir;
  t.v2 = l.position + l.edge2;
  EXPECT_EQ(gpu::emission_toward(m, t, vec3(0, 1, 0)), vec3(3.0f));  // two-sided: from below
  EXPECT_EQ(gpu::emission_toward(m, t, vec3(0, -1, 0)), vec3(3.0f));  // and from above
  m.flags = HRPP_MATERIAL_ONE_SIDED;
  EXPECT_EQ(gpu::emission_toward(m, t, vec3(0, 1, 0)), vec3(3.0f));   // a ray going up: front
  EXPECT_EQ(gpu::emission_toward(m, t, vec3(0, -1, 0)), vec3(0.0f));  // from above: its back
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
  // Roughness 1: the diffuse lobe; 0.5 and 0.3: the metal; 0.4: a dielectric's specular layer
  // (u_lobe 0 picks it).
  for (float roughness : {1.0f, 0.5f, 0.3f, 0.4f}) {
    gpu::GpuMaterial m{};
    m.base_color = vec3(1.0f);
    m.metallic = roughness < 1.0f && roughness != 0.4f ? 1.0f : 0.0f;
    m.roughness = roughness;
    m.specular_f0 = vec3(0.04f);
    m.specular_f90 = roughness == 0.4f ? 1.0f : 0.0f;
    const vec3 wo = glm::normalize(vec3(0.5f, 0.1f, 0.8f));
    const gpu::Lobe lobe = gpu::choose_lobe(m, m.base_color, wo.z, 0.0f);
    if (roughness == 0.4f) {
      ASSERT_EQ(lobe.kind, gpu::kLobeSpecular);
    }
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
