// Ray reordering: host/trace/ray_order.h on the CPU, host/gpu/ray_sorter.h +
// shaders/ray_sort_*.comp on the Vulkan device (lavapipe here, under the validation layer).
// The key's edge cases; the GPU permutation equals the CPU's stable counting sort exactly (no
// ray lost, none duplicated, equal keys in queue order) at sizes around the block boundaries;
// hits traced in sorted order (through the order by the indexed kernels, or gathered and put
// back) equal the unsorted trace's bit for bit; a render with --reorder morton is the render
// without, bit for bit; bad --reorder values, and --reorder with HRPP predicting, are errors.
// The indexed kernels on their own: tests/indexed_trace_test.cpp.
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bvh/binned_sah_builder.h"
#include "bvh/gpu_layout.h"
#include "cli_runner.h"
#include "common/error.h"
#include "gpu/gpu_tracer.h"
#include "gpu/ray_sorter.h"
#include "vk/vulkan_context.h"
#include "gpu_test_context.h"
#include "ray_sort_interface.h"
#include "render/wavefront_renderer.h"
#include "scene/load_scene.h"
#include "trace/ray_order.h"

namespace hrpp {
namespace {

using test::context;

Aabb unit_box() {
  Aabb b;
  b.grow(glm::vec3(-1.0f, 0.0f, 2.0f));
  b.grow(glm::vec3(3.0f, 4.0f, 6.0f));
  return b;
}

gpu::Ray ray(glm::vec3 o, glm::vec3 d) { return {o, 0.0f, d, 1e30f}; }

// Origins around the box (some outside it), any direction, plus extreme floats: few distinct
// keys repeat often, so stability is tested.
std::vector<gpu::Ray> random_rays(std::size_t n, const Aabb& box, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> t(-0.2f, 1.2f), dir(-1.0f, 1.0f);
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float odd[] = {inf, -inf, nan, -0.0f, 0.0f, std::bit_cast<float>(1u), 1e30f, -1e30f};
  std::vector<gpu::Ray> rays(n);
  for (std::size_t i = 0; i < n; ++i) {
    glm::vec3 o = box.lo + glm::vec3(t(rng), t(rng), t(rng)) * box.extent();
    glm::vec3 d{dir(rng), dir(rng), dir(rng)};
    const int axis = static_cast<int>(i % 3);
    if (i % 97 == 0) o[axis] = odd[(i / 97) % 8];
    if (i % 89 == 0) d[(axis + 1) % 3] = odd[(i / 89) % 8];
    rays[i] = ray(o, d);
  }
  return rays;
}

TEST(RaySortKey, OctantAboveMortonCode) {
  const RaySortGrid g = ray_sort_grid(unit_box());
  const int cell_bits = HRPP_SORT_CELL_BITS;
  const std::uint32_t last = (1u << cell_bits) - 1;
  // The low corner, +++ direction: key 0; the high corner: every Morton bit.
  EXPECT_EQ(ray_sort_key(ray({-1, 0, 2}, {1, 1, 1}), g), 0u);
  EXPECT_EQ(ray_sort_key(ray({3, 4, 6}, {1, 1, 1}), g), (1u << (3 * cell_bits)) - 1);
  // x in cell 1 only: bit 0; y in cell 1 only: bit 1; z: bit 2.
  const float step = 4.0f / static_cast<float>(1u << cell_bits);
  EXPECT_EQ(ray_sort_key(ray({-1 + 1.5f * step, 0, 2}, {1, 1, 1}), g), 1u);
  EXPECT_EQ(ray_sort_key(ray({-1, 1.5f * step, 2}, {1, 1, 1}), g), 2u);
  EXPECT_EQ(ray_sort_key(ray({-1, 0, 2 + 1.5f * step}, {1, 1, 1}), g), 4u);
  // Direction signs are the top 3 bits; -0 counts as negative (the sign bit).
  EXPECT_EQ(ray_sort_key(ray({-1, 0, 2}, {-1, 1, 1}), g) >> (3 * cell_bits), 1u);
  EXPECT_EQ(ray_sort_key(ray({-1, 0, 2}, {1, -0.0f, 1}), g) >> (3 * cell_bits), 2u);
  EXPECT_EQ(ray_sort_key(ray({-1, 0, 2}, {1, 1, -1}), g) >> (3 * cell_bits), 4u);
  // Outside the bounds: clamped to the first or last cell; NaN and -inf: the first.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(ray_sort_key(ray({-100, -100, -100}, {1, 1, 1}), g), 0u);
  EXPECT_EQ(ray_sort_key(ray({nan, -inf, nan}, {1, 1, 1}), g), 0u);
  EXPECT_EQ(ray_sort_key(ray({inf, 1e30f, 100}, {1, 1, 1}), g), (1u << (3 * cell_bits)) - 1);
  EXPECT_LT(ray_sort_key(ray({1, 1, 1}, {nan, nan, nan}), g), 1u << HRPP_SORT_KEY_BITS);
  // A flat axis (extent 0): scale 0, every origin in cell 0 on it.
  Aabb flat;
  flat.grow(glm::vec3(0, 0, 5));
  flat.grow(glm::vec3(1, 1, 5));
  const RaySortGrid f = ray_sort_grid(flat);
  EXPECT_EQ(f.scale.z, 0.0f);
  EXPECT_EQ(ray_sort_key(ray({1, 1, 9}, {1, 1, 1}), f),
            ray_sort_key(ray({1, 1, -9}, {1, 1, 1}), f));
  EXPECT_EQ(ray_sort_key(ray({1, 1, 5}, {1, 1, 1}), f) & 4u, 0u);  // z's lowest Morton bit
  EXPECT_EQ(ray_sort_key(ray({1, 1, 5}, {1, 1, 1}), f) & 3u, 3u);  // x, y in the last cell
  EXPECT_EQ(last & 1u, 1u);
}

TEST(RaySortKey, CpuOrderIsAStableSortByKey) {
  const Aabb box = unit_box();
  const RaySortGrid g = ray_sort_grid(box);
  const std::vector<gpu::Ray> rays = random_rays(20000, box, 3);
  const std::vector<std::uint32_t> order = stable_ray_order(rays, g);
  ASSERT_EQ(order.size(), rays.size());
  std::vector<bool> seen(rays.size(), false);
  for (std::size_t j = 0; j < order.size(); ++j) {
    ASSERT_LT(order[j], rays.size());
    ASSERT_FALSE(seen[order[j]]) << "ray " << order[j] << " placed twice";
    seen[order[j]] = true;
    if (j == 0) continue;
    const std::uint32_t a = ray_sort_key(rays[order[j - 1]], g);
    const std::uint32_t b = ray_sort_key(rays[order[j]], g);
    ASSERT_LE(a, b) << "position " << j;
    if (a == b) {
      ASSERT_LT(order[j - 1], order[j]) << "equal keys out of queue order at " << j;
    }
  }
}

// The GPU sort against the CPU's at sizes around a block (64 items) and beyond 1024 blocks
// (blocks of more than 64 items); the sorted rays are the input's, moved bit for bit.
TEST(RaySortGpu, PermutationEqualsTheStableCpuSort) {
  const Aabb box = unit_box();
  const RaySortGrid g = ray_sort_grid(box);
  RaySorter sorter(context(), box, 100000);
  for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{63}, std::size_t{64},
                        std::size_t{65}, std::size_t{1000}, std::size_t{70001},
                        std::size_t{100000}}) {
    const std::vector<gpu::Ray> rays = random_rays(n, box, static_cast<std::uint32_t>(n));
    const RaySortResult r = sorter.sort(rays);
    ASSERT_EQ(r.order, stable_ray_order(rays, g)) << n << " rays";
    ASSERT_EQ(r.rays.size(), n);
    for (std::size_t j = 0; j < n; ++j)
      ASSERT_EQ(std::memcmp(&r.rays[j], &rays[r.order[j]], sizeof(gpu::Ray)), 0) << "ray " << j;
  }
  EXPECT_THROW(RaySorter(context(), box, (std::size_t{1} << 22) + 1), Error);
  EXPECT_EQ(context().validation_messages(), 0u);
}

