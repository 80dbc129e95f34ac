// A render stopped on purpose keeps its work (common/interrupt.h, app/render_session.h): real
// signals to a real hrpp process. SIGINT or SIGTERM after the render began: exit 130 or 143, the
// image of the completed passes and stats that say so, no temporary left; a second signal ends
// at once; --time-limit stops before a pass that would end past it; two processes writing one
// --out leave one whole file. The CPU backend renders, so no Vulkan device is needed.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "cli_runner.h"

namespace hrpp {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

class InterruptTest : public test::CliTest {
 protected:
  // hrpp render ARGS in a child process (stdout and stderr to files in the test's folder).
  pid_t start(const std::vector<std::string>& args) const {
    std::vector<std::string> argv = {HRPP_BINARY, "render", "builtin:cornell", "--backend", "cpu",
                                     "--size",    "16x16"};
    argv.insert(argv.end(), args.begin(), args.end());
    const std::string out = (dir_ / "stdout.txt").string(), err = (dir_ / "stderr.txt").string();
    const pid_t pid = ::fork();
    if (pid == 0) {
      if (!std::freopen(out.c_str(), "w", stdout) || !std::freopen(err.c_str(), "w", stderr))
        ::_exit(99);
      std::vector<char*> c;
      for (std::string& a : argv) c.push_back(a.data());
      c.push_back(nullptr);
      ::execv(c[0], c.data());
      ::_exit(98);
    }
    return pid;
  }

  // The child's exit status (128 + signal when a signal ended it), waiting at most 120 s.
  static int wait_for(pid_t pid) {
    const auto end = Clock::now() + std::chrono::seconds(120);
    int raw = 0;
    while (::waitpid(pid, &raw, WNOHANG) == 0) {
      if (Clock::now() > end) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &raw, 0);
        return -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  }

  // Waits (at most 120 s) until `file` exists: the render is past its first pass.
  static bool appears(const fs::path& file) {
    const auto end = Clock::now() + std::chrono::seconds(120);
    while (!fs::exists(file)) {
      if (Clock::now() > end) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
  }

  void expect_no_temporaries() const {
    for (const auto& e : fs::directory_iterator(dir_)) {
      EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
    }
  }

  nlohmann::json stats() const { return nlohmann::json::parse(test::read_file(dir_ / "s.json")); }

  // The EXR's hrpp:samples string attribute (name, "string", 4-byte size, value).
  static std::string exr_samples(const fs::path& exr) {
    const std::string b = test::read_file(exr);
    const std::string key = std::string("hrpp:samples") + '\0' + "string" + '\0';
    const std::size_t at = b.find(key);
    if (at == std::string::npos || at + key.size() + 4 > b.size()) return "";
    std::uint32_t n = 0;
    std::memcpy(&n, b.data() + at + key.size(), 4);
    return b.substr(at + key.size() + 4, n);
  }

  void interrupt_with(int sig, int expected_status) {
    const fs::path exr = dir_ / "r.exr";
    const pid_t pid = start({"--spp", "1000000", "--out", exr.string(), "--stats",
                             (dir_ / "s.json").string(), "--save-every", "0.05"});
    ASSERT_TRUE(appears(exr)) << "no image saved by --save-every";
    ::kill(pid, sig);
    EXPECT_EQ(wait_for(pid), expected_status) << test::read_file(dir_ / "stderr.txt");
    const nlohmann::json s = stats();
    const auto passes = s["session"]["passes"].get<std::size_t>();
    EXPECT_TRUE(s["session"]["interrupted"].get<bool>());
    EXPECT_EQ(s["session"]["stopped_by"], "signal");
    EXPECT_EQ(s["session"]["signal"], sig);
    EXPECT_GE(passes, 1u);
    EXPECT_LT(passes, 1000000u);
    EXPECT_EQ(s["frames"].size(), passes);
    EXPECT_EQ(exr_samples(exr), std::to_string(passes));  // the final write, not a save
    expect_no_temporaries();
  }
};

TEST_F(InterruptTest, SigintKeepsTheCompletedPasses) { interrupt_with(SIGINT, 130); }

TEST_F(InterruptTest, SigtermKeepsTheCompletedPasses) { interrupt_with(SIGTERM, 143); }

TEST_F(InterruptTest, ASecondSignalEndsAtOnceLeavingNoTemporary) {
  const fs::path exr = dir_ / "r.exr";
  const pid_t pid = start({"--spp", "1000000", "--out", exr.string(), "--save-every", "0.01"});
  ASSERT_TRUE(appears(exr));
  ::kill(pid, SIGINT);
  ::kill(pid, SIGINT);
  EXPECT_EQ(wait_for(pid), 130);
  expect_no_temporaries();
  EXPECT_FALSE(exr_samples(exr).empty());  // a save or the final image, whole either way
}

TEST_F(InterruptTest, TimeLimitStopsBeforeAPassWouldEndPastIt) {
  const auto t0 = Clock::now();
  const pid_t pid = start({"--spp", "1000000", "--out", (dir_ / "r.exr").string(), "--stats",
                           (dir_ / "s.json").string(), "--time-limit", "1"});
  EXPECT_EQ(wait_for(pid), 0) << test::read_file(dir_ / "stderr.txt");
  const nlohmann::json s = stats();
  EXPECT_EQ(s["session"]["stopped_by"], "time limit");
  EXPECT_FALSE(s["session"]["interrupted"].get<bool>());
  // Within the limit plus one pass (a generous bound here: the machine may be busy).
  const double passes_s = s["session"]["passes_s"].get<double>();
  const double pass = passes_s / s["session"]["passes"].get<double>();
  EXPECT_LE(passes_s, 1.0 + 3.0 * pass + 0.5);
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - t0).count(), 60.0);
}

TEST_F(InterruptTest, TwoWritersOfOneOutputLeaveOneWholeFile) {
  const fs::path exr = dir_ / "r.exr";
  const pid_t a = start({"--spp", "64", "--seed", "1", "--out", exr.string()});
  const pid_t b = start({"--spp", "64", "--seed", "2", "--out", exr.string()});
  EXPECT_EQ(wait_for(a), 0);
  EXPECT_EQ(wait_for(b), 0);
  EXPECT_EQ(exr_samples(exr), "64");
  expect_no_temporaries();
}

}  // namespace
}  // namespace hrpp
