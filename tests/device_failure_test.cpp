// A render the device fails mid-way (VK_ERROR_DEVICE_LOST, VK_ERROR_OUT_OF_DEVICE_MEMORY) keeps
// the passes the host holds: one line naming the error, exit status 1, the image of the kept
// passes written whole and equal bit for bit to a render of that many passes, stats that say the
// render failed and why. Lavapipe neither loses its device nor runs out of memory on cue, so the
// failure comes from the test hook HRPP_TEST_FAIL_SUBMIT (host/vk/vulkan_context.cpp): the
// N-th "render bounce" submit gets the error in place of vkQueueSubmit's result.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"
#include "exr_pixels.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;

class DeviceFailureTest : public test::CliTest {
 protected:
  // hrpp render of the Cornell box, 32x32, at most 2 bounces, with `env` before the command.
  test::CliResult render(const std::string& env, std::uint32_t spp, const std::string& name) const {
    return test::run_command(env + " " + HRPP_BINARY +
                                 " render builtin:cornell --size 32x32 --max-depth 2 --seed 3 "
                                 "--spp " +
                                 std::to_string(spp) + " --out " +
                                 (dir_ / (name + ".exr")).string() + " --stats " +
                                 (dir_ / (name + ".json")).string(),
                             dir_);
  }

  // The image's pixels (exr_pixels.h), without the header's attributes.
  std::string pixels(const std::string& name) const {
    return test::exr_pixels(dir_ / (name + ".exr"), 32, 32);
  }

  void fails_keeping_passes(const char* kind, const char* vk_error) {
    const std::string env = std::string("HRPP_TEST_FAIL_SUBMIT='render bounce:10:") + kind + "'";
    const test::CliResult r = render(env, 64, "failed");
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find(vk_error), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("holds the mean of the"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    const nlohmann::json s = nlohmann::json::parse(test::read_file(dir_ / "failed.json"));
    const nlohmann::json& session = s.at("session");
    EXPECT_TRUE(session.at("failed").get<bool>());
    EXPECT_EQ(session.at("stopped_by"), "device failure");
    EXPECT_NE(session.at("error").get<std::string>().find(vk_error), std::string::npos);
    const auto kept = session.at("passes").get<std::uint32_t>();
    const auto before = session.at("passes_before_failure").get<std::uint32_t>();
    EXPECT_GE(kept, 1u);  // the first pass is always kept
    EXPECT_LE(kept, before);
    EXPECT_LT(before, 64u);
    EXPECT_EQ(s.at("frames").size(), kept);
    for (const auto& e : fs::directory_iterator(dir_))
      EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
    // The witness: the same render of `kept` passes, run to its end.
    const test::CliResult whole = render("", kept, "whole");
    ASSERT_EQ(whole.status, 0) << whole.err;
    ASSERT_FALSE(pixels("failed").empty());
    EXPECT_EQ(pixels("failed"), pixels("whole"));
  }
};

TEST_F(DeviceFailureTest, ALostDeviceKeepsThePassesTheHostHolds) {
  fails_keeping_passes("lost", "VK_ERROR_DEVICE_LOST");
}

TEST_F(DeviceFailureTest, OutOfDeviceMemoryKeepsThePassesTheHostHolds) {
  fails_keeping_passes("memory", "VK_ERROR_OUT_OF_DEVICE_MEMORY");
}

TEST_F(DeviceFailureTest, AMalformedHookIsRefused) {
  const test::CliResult r = render("HRPP_TEST_FAIL_SUBMIT='render bounce:x:lost'", 1, "bad");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("HRPP_TEST_FAIL_SUBMIT"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace hrpp
