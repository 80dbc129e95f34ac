// host/render/ + shaders/render_*.comp: the wavefront path tracer on the Vulkan device
// (lavapipe here), under the validation layer. Same seed → the same image bit for bit; furnace
// tests against radiance known in closed form; counters consistent with the image size and with
// each other; image files and CLI errors.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "common/error.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"
#include "render/image_output.h"
#include "render/render_stats.h"
#include "render/wavefront_renderer.h"
#include "scene/load_scene.h"

namespace hrpp {
namespace {

using test::context;

RenderResult render(const Scene& scene, RenderConfig config) {
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene, BvhConfig{}), scene);
  WavefrontRenderer renderer(context(), scene, bvh, config);
  return renderer.render();
}

RenderConfig small(std::uint32_t spp, std::uint32_t seed) {
  RenderConfig c;
  c.width = 32;
  c.height = 32;
  c.spp = spp;
  c.seed = seed;
  return c;
}

double mean(const std::vector<float>& rgb) {
  double s = 0.0;
  for (float v : rgb) s += v;
  return s / static_cast<double>(rgb.size());
}

// Standard error of the per-pixel means (channels averaged per pixel).
double standard_error(const std::vector<float>& rgb) {
  const std::size_t n = rgb.size() / 3;
  std::vector<double> px(n);
  for (std::size_t i = 0; i < n; ++i) px[i] = (rgb[3 * i] + rgb[3 * i + 1] + rgb[3 * i + 2]) / 3.0;
  double m = 0.0, v = 0.0;
  for (double p : px) m += p;
  m /= static_cast<double>(n);
  for (double p : px) v += (p - m) * (p - m);
  return std::sqrt(v / static_cast<double>(n - 1) / static_cast<double>(n));
}

void add_quad(Scene& s, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, std::uint32_t mat) {
  for (const auto& t : {Triangle{a, b, c}, Triangle{a, c, d}}) {
    s.triangles.push_back(t);
    TriangleShading sh;
    sh.material = mat;
    s.shading.push_back(sh);
  }
}

// A closed unit cube of material m, wound with its normals facing out.
Scene cube(const Material& m) {
  Scene s;
  s.materials.push_back(m);
  using V = glm::vec3;
  const V p[8] = {V(0, 0, 0), V(1, 0, 0), V(1, 1, 0), V(0, 1, 0),
                  V(0, 0, 1), V(1, 0, 1), V(1, 1, 1), V(0, 1, 1)};
  add_quad(s, p[0], p[1], p[2], p[3], 0);
  add_quad(s, p[4], p[7], p[6], p[5], 0);
  add_quad(s, p[0], p[3], p[7], p[4], 0);
  add_quad(s, p[1], p[5], p[6], p[2], 0);
  add_quad(s, p[0], p[4], p[5], p[1], 0);
  add_quad(s, p[3], p[2], p[6], p[7], 0);
  return s;
}

// The cube of one diffuse emissive material, the camera at its centre.
Scene emissive_box(float albedo, float emission) {
  Material m;
  m.base_color = glm::vec3(albedo);
  m.emission = glm::vec3(emission);
  Scene s = cube(m);
  s.name = "test:emissive-box";
  using V = glm::vec3;
  Camera cam;
  cam.position = V(0.5f, 0.5f, 0.5f);
  cam.forward = V(0, 0, 1);
  cam.up = V(0, 1, 0);
  cam.yfov = 1.5f;
  s.cameras.push_back(cam);
  return s;
}