// Each hit stays attached to its ray: rays bouncing around the Cornell box, traced through
// the sort's order (GpuTracer::trace with the sorter: no gather) or gathered, traced and put
// back, give the unsorted trace's hits bit for bit (closest and any hit); the order the trace
// read is the stable CPU order.
TEST(RaySortGpu, HitsStayWithTheirRays) {
  const Scene scene = load_scene("builtin:cornell");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene, BvhConfig{}), scene);
  GpuTracer tracer(context(), bvh);
  RaySorter sorter(context(), bvh.bounds, 50000);
  const std::vector<gpu::Ray> rays = random_rays(50000, bvh.bounds, 11);
  const std::vector<std::uint32_t> cpu_order = stable_ray_order(rays, ray_sort_grid(bvh.bounds));
  const RaySortResult sorted = sorter.sort(rays);
  for (QueryKind kind : kQueryKinds) {
    const GpuTraceResult plain = tracer.trace(rays, kind);
    const GpuTraceResult reordered = tracer.trace(sorted.rays, kind);
    const std::vector<gpu::Hit> back = hits_in_queue_order(reordered.hits, sorted.order);
    ASSERT_EQ(back.size(), plain.hits.size());
    EXPECT_EQ(std::memcmp(back.data(), plain.hits.data(), back.size() * sizeof(gpu::Hit)), 0);
    EXPECT_EQ(reordered.counters.hits, plain.counters.hits);
    EXPECT_GT(plain.counters.hits, 0u);

    const GpuTraceResult indexed = tracer.trace(rays, kind, &sorter);
    ASSERT_EQ(indexed.hits.size(), plain.hits.size());
    EXPECT_EQ(std::memcmp(indexed.hits.data(), plain.hits.data(),
                          plain.hits.size() * sizeof(gpu::Hit)), 0);
    EXPECT_EQ(indexed.counters.rays, rays.size());
    EXPECT_EQ(indexed.counters.hits, plain.counters.hits);
    EXPECT_GT(indexed.sort_ms, 0.0);
    EXPECT_GT(indexed.kernel_ms, indexed.sort_ms);
    EXPECT_EQ(plain.sort_ms, 0.0);
    EXPECT_EQ(sorter.order(static_cast<std::uint32_t>(rays.size())), cpu_order);
  }
  EXPECT_TRUE(tracer.trace(std::vector<gpu::Ray>{}, QueryKind::kClosest, &sorter).hits.empty());
  EXPECT_EQ(context().validation_messages(), 0u);
}

