// The process's peak resident memory (getrusage's ru_maxrss): what the render stats report as
// the host's peak beside the device buffers (on lavapipe the device's memory is host memory, so
// it is counted in both).
#pragma once

#include <cstdint>

namespace hrpp {

std::uint64_t peak_rss_bytes();

}  // namespace hrpp
