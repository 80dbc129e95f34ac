// The lanes of a trace workgroup that take rays: every lane, or in serial mode (HRPP's
// deterministic runs: the CPU reference's node order) one lane per subgroup. Shared by the trace
// kernels' host side (host/gpu/gpu_tracer.h) and the HRPP stage's (host/front/gpu_predictor.h),
// whose dispatches must agree on it.
#pragma once

#include <algorithm>
#include <cstdint>

#include "trace_interface.h"

namespace hrpp {

constexpr std::uint32_t trace_lanes(bool serial, std::uint32_t subgroup_size) {
  return serial ? std::max(HRPP_TRACE_WORKGROUP_SIZE / std::max(subgroup_size, 1u), 1u)
                : HRPP_TRACE_WORKGROUP_SIZE;
}

}  // namespace hrpp