TEST(Render, SameSeedSameImageBitForBit) {
  const Scene scene = load_scene("builtin:cornell");
  const RenderResult a = render(scene, small(2, 7));
  const RenderResult b = render(scene, small(2, 7));
  ASSERT_EQ(a.rgb.size(), 32u * 32u * 3u);
  EXPECT_TRUE(a.rgb == b.rgb) << "same seed gave a different image";
  // Wavefronts of 100 paths: other queue contents and orders, the same image.
  RenderConfig split = small(2, 7);
  split.wavefront_paths = 100;
  EXPECT_TRUE(a.rgb == render(scene, split).rgb) << "the wavefront size changed the image";
  const RenderResult c = render(scene, small(2, 8));
  EXPECT_FALSE(a.rgb == c.rgb) << "a different seed gave the same image";
  EXPECT_EQ(context().validation_messages(), 0u);
}

TEST(Render, CountersAreConsistent) {
  const Scene scene = load_scene("builtin:cornell");
  const RenderConfig config = small(3, 1);
  const RenderResult r = render(scene, config);
  const RenderStats& s = r.stats;
  EXPECT_EQ(s.camera_rays(), 32u * 32u * 3u);
  // Every continuation ray and every shadow ray leaves a surface that a camera or bounce ray
  // hit: at most one of each per hit.
  const std::uint64_t surface_hits =
      s.classes[RayClass::kCamera].counters.hits + s.classes[RayClass::kBounce].counters.hits;
  EXPECT_GT(s.bounce_rays(), 0u);
  EXPECT_LE(s.bounce_rays(), surface_hits);
  EXPECT_GT(s.shadow().counters.rays, 0u);
  EXPECT_LE(s.shadow().counters.rays, surface_hits);
  const RayClassStats closest_stats = s.closest();
  for (const RayClassStats* c : {&closest_stats, &s.shadow()}) {
    EXPECT_GE(c->counters.triangles_tested, c->counters.hits);
    EXPECT_GE(c->counters.leaves_visited, c->counters.hits);
    EXPECT_LE(c->counters.hits, c->counters.rays);
    EXPECT_GT(c->counters.interior_visited, 0u);
  }
  // The camera looks into the box: most camera and bounce rays hit; the open front lets some
  // escape.
  EXPECT_GT(s.closest().counters.hits, s.camera_rays() / 2);
  EXPECT_LT(s.closest().counters.hits, s.closest().counters.rays);
  EXPECT_EQ(s.features, std::vector<std::string>{"emissive_triangles"});
  for (Kernel k : {Kernel::render_generate, Kernel::trace_closest, Kernel::render_shade,
                   Kernel::trace_any, Kernel::render_accumulate})
    EXPECT_GT(s.kernels_ms.at(TimerLabel{k}), 0.0) << kernel_name(k);
  const nlohmann::json j = render_stats_json(scene.name, config, context().info(), r);
  EXPECT_EQ(j["closest"]["rays"].get<std::uint64_t>(), s.closest().counters.rays);
  EXPECT_EQ(j["totals"]["rays"].get<std::uint64_t>(),
            s.closest().counters.rays + s.shadow().counters.rays);
  EXPECT_EQ(j["config"]["spp"].get<int>(), 3);
  ASSERT_EQ(s.frames.size(), 3u);
  std::uint64_t closest = 0;
  for (const FrameStats& f : s.frames) {
    EXPECT_EQ(f.camera_rays(), 32u * 32u);
    closest += f.closest().counters.rays;
  }
  EXPECT_EQ(closest, s.closest().counters.rays);
  EXPECT_EQ(j["frames"].size(), 3u);
  // Nothing is negative or NaN, and the light is the brightest thing in the image: the
  // brightest pixel lies in the top third (the ceiling), sees at least the light's emission
  // (17, 12, 4: every sample of a pixel inside the light hits it) and has its colour order.
  for (float v : r.rgb) ASSERT_TRUE(v >= 0.0f && std::isfinite(v));
  std::size_t brightest = 0;
  for (std::size_t p = 0; p < r.rgb.size() / 3; ++p)
    if (r.rgb[3 * p] > r.rgb[3 * brightest]) brightest = p;
  const float* px = &r.rgb[3 * brightest];
  EXPECT_LT(brightest / config.width, config.height / 3) << "brightest pixel " << brightest;
  EXPECT_GE(px[0], 17.0f);
  EXPECT_GE(px[1], 12.0f);
  EXPECT_GE(px[2], 4.0f);
  EXPECT_GT(px[0], px[1]);
  EXPECT_GT(px[1], px[2]);
  EXPECT_EQ(context().validation_messages(), 0u);
}

