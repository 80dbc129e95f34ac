// Many renders on one device: 8 `hrpp render` processes at once on the Vulkan device, each with
// its own seed and HRPP off (only HRPP off or exact mode is deterministic under load: the
// adaptive predictor decides from timings), each image equal bit for bit to the one the same
// command renders alone; and 2 `hrpp trace` processes writing one --hits path, which ends as one
// whole file equal to a lone run's. No process fails and no output is mixed.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_runner.h"
#include "exr_pixels.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;

class ConcurrentRendersTest : public test::CliTest {
 protected:
  std::string render_command(int seed, const std::string& name) const {
    return std::string(HRPP_BINARY) + " render builtin:cornell --size 32x32 --spp 4 --seed " +
           std::to_string(seed) + " --out " + (dir_ / (name + ".exr")).string();
  }
  // The image's pixels (exr_pixels.h), without the header's attributes.
  std::string pixels(const std::string& name) const {
    return test::exr_pixels(dir_ / (name + ".exr"), 32, 32);
  }
  // `commands` at once in the background; each one's exit status in status.K.
  test::CliResult run_at_once(const std::vector<std::string>& commands) const {
    std::string script;
    for (std::size_t k = 0; k < commands.size(); ++k)
      script += "(" + commands[k] + " >/dev/null 2>" +
                (dir_ / ("err." + std::to_string(k))).string() + "; echo $? > " +
                (dir_ / ("status." + std::to_string(k))).string() + ") & ";
    return test::run_command("sh -c '" + script + "wait'", dir_);
  }
  std::string status(std::size_t k) const {
    return test::read_file(dir_ / ("status." + std::to_string(k)));
  }
};

TEST_F(ConcurrentRendersTest, EightRendersAtOnceEqualTheirLoneImages) {
  constexpr int kRenders = 8;
  std::vector<std::string> commands;
  for (int k = 0; k < kRenders; ++k)
    commands.push_back(render_command(k + 1, "at_once" + std::to_string(k)));
  ASSERT_EQ(run_at_once(commands).status, 0);
  for (int k = 0; k < kRenders; ++k) {
    EXPECT_EQ(status(k), "0\n") << test::read_file(dir_ / ("err." + std::to_string(k)));
    const test::CliResult alone = test::run_command(render_command(k + 1, "alone"), dir_);
    ASSERT_EQ(alone.status, 0) << alone.err;
    ASSERT_FALSE(pixels("alone").empty());
    EXPECT_EQ(pixels("at_once" + std::to_string(k)), pixels("alone")) << "seed " << k + 1;
  }
  // Different seeds, different images: the comparison above can fail.
  EXPECT_NE(pixels("at_once0"), pixels("at_once1"));
}

TEST_F(ConcurrentRendersTest, TwoTracesWritingOneHitsFileLeaveOneWholeFile) {
  const fs::path rays = dir_ / "b";
  ASSERT_EQ(
      run("bench builtin:cornell --rays 16384 --no-embree --save-rays " + rays.string()).status, 0);
  const std::string trace = std::string(HRPP_BINARY) + " trace builtin:cornell --rays " +
                            (rays / "diffuse.rays").string() + " --hits ";
  ASSERT_EQ(test::run_command(trace + (dir_ / "alone.hits").string(), dir_).status, 0);
  const std::string shared = (dir_ / "shared.hits").string();
  ASSERT_EQ(run_at_once({trace + shared, trace + shared}).status, 0);
  EXPECT_EQ(status(0), "0\n") << test::read_file(dir_ / "err.0");
  EXPECT_EQ(status(1), "0\n") << test::read_file(dir_ / "err.1");
  EXPECT_EQ(test::read_file(shared), test::read_file(dir_ / "alone.hits"));
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
}

}  // namespace
}  // namespace hrpp
