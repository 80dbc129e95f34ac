// Runs the hrpp binary as a user would, for the CLI suites (tests/cli_test.cpp,
// tests/hrpp_cli_test.cpp): exit status, stdout and stderr, through files in a test's directory.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

namespace hrpp::test {

struct CliResult {
  int status = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// A shell command line with stdin from /dev/null; stdout and stderr go through files in `dir`.
inline CliResult run_command(const std::string& command_line, const std::filesystem::path& dir) {
  const std::filesystem::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd = command_line + " >" + out.string() + " 2>" + err.string() + " </dev/null";
  const int raw = std::system(cmd.c_str());
  CliResult r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  r.out = read_file(out);
  r.err = read_file(err);
  return r;
}

// `hrpp ARGS`, as run_command.
inline CliResult run_hrpp(const std::string& args, const std::filesystem::path& dir) {
  return run_command(std::string(HRPP_BINARY) + " " + args, dir);
}

// A fixture with a fresh directory per test (removed afterwards) and run() for hrpp commands.
class CliTest : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("hrpp_cli_test_" + std::to_string(::getpid()) + "_" +
            testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  CliResult run(const std::string& args) const { return run_hrpp(args, dir_); }

  std::filesystem::path dir_;
};

}  // namespace hrpp::test