// Inside a closed box whose walls emit E and reflect albedo a (diffuse), radiance with at most
// D surface interactions (the last one still samples a light, so light reaches the camera over
// up to D + 1 segments) is E (1 + a + ... + a^D) everywhere: exercises emission on camera
// hits, next-event estimation to emissive triangles, the diffuse lobe and Russian roulette;
// every wall is a light, so under MIS every bounce's emission is shared between the light
// sample and the BSDF sample that find it (each strategy alone gives the same mean).
TEST(Render, FurnaceClosedEmissiveBox) {
  const float a = 0.5f, e = 1.0f;
  for (const auto& [strategy, name] : kLightSamplingNames) {
    RenderConfig config = small(32, 3);
    config.max_depth = 5;
    config.light_sampling = strategy;
    const RenderResult r = render(emissive_box(a, e), config);
    double expected = 0.0;
    for (std::uint32_t k = 0; k <= config.max_depth; ++k) expected += e * std::pow(a, k);
    const double m = mean(r.rgb), se = standard_error(r.rgb);
    EXPECT_NEAR(m, expected, std::max(4.0 * se, 1e-3 * expected))
        << name << ": mean " << m << ", standard error " << se;
    EXPECT_LT(se, 0.015 * expected) << name;  // the test can see a 6% bias
    std::printf("furnace box, %s: mean %.4f expected %.4f standard error %.4f\n", name, m, expected,
                se);
    EXPECT_EQ(r.stats.closest().counters.hits, r.stats.closest().counters.rays);  // no misses
  }
}

// The Cornell box's mean radiance under MIS, light sampling alone and BSDF sampling alone: the
// same integral, so equal within the standard errors measured over independent seeds. A weight
// that counted emission twice or dropped a share would move one mean away from the others.
TEST(Render, LightSamplingStrategiesAgreeInTheMean) {
  const Scene scene = load_scene("builtin:cornell");
  constexpr int kSeeds = 8;
  double means[3], errors[3];
  for (const auto& [strategy, name] : kLightSamplingNames) {
    const auto k = static_cast<std::size_t>(strategy);
    double sum = 0.0, sum2 = 0.0;
    for (int seed = 0; seed < kSeeds; ++seed) {
      RenderConfig config = small(16, 100 + static_cast<std::uint32_t>(seed));
      config.light_sampling = strategy;
      const double m = mean(render(scene, config).rgb);
      sum += m;
      sum2 += m * m;
    }
    means[k] = sum / kSeeds;
    errors[k] = std::sqrt(std::max(0.0, sum2 / kSeeds - means[k] * means[k]) / (kSeeds - 1));
    std::printf("cornell %-5s mean %.5f standard error %.5f\n", name, means[k], errors[k]);
  }
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = i + 1; j < 3; ++j)
      EXPECT_NEAR(means[i], means[j], 4.0 * std::hypot(errors[i], errors[j]))
          << kLightSamplingNames[i].name << " against " << kLightSamplingNames[j].name;
  // MIS and light sampling are the tight estimates here (a small light): within 2%.
  EXPECT_LT(errors[0], 0.01 * means[0]);
}

