// Progress of a long render on stderr. On a terminal, one line updated in place; in a log (a
// file, CI, a sweep: stderr not a terminal), one line each time another 5% of the samples is
// done and a final one, so at most 21 lines whatever --spp is. Quiet for a render's first second.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>

namespace hrpp {

class RenderProgress {
 public:
  static constexpr std::uint32_t kLogSteps = 20;  // lines in a log: every 100 / kLogSteps %
  static constexpr double kQuietSeconds = 1.0;

  RenderProgress(std::uint32_t total, bool terminal, std::FILE* out)
      : total_(total), terminal_(terminal), out_(out) {}

  // `done` of the total samples after `elapsed_s` seconds.
  void report(std::uint32_t done, double elapsed_s);
  std::uint32_t lines() const { return lines_; }

 private:
  std::uint32_t total_;
  bool terminal_;
  std::FILE* out_;
  bool shown_ = false;             // a line has been written
  std::uint32_t logged_step_ = 0;  // log: the last 5% step written
  std::uint32_t lines_ = 0;        // lines begun (a terminal's updates count once)
};

// The renderers' progress callback on stderr, timed from now; terminal or log by isatty.
std::function<void(std::uint32_t)> render_progress(std::uint32_t spp);

}  // namespace hrpp
