// RenderProgress (host/render/render_progress.h): what a render writes to a log or a terminal.
#include "render/render_progress.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

namespace hrpp {
namespace {

// What `total` samples reported one by one, `seconds_each` apart, write.
std::string run(std::uint32_t total, bool terminal, double seconds_each, std::uint32_t* lines) {
  std::FILE* f = std::tmpfile();
  RenderProgress p(total, terminal, f);
  for (std::uint32_t done = 1; done <= total; ++done) p.report(done, done * seconds_each);
  *lines = p.lines();
  std::string text(static_cast<std::size_t>(std::ftell(f)), '\0');
  std::rewind(f);
  text.resize(std::fread(text.data(), 1, text.size(), f));
  std::fclose(f);
  return text;
}

std::size_t count(const std::string& s, char c) {
  return static_cast<std::size_t>(std::count(s.begin(), s.end(), c));
}

TEST(RenderProgress, ALogGetsAtMostTwentyOneLines) {
  std::uint32_t lines = 0;
  const std::string log = run(2000, false, 0.05, &lines);  // 100 s
  EXPECT_EQ(lines, RenderProgress::kLogSteps);
  EXPECT_EQ(count(log, '\n'), lines);
  EXPECT_EQ(count(log, '\r'), 0u);
  EXPECT_NE(log.find("render: 100/2000 spp (5%)"), std::string::npos) << log;
  EXPECT_NE(log.find("render: 2000/2000 spp (100%), 100.0 s\n"), std::string::npos) << log;
  // Few slow samples: a line each.
  EXPECT_EQ(count(run(3, false, 2.0, &lines), '\n'), 3u);
}

TEST(RenderProgress, QuietForTheFirstSecond) {
  std::uint32_t lines = 0;
  EXPECT_EQ(run(2000, false, 0.0004, &lines), "");  // 0.8 s in all
  EXPECT_EQ(lines, 0u);
  const std::string log = run(100, false, 0.02, &lines);  // 2 s: from 50 spp on
  EXPECT_EQ(log.find("render: 45/"), std::string::npos) << log;
  EXPECT_NE(log.find("render: 50/100"), std::string::npos) << log;
  EXPECT_NE(log.find("render: 100/100"), std::string::npos) << log;
}

TEST(RenderProgress, ATerminalGetsOneUpdatedLine) {
  std::uint32_t lines = 0;
  const std::string tty = run(2000, true, 0.05, &lines);
  EXPECT_EQ(lines, 1u);
  EXPECT_EQ(count(tty, '\n'), 1u);
  EXPECT_GT(count(tty, '\r'), 1000u);
  const std::string last = "\rrender: 2000/2000 spp, 100.0 s\n";
  ASSERT_GE(tty.size(), last.size());
  EXPECT_EQ(tty.substr(tty.size() - last.size()), last);
}

}  // namespace
}  // namespace hrpp