// A white (albedo 1) open Cornell box without emitters inside a constant environment L: every
// path escapes eventually and carries exactly L (Russian roulette only adds noise).
TEST(Render, FurnaceWhiteBoxInEnvironment) {
  Scene scene = load_scene("builtin:cornell");
  for (Material& m : scene.materials) {
    m.base_color = glm::vec3(1.0f);
    m.emission = glm::vec3(0.0f);
  }
  scene.lights.clear();
  Light env;
  env.type = LightType::kEnvironment;
  env.color = glm::vec3(0.5f);
  scene.lights.push_back(env);
  RenderConfig config = small(16, 5);
  config.max_depth = 200;
  const RenderResult r = render(scene, config);
  const double m = mean(r.rgb), se = standard_error(r.rgb);
  EXPECT_NEAR(m, 0.5, std::max(4.0 * se, 1e-3)) << "mean " << m << ", standard error " << se;
  EXPECT_LT(se, 0.02);
  std::printf("furnace environment: mean %.4f expected 0.5 standard error %.4f\n", m, se);
  EXPECT_EQ(r.stats.features, std::vector<std::string>{"environment"});
  EXPECT_EQ(r.stats.shadow().counters.rays, 0u);  // no lights to sample
}

// A scene without lights (most glTF models) is lit by RenderConfig::default_lighting: a uniform
// environment L and a sun of irradiance E. A lightless diffuse plane of albedo a that fills the
// view then has radiance a L + (a / π) E cos θ exactly (every bounce escapes into the
// environment, nothing shadows the sun), the view away from it L; with both none, black.
TEST(Render, LightlessSceneGetsTheDefaultLighting) {
  Material grey;
  grey.base_color = glm::vec3(0.6f);
  Scene scene;
  scene.name = "test:lightless-plane";
  scene.materials.push_back(grey);
  add_quad(scene, {-50, -50, 0}, {50, -50, 0}, {50, 50, 0}, {-50, 50, 0}, 0);
  Camera cam;
  cam.position = {0, 0, 3};
  cam.forward = {0, 0, -1};
  cam.up = {0, 1, 0};
  cam.yfov = 1.0f;
  scene.cameras.push_back(cam);
  cam.forward = {0, 0, 1};
  scene.cameras.push_back(cam);
  const glm::vec3 env(0.5f, 1.0f, 2.0f);
  const float sun = 1.5f;
  const float cos_sun = -glm::normalize(DefaultLighting::kSunDirection).z;  // plane normal +z
  for (std::uint32_t camera : {0u, 1u}) {
    RenderConfig config = small(2, 3);
    config.camera = camera;
    config.default_lighting = {env, sun};
    const RenderResult r = render(scene, config);
    EXPECT_EQ(r.stats.lighting, Lighting::kDefault);
    EXPECT_EQ(r.stats.environment, env);
    EXPECT_EQ(r.stats.default_sun, sun);
    const glm::vec3 expected =
        camera == 0 ? 0.6f * env + glm::vec3(0.6f / 3.14159265f * sun * cos_sun) : env;
    for (std::size_t i = 0; i < r.rgb.size(); ++i)
      ASSERT_NEAR(r.rgb[i], expected[static_cast<int>(i % 3)], 1e-5f)
          << "camera " << camera << " value " << i;
  }
  RenderConfig dark = small(1, 3);
  dark.default_lighting = {glm::vec3(0.0f), 0.0f};
  const RenderResult black = render(scene, dark);
  EXPECT_EQ(black.stats.lighting, Lighting::kNone);
  EXPECT_EQ(*std::max_element(black.rgb.begin(), black.rgb.end()), 0.0f);
  EXPECT_NE(render_stats_text(dark, black).find("lighting    none"), std::string::npos);
  // A scene with a light of its own keeps it alone.
  Light point;
  point.position = {0, 0, 1};
  scene.lights.push_back(point);
  const RenderResult lit = render(scene, small(1, 3));
  EXPECT_EQ(lit.stats.lighting, Lighting::kScene);
  EXPECT_EQ(lit.stats.environment, glm::vec3(0.0f));
  EXPECT_EQ(render_stats_text(small(1, 3), lit).find("lighting"), std::string::npos);
}

