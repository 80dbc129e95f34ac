// What a timed dispatch is booked under: the kernel (shaders/CMakeLists.txt's list), the ray
// class it traced or predicted for (none for the renderer's own kernels) and the phase (a frame's
// work, or the adaptive predictor's sample). KernelTimer (vk/compute_pipeline.h) sums device
// time per label; the render stats keep it per label without the class, per class; the adaptive
// predictor reads it by field (add_kernel_times).
#pragma once

#include <compare>
#include <cstdint>
#include <optional>
#include <string>

#include "trace/ray_class.h"
#include "kernel_names.h"

namespace hrpp {

enum class Phase : std::uint8_t {
  kRun,          // the frame's (or the trace's) own work
  kSample,       // the adaptive predictor's sample pass (GpuPredictor::record_sample)
  kSampleEmpty,  // its hrpp_predict dispatch over no ray: the fixed cost of a dispatch
};

struct TimerLabel {
  TimerLabel(Kernel k, Phase p = Phase::kRun, std::optional<RayClass> c = std::nullopt)
      : kernel(k), phase(p), ray_class(c) {}

  Kernel kernel;
  Phase phase;
  std::optional<RayClass> ray_class;

  auto operator<=>(const TimerLabel&) const = default;
  TimerLabel without_class() const { return {kernel, phase, std::nullopt}; }
};

// The ray sorter's kernels (gpu/ray_sorter.h), reported together as "ray_sort".
constexpr bool is_ray_sort(Kernel k) {
  return k == Kernel::ray_sort_keys || k == Kernel::ray_sort_count || k == Kernel::ray_sort_scan ||
         k == Kernel::ray_sort_scatter || k == Kernel::ray_sort_gather;
}

// The label's name in reports (stats JSON, terminal): the kernel ("ray_sort" for the sort's),
// "sample_<kernel>" for a sample's dispatches, "sample_hrpp_empty" for the empty one; the ray
// class is not part of it.
inline std::string label_name(const TimerLabel& l) {
  const std::string kernel = is_ray_sort(l.kernel) ? "ray_sort" : kernel_name(l.kernel);
  switch (l.phase) {
    case Phase::kSample:
      return "sample_" + kernel;
    case Phase::kSampleEmpty:
      return "sample_hrpp_empty";
    case Phase::kRun:
      break;
  }
  return kernel;
}

}  // namespace hrpp
