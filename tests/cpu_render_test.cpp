// host/cpu_render/: the CPU reference renderer against the wavefront renderer on the Vulkan
// device (lavapipe here, under the validation layer), pixel by pixel, on the suite's scenes and
// on a scene with every material lobe, light type and a texture; and `hrpp render --backend
// cpu`. Both run the shading code of shaders/shared/path_vertex.h; what may differ is the
// device's sin, cos and pow and its fused multiply-adds (last-bit differences), and the few path
// decisions such a bit can flip (a Russian-roulette or lobe choice, a ray grazing an edge). So the images agree to
// float rounding on nearly every pixel, and a change to a BSDF or light on one side only (a
// 1% albedo change in render_shade.comp alone, tried) fails on most pixels.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "cli_runner.h"
#include "common/error.h"
#include "cpu_render/cpu_renderer.h"
#include "cpu_render/scene_lookups.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"
#include "reference/embree_tracer.h"
#include "render/wavefront_renderer.h"
#include "scene/load_scene.h"
#include "test_scenes.h"

namespace hrpp {
namespace {

using V = glm::vec3;

using test::context;

struct BothImages {
  RenderResult device, cpu;
};

BothImages render_both(const Scene& scene, const RenderConfig& config) {
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene, BvhConfig{}), scene);
  BothImages r;
  r.device = WavefrontRenderer(context(), scene, bvh, config).render();
  r.cpu = CpuRenderer(scene, bvh, config).render();
  return r;
}

RenderConfig small(std::uint32_t size, std::uint32_t spp) {
  RenderConfig c;
  c.width = c.height = size;
  c.spp = spp;
  c.seed = 5;
  return c;
}

// Per pixel: every channel within kAbs + kRel × the larger value. Rounding differences stay
// orders of magnitude below this; a flipped path decision or a changed albedo does not.
constexpr double kAbs = 1e-5;
constexpr double kRel = 1e-4;

struct Agreement {
  double close = 0.0;     // fraction of pixels within the tolerance
  double mean_rel = 0.0;  // |mean(device) - mean(cpu)| / mean(cpu), all channels
};

Agreement compare(const std::vector<float>& device, const std::vector<float>& cpu) {
  std::size_t close = 0;
  double sum_d = 0.0, sum_c = 0.0;
  for (std::size_t p = 0; p < device.size(); p += 3) {
    bool ok = true;
    for (std::size_t c = p; c < p + 3; ++c) {
      const double a = device[c], b = cpu[c];
      ok = ok && std::abs(a - b) <= kAbs + kRel * std::max(std::abs(a), std::abs(b));
      sum_d += a;
      sum_c += b;
    }
    close += ok ? 1 : 0;
  }
  Agreement g;
  g.close = static_cast<double>(close) / static_cast<double>(device.size() / 3);
  g.mean_rel = sum_d == sum_c ? 0.0 : std::abs(sum_d - sum_c) / std::abs(sum_c);
  return g;
}

// At least 99% of the pixels agree to rounding, and the image means within 0.2%: room for a
// few flipped paths out of thousands, none for a change in what a path carries.
void expect_agreement(const BothImages& r, const std::string& what) {
  ASSERT_EQ(r.device.rgb.size(), r.cpu.rgb.size());
  const Agreement g = compare(r.device.rgb, r.cpu.rgb);
  std::printf("%s: %.2f%% of pixels within rounding, image means %.2g apart (relative)\n",
              what.c_str(), 100.0 * g.close, g.mean_rel);
  EXPECT_GE(g.close, 0.99) << what << ": pixels within rounding";
  EXPECT_LE(g.mean_rel, 2e-3) << what << ": image means";
  // The CPU traversal answers as the kernels do: the same camera rays.
  EXPECT_EQ(r.cpu.stats.camera_rays(), r.device.stats.camera_rays()) << what;
}

class CpuReferenceScenes : public testing::TestWithParam<std::string> {};