// HRPP through the renderer: the predictor lives in the trace kernels, so render only passes its
// configuration on. In exact mode every closest hit equals the full traversal's and any-hit
// answers are exact, so the image is the one without HRPP, bit for bit; the per-class HRPP
// counters come back.
TEST(Render, HrppExactGivesTheSameImage) {
  const Scene scene = load_scene("builtin:cornell");
  RenderConfig config = small(2, 11);
  // Independent jitter: at 32x32 and 2 spp the Sobol pairs spread each pixel's camera rays
  // apart, and no probe finds an entry (6 predictor hits with independent samples).
  config.sampler = Sampler::kIndependent;
  const RenderResult off = render(scene, config);
  config.predictor.enabled = true;
  config.predictor.mode = PredictorMode::kExact;
  config.predictor.adaptive = false;  // every class probes every ray
  const RenderResult on = render(scene, config);
  EXPECT_TRUE(off.rgb == on.rgb) << "HRPP exact changed the image";
  EXPECT_EQ(on.stats.closest().counters.rays, off.stats.closest().counters.rays);
  EXPECT_EQ(on.stats.closest().predictor.c[HRPP_PC_PROBES], on.stats.closest().counters.rays);
  EXPECT_EQ(on.stats.shadow().predictor.c[HRPP_PC_PROBES], on.stats.shadow().counters.rays);
  EXPECT_GT(on.stats.closest().predictor.c[HRPP_PC_PREDICTOR_HITS], 0u);
  EXPECT_EQ(context().validation_messages(), 0u);
}

// A clear glass cube (ior 1.2: no direction is trapped by total internal reflection in a cube,
// since some direction cosine is always >= 1/sqrt(3) > cos(asin(1/1.2))) in a constant
// environment: reflection and refraction both carry weight 1, so every path returns L.
TEST(Render, FurnaceGlassCubeInEnvironment) {
  Material glass;
  glass.base_color = glm::vec3(1.0f);
  glass.transmission = 1.0f;
  glass.ior = 1.2f;
  Scene scene = cube(glass);
  scene.name = "test:glass-cube";
  Light env;
  env.type = LightType::kEnvironment;
  env.color = glm::vec3(0.5f);
  scene.lights.push_back(env);
  Camera cam;
  cam.position = glm::vec3(1.8f, 1.6f, 2.2f);
  cam.forward = glm::normalize(glm::vec3(0.5f) - cam.position);
  cam.up = glm::normalize(glm::cross(glm::cross(cam.forward, glm::vec3(0, 1, 0)), cam.forward));
  cam.yfov = 0.9f;
  scene.cameras.push_back(cam);
  RenderConfig config = small(8, 9);
  config.max_depth = 64;
  const RenderResult r = render(scene, config);
  const double m = mean(r.rgb), se = standard_error(r.rgb);
  EXPECT_NEAR(m, 0.5, std::max(4.0 * se, 1e-3)) << "mean " << m << ", standard error " << se;
  std::printf("furnace glass: mean %.4f expected 0.5 standard error %.4f\n", m, se);
  EXPECT_EQ(r.stats.features, (std::vector<std::string>{"environment", "glass"}));
  EXPECT_GT(r.stats.closest().counters.hits, r.stats.camera_rays() / 4);  // the cube fills the view
}

TEST(Render, BadConfigurationsAreErrors) {
  const Scene scene = load_scene("builtin:cornell");
  RenderConfig c = small(1, 0);
  c.camera = 5;
  EXPECT_THROW(render(scene, c), Error);
  c = small(0, 0);
  EXPECT_THROW(render(scene, c), Error);
  c = small(1, 0);
  c.max_depth = 0;
  EXPECT_THROW(render(scene, c), Error);
}

