#include "render/render_progress.h"

#include <chrono>
#include <memory>

#include <unistd.h>

namespace hrpp {

void RenderProgress::report(std::uint32_t done, double elapsed_s) {
  if (!shown_ && elapsed_s < kQuietSeconds) return;
  const std::uint32_t total = total_ > 0 ? total_ : 1;
  if (terminal_) {
    if (!shown_) ++lines_;
    std::fprintf(out_, "\rrender: %u/%u spp, %.1f s", done, total_, elapsed_s);
    if (done >= total) std::fprintf(out_, "\n");
  } else {
    const auto step = static_cast<std::uint32_t>(std::uint64_t{done} * kLogSteps / total);
    if (step <= logged_step_) return;  // the final one is step kLogSteps
    logged_step_ = step;
    ++lines_;
    std::fprintf(out_, "render: %u/%u spp (%u%%), %.1f s\n", done, total_,
                 static_cast<unsigned>(std::uint64_t{done} * 100 / total), elapsed_s);
  }
  shown_ = true;
  std::fflush(out_);
}

std::function<void(std::uint32_t)> render_progress(std::uint32_t spp) {
  const auto start = std::chrono::steady_clock::now();
  auto progress = std::make_shared<RenderProgress>(spp, isatty(fileno(stderr)) != 0, stderr);
  return [start, progress](std::uint32_t done) {
    progress->report(
        done, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  };
}

}  // namespace hrpp