// The bare meshes have no light of their own: a sky (environment) and a sun (directional)
// light them, so their images are not black.
void light_if_dark(Scene& s) {
  if (!s.lights.empty()) return;
  Light sky;
  sky.type = LightType::kEnvironment;
  sky.color = V(0.3f, 0.35f, 0.4f);
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(V(0.3f, -1.0f, -0.5f));
  sun.color = V(2.0f, 1.9f, 1.7f);
  s.lights = {sky, sun};
}

TEST_P(CpuReferenceScenes, AgreesWithTheDevicePerPixel) {
  Scene scene = test::load_test_scene(GetParam());
  light_if_dark(scene);
  const BothImages r = render_both(scene, small(32, 4));
  expect_agreement(r, GetParam());
  EXPECT_EQ(context().validation_messages(), 0u);
}

INSTANTIATE_TEST_SUITE_P(TestScenes, CpuReferenceScenes,
                         testing::ValuesIn(test::reference_scene_names()), test::scene_param_name);

// builtin:cornell with vertex colours on every triangle (as glTF COLOR_0 gives them): the device
// multiplies them into the base colour as the CPU reference does, and they change the image.
TEST(CpuReference, VertexColoursAgreeWithTheDevice) {
  Scene scene = load_scene("builtin:cornell");
  for (std::size_t i = 0; i < scene.shading.size(); ++i) {
    TriangleShading& s = scene.shading[i];
    s.c0 = 0x0000FFu;  // 0xBBGGRR: red
    s.c1 = 0x00FF00u;
    s.c2 = static_cast<std::uint32_t>(0x102030u * (i % 5 + 1));
  }
  const BothImages r = render_both(scene, small(32, 4));
  expect_agreement(r, "cornell, vertex colours");
  EXPECT_NE(r.cpu.rgb, render_both(load_scene("builtin:cornell"), small(32, 4)).cpu.rgb);
  EXPECT_EQ(context().validation_messages(), 0u);
}

// builtin:cornell with every lobe, light type and a texture: the short block glass, the tall
// block a rough metal chosen with probability 0.7 (the rest diffuse) scaled by the checker as
// a metallic-roughness texture, the back wall a mirror, the green wall textured (4 × 4 sRGB
// checker) and emissive through the checker (no light: found by BSDF samples); a point light, a spot light, a directional
// light through the open front and a constant environment beside the ceiling's emitter.
Scene every_feature_cornell() {
  Scene s = load_scene("builtin:cornell");
  const auto add = [&](Material m) {
    s.materials.push_back(m);
    return static_cast<std::uint32_t>(s.materials.size() - 1);
  };
  Material glass;
  glass.transmission = 1.0f;
  glass.ior = 1.5f;
  glass.base_color = V(0.95f, 0.9f, 0.85f);
  Material metal;
  metal.metallic = 0.7f;
  metal.roughness = 0.35f;
  metal.base_color = V(0.9f, 0.7f, 0.5f);
  metal.metallic_roughness_texture = 0;  // the checker read as linear data
  Material mirror;
  mirror.metallic = 1.0f;
  mirror.roughness = 0.0f;
  Texture checker;
  checker.width = checker.height = 4;
  for (int i = 0; i < 16; ++i) {
    const bool dark = ((i % 4) + (i / 4)) % 2 == 1;
    for (std::uint8_t c : {std::uint8_t(dark ? 30 : 220), std::uint8_t(dark ? 90 : 200),
                           std::uint8_t(dark ? 20 : 60), std::uint8_t(255)})
      checker.rgba.push_back(c);
  }
  s.textures.push_back(checker);
  Material textured;
  textured.base_color_texture = 0;
  textured.emission = V(0.2f, 0.1f, 0.05f);
  textured.emissive_texture = 0;  // emits, but is no light
  const std::uint32_t ids[] = {add(glass), add(metal), add(mirror), add(textured)};
  // Triangles of builtin:cornell: back wall 6-7, green wall 10-11, short block 12-21, tall 22-31.
  for (std::size_t t = 12; t < 22; ++t) s.shading[t].material = ids[0];
  for (std::size_t t = 22; t < 32; ++t) s.shading[t].material = ids[1];
  for (std::size_t t : {6, 7}) s.shading[t].material = ids[2];
  for (std::size_t t : {10, 11}) s.shading[t].material = ids[3];
  Light point;
  point.type = LightType::kPoint;
  point.position = V(150.0f, 450.0f, 150.0f);
  point.color = V(3e4f, 4e4f, 5e4f);
  Light spot = point;
  spot.type = LightType::kSpot;
  spot.position = V(400.0f, 500.0f, 100.0f);
  spot.direction = V(-0.3f, -1.0f, 0.4f);
  spot.inner_cone = 0.3f;
  spot.outer_cone = 0.6f;
  Light sun;
  sun.type = LightType::kDirectional;
  sun.direction = V(0.2f, -0.3f, 1.0f);
  sun.color = V(0.8f);
  Light env;
  env.type = LightType::kEnvironment;
  env.color = V(0.05f, 0.07f, 0.1f);
  for (const Light& l : {point, spot, sun, env}) s.lights.push_back(l);
  return s;
}

