// SPIR-V of the compute kernels, compiled from shaders/*.comp at build time and embedded in the
// binary (shaders/CMakeLists.txt), so an installed hrpp needs no shader files.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "kernel_names.h"

namespace hrpp {

// The SPIR-V words of kernel `name` ("trace_closest", "trace_any"); throws hrpp::Error for an
// unknown name.
std::span<const std::uint32_t> embedded_spirv(std::string_view name);
inline std::span<const std::uint32_t> embedded_spirv(Kernel k) {
  return embedded_spirv(kernel_name(k));
}

}  // namespace hrpp
