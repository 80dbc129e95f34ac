// What a render does between its sample passes (both renderers): report progress, stop early
// (a signal, a time limit), save the image so far. Without one a render runs all its passes.
#pragma once

#include <cstdint>
#include <functional>

#include "render/render_result.h"

namespace hrpp {

class PassObserver {
 public:
  virtual ~PassObserver() = default;
  // After pass `done` (from 1), `elapsed_s` seconds after the first pass began; `image()` makes
  // the mean image of the passes so far (a download on the device). false: stop after `done`.
  virtual bool after_pass(std::uint32_t done, double elapsed_s,
                          const std::function<RenderResult()>& image) = 0;
};

}  // namespace hrpp
