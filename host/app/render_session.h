// The render command's pass observer (render/pass_observer.h): progress on stderr, a stop after
// the pass in flight on SIGINT or SIGTERM (common/interrupt.h) or before a pass that would end
// past --time-limit, and the image of the passes so far every --save-every seconds. While it
// lives the signal handlers are in force; the render writes its outputs inside it.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "common/interrupt.h"
#include "render/pass_observer.h"

namespace hrpp::app {

struct RenderLimits {
  double time_limit_s = 0.0;  // 0: none. Counted from the first pass: loading, the BVH build
                              // and the pipelines' compilation come before it and do not count
  double save_every_s = 0.0;  // 0: never
};

class RenderSession : public PassObserver {
 public:
  // `save` writes an image of the passes so far (--save-every).
  RenderSession(std::uint32_t spp, RenderLimits limits,
                std::function<void(const RenderResult&)> save);

  bool after_pass(std::uint32_t done, double elapsed_s,
                  const std::function<RenderResult()>& image) override;

  int signal() const { return interrupt_signal(); }
  // "signal", "time limit" or "" (all passes done).
  std::string stopped_by() const;
  // The stats' "session" object: passes, stop, the time limit and how far its predictions of
  // the next pass's end were off, the saves.
  nlohmann::json json(std::uint32_t passes) const;

 private:
  InterruptScope interrupts_;
  std::function<void(std::uint32_t)> progress_;
  RenderLimits limits_;
  std::function<void(const RenderResult&)> save_;
  bool time_stop_ = false;
  double predicted_end_ = -1.0;     // when the pass now running was predicted to end
  double worst_prediction_s_ = 0.0;  // the largest |actual - predicted| pass end
  double last_save_s_ = 0.0;
  std::uint32_t saves_ = 0;
  double elapsed_s_ = 0.0;
};

}  // namespace hrpp::app