TEST(CpuReference, AgreesWithTheDeviceOnEveryLobeLightAndTexture) {
  const Scene scene = every_feature_cornell();
  const BothImages r = render_both(scene, small(48, 4));
  expect_agreement(r, "every feature");
  // Every feature was compiled into the kernels, so every one was compared.
  EXPECT_EQ(r.device.stats.features.size(), 9u);
  EXPECT_EQ(context().validation_messages(), 0u);
}

// The light choice by cdf (scene_lookups.h; render_shade's pick_light): each light with the
// probability its cdf step gives, the boundaries to the light above, u just below 1 to the
// last, a zero-power light never.
TEST(CpuReference, PickLightFollowsTheCdf) {
  RenderScene rs;
  for (float cdf : {0.25f, 0.25f, 0.75f, 1.0f}) {
    gpu::GpuLight l{};
    l.cdf = cdf;
    rs.lights.push_back(l);
  }
  const struct {
    float u;
    std::uint32_t light;
    float prob;
  } cases[] = {{0.0f, 0, 0.25f},  {0.2499f, 0, 0.25f}, {0.25f, 2, 0.5f},
               {0.5f, 2, 0.5f},   {0.75f, 3, 0.25f},   {0.99999994f, 3, 0.25f}};
  for (const auto& c : cases) {
    float prob = -1.0f;
    EXPECT_EQ(pick_light(rs, c.u, prob), c.light) << "u " << c.u;
    EXPECT_EQ(prob, c.prob) << "u " << c.u;
  }
  rs.lights.resize(1);
  rs.lights[0].cdf = 1.0f;
  float prob = 0.0f;
  EXPECT_EQ(pick_light(rs, 0.7f, prob), 0u);
  EXPECT_EQ(prob, 1.0f);
}

// The same seed gives the same image however the work is split: the CPU reference is a pure
// function of the scene and configuration, as the device's image is.
TEST(CpuReference, SameSeedSameImageOtherSeedDiffers) {
  const Scene scene = load_scene("builtin:cornell");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene, BvhConfig{}), scene);
  RenderConfig c = small(24, 2);
  const RenderResult a = CpuRenderer(scene, bvh, c).render();
  const RenderResult b = CpuRenderer(scene, bvh, c).render();
  EXPECT_EQ(a.rgb, b.rgb);
  c.seed = 6;
  EXPECT_NE(CpuRenderer(scene, bvh, c).render().rgb, a.rgb);
  c.camera = 3;
  EXPECT_THROW(CpuRenderer(scene, bvh, c), Error);
}

// RMS of the per-value difference of two images.
double rms_difference(const std::vector<float>& a, const std::vector<float>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (double{a[i]} - b[i]) * (double{a[i]} - b[i]);
  return std::sqrt(s / static_cast<double>(a.size()));
}