TEST(ImageOutput, WritesPngAndExrAndNoPartialFileOnError) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("hrpp_render_test_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::vector<float> rgb = {0.0f, 0.5f, 1.0f, 2.0f, -1.0f, 0.25f};
#ifdef HRPP_HAVE_OIIO
  write_image(dir / "a.png", 2, 1, rgb);
  EXPECT_GT(std::filesystem::file_size(dir / "a.png"), 0u);
  const std::size_t written = 2;
#else  // the portable build (HRPP_WITH_OIIO=OFF) writes .exr only
  EXPECT_THROW(write_image(dir / "a.png", 2, 1, rgb), Error);
  const std::size_t written = 1;
#endif
  write_image(dir / "a.exr", 2, 1, rgb);
  EXPECT_GT(std::filesystem::file_size(dir / "a.exr"), 0u);
  EXPECT_THROW(write_image(dir / "a.jpg", 2, 1, rgb), Error);
  EXPECT_THROW(write_image(dir / "missing" / "a.png", 2, 1, rgb), Error);
  EXPECT_THROW(write_image(dir / "b.png", 3, 1, rgb), Error);
  std::size_t files = 0;
  for (const auto& f : std::filesystem::directory_iterator(dir)) {
    (void)f;
    ++files;
  }
  EXPECT_EQ(files, written);
  EXPECT_FLOAT_EQ(linear_to_srgb(1.0f), 1.0f);
  EXPECT_FLOAT_EQ(linear_to_srgb(-1.0f), 0.0f);
  EXPECT_NEAR(linear_to_srgb(0.5f), 0.7354f, 1e-3);
  std::filesystem::remove_all(dir);
}

// The CLI: one-line errors with exit status 1 (CLI11's own parse errors exit non-zero too),
// and a small render that writes the image and the stats.
int run(const std::string& args, std::string* err = nullptr) {
  const std::filesystem::path e =
      std::filesystem::temp_directory_path() / ("hrpp_render_err_" + std::to_string(getpid()));
  const int status = std::system((std::string(HRPP_BINARY) + " " + args + " >/dev/null 2>" +
                                  e.string()).c_str());
  if (err) {
    std::ifstream in(e);
    std::getline(in, *err);
  }
  std::filesystem::remove(e);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(RenderCli, ErrorsAndOutputs) {
  std::string err;
  EXPECT_EQ(run("render --size 32y32", &err), 1);
  EXPECT_NE(err.find("--size"), std::string::npos) << err;
  EXPECT_EQ(run("render --size 0x4", &err), 1);
  EXPECT_EQ(run("render --size 8x8 --out x.jpg", &err), 1);
  EXPECT_NE(err.find("x.jpg"), std::string::npos) << err;
  EXPECT_EQ(run("render no-such-scene --size 8x8", &err), 1);
  EXPECT_EQ(run("render --spp 0", &err), 1);
  EXPECT_NE(err.find("--spp"), std::string::npos) << err;
  EXPECT_EQ(run("render --max-depth 0", &err), 1);
  EXPECT_NE(err.find("--max-depth"), std::string::npos) << err;
  EXPECT_NE(run("render --spp -3"), 0);  // CLI11: not a number of samples
  for (const char* flags : {"--default-environment 1,x", "--default-environment -1",
                            "--default-sun 1,2,3", "--default-sun nan", "--light-sampling nee",
                            "--sampler halton"}) {
    EXPECT_EQ(run(std::string("render --size 8x8 ") + flags, &err), 1) << flags;
    const std::string flag = std::string(flags).substr(0, std::string(flags).find(' '));
    EXPECT_NE(err.find(flag), std::string::npos) << flags << ": " << err;
  }

  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("hrpp_render_cli_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  ASSERT_EQ(run("render --size 16x16 --spp 1 --validate --bvh-bins 8 --bvh-max-leaf 2 --out " +
                (dir / "c.exr").string() +
                " --stats " + (dir / "c.json").string(), &err), 0) << err;
  std::ifstream in(dir / "c.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["rays"]["camera"].get<int>(), 16 * 16);
  EXPECT_TRUE(j.contains("kernels_ms") && j.contains("device") && j.contains("features"));
  EXPECT_GT(std::filesystem::file_size(dir / "c.exr"), 0u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hrpp