// Every path owns its random stream, so sorting the continuation rays with their paths changes
// the order of work only: the same image bit for bit, the same rays traced.
TEST(RaySortGpu, RenderIsTheSameImageWithReordering) {
  const Scene scene = load_scene("builtin:cornell");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene, BvhConfig{}), scene);
  RenderConfig config;
  config.width = 40;
  config.height = 30;
  config.spp = 2;
  config.seed = 5;
  config.wavefront_paths = 700;  // several wavefronts, the last one partial
  const RenderResult off = WavefrontRenderer(context(), scene, bvh, config).render();
  config.reorder = RayOrder::kMorton;
  const RenderResult on = WavefrontRenderer(context(), scene, bvh, config).render();
  EXPECT_TRUE(off.rgb == on.rgb) << "reordering changed the image";
  EXPECT_EQ(on.stats.bounce_rays(), off.stats.bounce_rays());
  EXPECT_GT(on.stats.bounce_rays(), 0u);
  EXPECT_EQ(on.stats.shadow().counters.rays, off.stats.shadow().counters.rays);
  EXPECT_GT(times_by_name(on.stats.kernels_ms).at("ray_sort"), 0.0);
  EXPECT_EQ(times_by_name(off.stats.kernels_ms).count("ray_sort"), 0u);
  EXPECT_EQ(context().validation_messages(), 0u);
}

