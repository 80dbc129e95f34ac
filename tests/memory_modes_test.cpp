// --memory staged against --memory mapped on lavapipe (both work on any device), under the
// validation layer with synchronization validation: a staged buffer's upload, download and fill
// (several staging chunks, offsets) round-trip; `hrpp trace` writes the same hits file, `hrpp
// render` the same image (HRPP off and on), `hrpp bench` the same hits and counters, bit for
// bit; the outputs say which mode ran and where buffers live.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.h"
#include "error_of.h"
#include "vk/staged_transfer.h"
#include "vk/storage_buffer.h"
#include "vk/vulkan_context.h"
#include "scene/load_scene.h"
#include "trace/ray_batches.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;
using test::read_file;

VulkanContext& staged_context() {
  static auto* ctx = new VulkanContext(VulkanOptions{"", true, MemoryMode::kStaged});
  return *ctx;
}

TEST(MemoryModes, AStagedBufferRoundTrips) {
  VulkanContext& ctx = staged_context();
  ASSERT_EQ(ctx.info().memory_mode, MemoryMode::kStaged);
  ASSERT_NE(ctx.staging(), nullptr);
  // More than two staging chunks, at an offset that is not a multiple of 4.
  const std::size_t words = StagedTransfer::kChunkBytes / 2 + 1000;
  std::vector<std::uint32_t> data(words);
  std::iota(data.begin(), data.end(), 1u);
  StorageBuffer b(ctx, 5 * words * sizeof(std::uint32_t) / 2 + 3, "staged round trip");
  b.fill(0xDEADBEEFu);
  std::vector<std::uint32_t> filled(b.size() / 4);
  b.download(std::span<std::uint32_t>(filled));
  EXPECT_EQ(std::count(filled.begin(), filled.end(), 0xDEADBEEFu), filled.size());
  const std::size_t offset = 7;
  b.upload(data.data(), data.size() * sizeof(std::uint32_t), offset);
  std::vector<std::uint32_t> back(words);
  b.download(back.data(), back.size() * sizeof(std::uint32_t), offset);
  EXPECT_TRUE(back == data);
  std::uint8_t before[7];
  b.download(before, sizeof before);
  for (std::uint8_t v : before) EXPECT_TRUE(v == 0xEF || v == 0xBE || v == 0xAD || v == 0xDE);
  EXPECT_NE(test::error_of([&] { b.upload(data.data(), b.size() + 1); }).find("overruns"),
            std::string::npos);
  EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(MemoryModes, AStagedCopyInsideARecordingIsRefused) {
  VulkanContext& ctx = staged_context();
  StorageBuffer b(ctx, 64, "recorded upload");
  const std::uint32_t word = 1;
  const std::string e = test::error_of([&] {
    ctx.submit_and_wait([&](VkCommandBuffer) { b.upload(&word, sizeof word); }, "outer");
  });
  EXPECT_NE(e.find("being recorded"), std::string::npos) << e;
  b.upload(&word, sizeof word);  // the context still works
  EXPECT_EQ(ctx.validation_messages(), 0u);
}

TEST(MemoryModes, HostSharedBuffersAreMappedWhenStaged) {
  VulkanContext& ctx = staged_context();
  EXPECT_FALSE(ctx.info().device_memory.mapped);
  EXPECT_TRUE(ctx.info().host_shared_memory.mapped);
  const MemoryPlacement& p = ctx.memory().report().placement;
  EXPECT_EQ(p.mode, "staged");
  EXPECT_FALSE(p.roles.at("device").mapped);
  EXPECT_TRUE(p.roles.at("host_shared").mapped);
}

class MemoryModesCli : public test::CliTest {
 protected:
  // The mode's run of `args` (status 0 expected); its stdout.
  std::string run_in(const std::string& mode, const std::string& args) const {
    const test::CliResult r = run(args + " --memory " + mode);
    EXPECT_EQ(r.status, 0) << args << " --memory " << mode << "\n" << r.err;
    EXPECT_NE(r.out.find(mode + ": device buffers in type"), std::string::npos) << r.out;
    return r.out;
  }
};

TEST_F(MemoryModesCli, TraceWritesTheSameHits) {
  const Scene scene = load_scene(std::string(HRPP_TEST_SCENES_DIR) + "/teapot.scene.json");
  const std::vector<gpu::Ray> rays = make_primary_rays(scene.cameras[0], 64, 64, false, 1);
  const fs::path ray_file = dir_ / "rays.bin";
  std::ofstream(ray_file, std::ios::binary)
      .write(reinterpret_cast<const char*>(rays.data()),
             static_cast<std::streamsize>(rays.size() * sizeof(gpu::Ray)));
  for (const char* hrpp : {"off", "on"}) {
    std::string hits[2];
    const char* modes[2] = {"staged", "mapped"};
    for (int m = 0; m < 2; ++m) {
      const fs::path out = dir_ / (std::string(modes[m]) + hrpp + ".bin");
      const fs::path stats = dir_ / (std::string(modes[m]) + hrpp + ".json");
      run_in(modes[m], "trace " + std::string(HRPP_TEST_SCENES_DIR) + "/teapot.scene.json --rays " +
                           ray_file.string() + " --hits " + out.string() + " --stats " +
                           stats.string() + " --hrpp " + hrpp);
      hits[m] = read_file(out);
      const nlohmann::json j = nlohmann::json::parse(read_file(stats));
      EXPECT_EQ(j.at("memory").at("mode"), modes[m]);
      EXPECT_EQ(j.at("memory").at("placement").at("device").at("mapped"), m == 1);
    }
    ASSERT_EQ(hits[0].size(), rays.size() * 16) << hrpp;
    EXPECT_TRUE(hits[0] == hits[1]) << "--hrpp " << hrpp;
  }
}

// An EXR file's bytes with the values of its capDate attribute (the time OpenImageIO wrote it)
// and its hrpp:command_line attribute (--memory and --out differ; in these tests, not in length)
// blanked: the rest (the other attributes and every pixel) compares bit for bit.
std::string without_capture_date(std::string exr) {
  for (const std::string name : {"capDate", "hrpp:command_line"}) {
    const std::string attribute = name + std::string("\0string\0", 8);
    const std::size_t at = exr.find(attribute);
    if (at == std::string::npos || at + attribute.size() + 4 > exr.size()) continue;
    std::uint32_t length = 0;
    std::memcpy(&length, exr.data() + at + attribute.size(), sizeof length);
    const std::size_t value = at + attribute.size() + 4;
    if (value + length <= exr.size()) exr.replace(value, length, length, '-');
  }
  return exr;
}

TEST_F(MemoryModesCli, RenderWritesTheSameImage) {
  for (const char* hrpp : {"off", "on"}) {
    std::string images[2];
    const char* modes[2] = {"staged", "mapped"};
    for (int m = 0; m < 2; ++m) {
      const fs::path out = dir_ / (std::string(modes[m]) + hrpp + ".exr");
      run_in(modes[m], std::string("render builtin:cornell --size 32x24 --spp 3 --wavefront 300 "
                                   "--seed 5 --hrpp ") +
                           hrpp + " --out " + out.string());
      images[m] = without_capture_date(read_file(out));
    }
    ASSERT_FALSE(images[0].empty()) << hrpp;
    EXPECT_TRUE(images[0] == images[1]) << "--hrpp " << hrpp;
  }
}

// Staged, the staging buffer is host memory, not the device's heap: a capped heap refuses the
// scene by name as in mapped mode, not the staging buffer.
TEST_F(MemoryModesCli, AStagedSceneOverTheHeapIsRefusedByName) {
  ::setenv("HRPP_DEVICE_HEAP_MIB", "1", 1);
  const test::CliResult r =
      run("render builtin:cornell --size 512x512 --spp 1 --memory staged --out " +
          (dir_ / "i.exr").string());
  ::unsetenv("HRPP_DEVICE_HEAP_MIB");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("more than the device's memory heap as capped by HRPP_DEVICE_HEAP_MIB"),
            std::string::npos)
      << r.err;
}

// Every tracer's hit count, counters and check against the CPU reference, per ray kind.
nlohmann::json bench_hits(const nlohmann::json& report) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& kind : report.at("kinds"))
    for (const auto& t : kind.at("tracers"))
      out.push_back({kind.at("kind"), t.at("tracer"), t.at("hits"),
                     t.value("counters", nlohmann::json{}), t.at("validation")});
  return out;
}

TEST_F(MemoryModesCli, BenchFindsTheSameHits) {
  nlohmann::json hits[2];
  const char* modes[2] = {"staged", "mapped"};
  for (int m = 0; m < 2; ++m) {
    const fs::path json = dir_ / (std::string(modes[m]) + ".json");
    run_in(modes[m],
           "bench teapot --rays 2048 --no-embree --repeat 1 --hrpp on "
           "--check-rays 512 --json " +
               json.string());
    const nlohmann::json report = nlohmann::json::parse(read_file(json));
    EXPECT_EQ(report.at("machine").at("vulkan_memory_mode"), modes[m]);
    hits[m] = bench_hits(report);
  }
  ASSERT_GE(hits[0].size(), 3u);
  EXPECT_EQ(hits[0], hits[1]);
}

}  // namespace
}  // namespace hrpp
