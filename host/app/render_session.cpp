// RenderSession: the render command's stops and saves between passes (render_session.h).
#include "app/render_session.h"

#include <cmath>
#include <utility>

#include "render/render_progress.h"

namespace hrpp::app {

RenderSession::RenderSession(std::uint32_t spp, RenderLimits limits,
                             std::function<void(const RenderResult&)> save)
    : progress_(render_progress(spp)), limits_(limits), save_(std::move(save)) {}

bool RenderSession::after_pass(std::uint32_t done, double elapsed_s,
                               const std::function<RenderResult()>& image) {
  elapsed_s_ = elapsed_s;
  progress_(done);
  if (predicted_end_ >= 0.0) {
    worst_prediction_s_ = std::max(worst_prediction_s_, std::fabs(elapsed_s - predicted_end_));
  }
  if (signal() != 0) return false;
  if (limits_.save_every_s > 0.0 && elapsed_s - last_save_s_ >= limits_.save_every_s) {
    save_(image());
    last_save_s_ = elapsed_s;
    ++saves_;
  }
  // The next pass is predicted to take the mean of the passes so far.
  predicted_end_ = elapsed_s + elapsed_s / done;
  if (limits_.time_limit_s > 0.0 && predicted_end_ > limits_.time_limit_s) {
    time_stop_ = true;
    return false;
  }
  return true;
}

std::string RenderSession::stopped_by() const {
  if (signal() != 0) return "signal";
  return time_stop_ ? "time limit" : "";
}

nlohmann::json RenderSession::json(std::uint32_t passes) const {
  nlohmann::json j = {{"passes", passes},
                      {"interrupted", signal() != 0},
                      {"stopped_by", stopped_by().empty() ? nullptr : nlohmann::json(stopped_by())},
                      {"passes_s", elapsed_s_},
                      {"saves", saves_}};
  if (signal() != 0) j["signal"] = signal();
  if (limits_.time_limit_s > 0.0) {
    j["time_limit_s"] = limits_.time_limit_s;
    j["worst_pass_end_prediction_s"] = worst_prediction_s_;
  }
  if (limits_.save_every_s > 0.0) j["save_every_s"] = limits_.save_every_s;
  return j;
}

}  // namespace hrpp::app