class ReorderCli : public test::CliTest {
 protected:
  void write(const std::filesystem::path& p, const void* data, std::size_t bytes) {
    std::ofstream(p, std::ios::binary).write(static_cast<const char*>(data),
                                             static_cast<std::streamsize>(bytes));
  }
};

// hrpp trace --reorder morton writes the hits file of --reorder off, byte for byte.
TEST_F(ReorderCli, TraceWritesTheSameHitsFile) {
  const Scene scene = load_scene("builtin:cornell");
  const GpuBvh bvh = make_gpu_layout(build_bvh(scene, BvhConfig{}), scene);
  const std::vector<gpu::Ray> rays = random_rays(5000, bvh.bounds, 17);
  write(dir_ / "r.bin", rays.data(), rays.size() * sizeof(gpu::Ray));
  for (const char* any : {"", " --any-hit"}) {
    const std::string base = "trace builtin:cornell --rays " + (dir_ / "r.bin").string() + any;
    const test::CliResult off = run(base + " --hits " + (dir_ / "off.bin").string());
    ASSERT_EQ(off.status, 0) << off.err;
    const test::CliResult on = run(base + " --reorder morton --repeat 2 --hits " +
                                   (dir_ / "on.bin").string());
    ASSERT_EQ(on.status, 0) << on.err;
    EXPECT_NE(on.out.find("reorder     morton"), std::string::npos) << on.out;
    const std::string a = test::read_file(dir_ / "off.bin"), b = test::read_file(dir_ / "on.bin");
    EXPECT_EQ(a.size(), rays.size() * sizeof(gpu::Hit));
    EXPECT_TRUE(a == b) << "the hits file changed with --reorder morton" << any;
  }
}

// hrpp render --reorder morton: the stats name the order, time the sort and count the rays of
// the --reorder off render.
TEST_F(ReorderCli, RenderStatsNameTheOrderAndTimeTheSort) {
  const std::string base = "render builtin:cornell --size 24x16 --spp 1 --seed 4";
  const test::CliResult off = run(base + " --out " + (dir_ / "off.exr").string() + " --stats " +
                                  (dir_ / "off.json").string());
  ASSERT_EQ(off.status, 0) << off.err;
  const test::CliResult on = run(base + " --reorder morton --out " + (dir_ / "on.exr").string() +
                                 " --stats " + (dir_ / "on.json").string());
  ASSERT_EQ(on.status, 0) << on.err;
  const nlohmann::json a = nlohmann::json::parse(test::read_file(dir_ / "off.json"));
  const nlohmann::json b = nlohmann::json::parse(test::read_file(dir_ / "on.json"));
  EXPECT_EQ(a["config"]["reorder"], "off");
  EXPECT_EQ(b["config"]["reorder"], "morton");
  EXPECT_FALSE(a["kernels_ms"].contains("ray_sort"));
  EXPECT_GT(b["kernels_ms"]["ray_sort"].get<double>(), 0.0);
  EXPECT_EQ(a["rays"], b["rays"]);  // the same paths, bounce by bounce
}

// HRPP's predicted trace reads the rays in file order: --reorder with it is refused.
TEST_F(ReorderCli, ReorderWithHrppPredictingIsAnError) {
  const test::CliResult r = run("trace builtin:cornell --rays r.bin --hits " +
                                (dir_ / "h.bin").string() + " --reorder morton --hrpp on");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("--reorder"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "h.bin"));
}

TEST_F(ReorderCli, BadValueIsAnErrorNamingTheFlag) {
  for (const char* cmd : {"render builtin:cornell --size 8x8 --spp 1 --reorder sideways",
                          "trace builtin:cornell --rays r.bin --hits h.bin --reorder sideways"}) {
    const test::CliResult r = run(cmd);
    EXPECT_NE(r.status, 0) << cmd;
    EXPECT_NE(r.err.find("--reorder"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace hrpp
