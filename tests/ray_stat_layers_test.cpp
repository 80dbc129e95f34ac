// Per-pixel ray statistics (render/ray_stat_layers.h, `hrpp render --backend cpu --ray-stats`):
// each layer against a witness outside the layers' own bookkeeping:
//   - camera.interior at every pixel is what the CPU traversal visits tracing that pixel's
//     camera rays itself (gpu::camera_ray), and camera.rays is one a sample;
//   - with exact HRPP and count_baseline, camera.interior + camera.skipped at every pixel is
//     the HRPP-off render's camera.interior (what a full traversal of the same rays visits);
//   - camera.verified summed over the pixels is the render's true positives;
//   - the CLI writes the layers into the EXR under their names (read back by OpenImageIO) and
//     refuses the flag with the GPU backend or a PNG.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "cli_runner.h"
#include "cpu_render/cpu_renderer.h"
#include "path_vertex.h"
#include "render/ray_stat_layers.h"
#include "render/render_params.h"
#include "render/render_scene.h"
#include "test_scenes.h"
#include "trace/cpu_traversal.h"

namespace hrpp {
namespace {

struct Rendered {
  RenderResult result;
  std::map<std::string, std::vector<float>> layers;
};

RenderConfig small_config(std::uint32_t width = 24, std::uint32_t height = 16,
                          std::uint32_t spp = 3) {
  RenderConfig c;
  c.width = width;
  c.height = height;
  c.spp = spp;
  c.seed = 4;
  c.ray_stats = true;
  return c;
}

Rendered render(const Scene& scene, const GpuBvh& bvh, const RenderConfig& c) {
  Rendered r{CpuRenderer(scene, bvh, c).render(), {}};
  for (const ImageChannel& ch : r.result.channels) r.layers[ch.name] = ch.values;
  return r;
}

class RayStatLayersTest : public testing::Test {
 protected:
  Scene scene = test::load_test_scene("meshes/mcguire_bunny.glb");
  GpuBvh bvh = make_gpu_layout(build_bvh(scene, BvhConfig{}), scene);
};

TEST_F(RayStatLayersTest, CameraInteriorIsThePixelsOwnTraversal) {
  const RenderConfig c = small_config();
  const Rendered r = render(scene, bvh, c);
  ASSERT_EQ(r.layers.count("camera.interior"), 1u);
  EXPECT_EQ(r.layers.count("camera.verified"), 0u);  // HRPP off: no predictor layers
  const RenderScene rs = make_render_scene(scene, c.default_lighting);
  const gpu::RenderParams params = make_render_params(c, scene.cameras[c.camera], rs, 0);
  double visited = 0.0;
  for (std::uint32_t p = 0; p < c.width * c.height; ++p) {
    TraversalCounters counters;
    for (std::uint32_t s = 0; s < c.spp; ++s)
      trace_closest(bvh, gpu::camera_ray(params, p, s), &counters);
    const float expected =
        static_cast<float>(static_cast<double>(counters.interior_visited) / c.spp);
    ASSERT_EQ(r.layers.at("camera.interior")[p], expected) << "pixel " << p;
    ASSERT_EQ(r.layers.at("camera.rays")[p], 1.0f) << "pixel " << p;
    visited += static_cast<double>(counters.interior_visited);
  }
  EXPECT_GT(visited, 0.0);
  EXPECT_EQ(r.result.stats.classes[RayClass::kCamera].counters.interior_visited,
            static_cast<std::uint64_t>(visited));
}

TEST_F(RayStatLayersTest, SkippedIsTheFullTraversalMinusThePredictedWork) {
  RenderConfig c = small_config(64, 48, 4);  // enough neighbouring rays to share keys
  const Rendered off = render(scene, bvh, c);
  c.predictor.enabled = true;
  c.predictor.mode = PredictorMode::kExact;
  c.predictor.adaptive = false;
  c.predictor.count_baseline = true;
  const Rendered on = render(scene, bvh, c);
  for (const char* name : {"camera.predicted", "camera.verified", "camera.skipped",
                           "bounce.skipped", "shadow.verified"})
    ASSERT_EQ(on.layers.count(name), 1u) << name;
  const std::vector<float>& skipped = on.layers.at("camera.skipped");
  double verified = 0.0, saved = 0.0;
  for (std::size_t p = 0; p < skipped.size(); ++p) {
    const double full = off.layers.at("camera.interior")[p];
    EXPECT_NEAR(on.layers.at("camera.interior")[p] + skipped[p], full, 1e-4 * (1.0 + full))
        << "pixel " << p;
    EXPECT_LE(on.layers.at("camera.verified")[p], on.layers.at("camera.predicted")[p]);
    verified += on.layers.at("camera.verified")[p] * static_cast<double>(c.spp);
    saved += skipped[p];
  }
  const auto& camera = on.result.stats.classes[RayClass::kCamera].predictor;
  EXPECT_GT(camera.c[HRPP_PC_TRUE_POSITIVES], 0u);
  EXPECT_NEAR(verified, static_cast<double>(camera.c[HRPP_PC_TRUE_POSITIVES]), 1e-3 * verified);
  EXPECT_NE(saved, 0.0);
}

// The layers through the CLI into the file: every channel name, in an image that still holds its
// R, G and B.
TEST(RayStatLayersCli, LayersInTheExrAndRefusals) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("hrpp_ray_stats_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string out = (dir / "s.exr").string();
  test::CliResult r = test::run_hrpp(
      "render --backend cpu --ray-stats --hrpp on --size 12x8 --spp 1 --out " + out, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(out);
  ASSERT_TRUE(in) << OIIO::geterror();
  std::vector<std::string> names;
  for (int i = 0; i < in->spec().nchannels; ++i) names.push_back(in->spec().channel_name(i));
  in->close();
  for (const char* name : {"R", "G", "B", "camera.rays", "camera.interior", "camera.predicted",
                           "camera.verified", "bounce.rays", "shadow.interior"})
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  EXPECT_EQ(std::find(names.begin(), names.end(), "camera.skipped"), names.end());

  for (const std::string& bad :
       {std::string("render --ray-stats --size 8x8 --out ") + out,
        "render --backend cpu --ray-stats --size 8x8 --out " + (dir / "s.png").string()}) {
    r = test::run_hrpp(bad, dir);
    EXPECT_EQ(r.status, 1) << bad;
    EXPECT_NE(r.err.find("--ray-stats"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "s.png"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hrpp