// --cpu-tracer embree: Embree in place of the CPU traversal, an independent tracer, gives the
// scalar traversal's image up to its own rounding (far below the noise between two seeds); with
// HRPP in front of it in exact mode, the same image again (the prediction bounds Embree's
// search; a verified hit comes from the project's triangle test). Skipped without Embree.
TEST(CpuReference, EmbreeInPlaceOfTheTraversalRendersTheSameImage) {
  if (!embree_available()) GTEST_SKIP() << "this build has no Embree";
  const Scene scene = test::load_test_scene("meshes/mcguire_bunny.glb");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene, BvhConfig{}), scene);
  const EmbreeTracer embree(scene);
  OutsideTracer outside;
  outside.closest = [&](const gpu::Ray& r) { return embree.closest(r); };
  outside.occluded = [&](const gpu::Ray& r) { return embree.occluded(r); };
  RenderConfig c = small(64, 4);
  const std::vector<float> scalar = CpuRenderer(scene, bvh, c).render().rgb;
  const RenderResult off = CpuRenderer(scene, bvh, c, outside).render();
  c.predictor.enabled = true;
  c.predictor.mode = PredictorMode::kExact;
  const RenderResult on = CpuRenderer(scene, bvh, c, outside).render();
  c.predictor.enabled = false;
  c.seed = 9;
  const double floor = rms_difference(scalar, CpuRenderer(scene, bvh, c).render().rgb);
  const double embree_off = rms_difference(scalar, off.rgb);
  const double embree_on = rms_difference(off.rgb, on.rgb);
  std::printf("rms: embree / scalar %.3g, embree exact HRPP / embree %.3g; two seeds %.3g\n",
              embree_off, embree_on, floor);
  EXPECT_LT(embree_off, 0.01 * floor);
  EXPECT_LT(embree_on, 0.01 * floor);
  EXPECT_GT(on.stats.classes[RayClass::kCamera].predictor.c[HRPP_PC_TRUE_POSITIVES], 0u);
  EXPECT_EQ(off.stats.classes[RayClass::kCamera].counters.interior_visited, 0u);  // invisible
  OutsideTracer half;
  half.closest = outside.closest;
  EXPECT_THROW(CpuRenderer(scene, bvh, c, half), Error);
}

TEST(CpuReferenceCli, BackendFlag) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("hrpp_cpu_render_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string out = (dir / "c.exr").string(), stats = (dir / "c.json").string();
  test::CliResult r = test::run_hrpp(
      "render --backend cpu --size 16x16 --spp 1 --out " + out + " --stats " + stats, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_GT(std::filesystem::file_size(out), 0u);
  const nlohmann::json j = nlohmann::json::parse(test::read_file(stats));
  EXPECT_EQ(j["backend"], "cpu");
  EXPECT_EQ(j["rays"]["camera"].get<int>(), 16 * 16);

  // HRPP inline in the CPU renderer: the predicting classes' counters in the stats.
  r = test::run_hrpp("render --backend cpu --hrpp on --size 16x16 --spp 2 --out " + out +
                         " --stats " + stats, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("hrpp camera probes 512"), std::string::npos) << r.out;
  const nlohmann::json h = nlohmann::json::parse(test::read_file(stats));
  EXPECT_EQ(h["classes"]["camera"]["hrpp"]["probes"].get<int>(), 16 * 16 * 2);
  // --cpu-tracer embree (with HRPP in front), and --cpu-tracer without --backend cpu.
  if (embree_available()) {
    r = test::run_hrpp("render --backend cpu --cpu-tracer embree --hrpp on --size 16x16 --spp 1 "
                       "--out " + out + " --stats " + stats, dir);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(test::read_file(stats))["cpu_tracer"], "embree");
  }
  r = test::run_hrpp("render --cpu-tracer embree --size 8x8 --out " + (dir / "d.exr").string(),
                     dir);
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--cpu-tracer"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "d.exr"));
  r = test::run_hrpp("render --backend tpu --size 8x8 --out " + out, dir);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("--backend"), std::string::npos) << r.err;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hrpp
