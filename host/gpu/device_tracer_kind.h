// Which device tracer (gpu/device_tracer.h) answers a command's queries (--tracer): the
// project's BVH kernels (GpuTracer) or the driver's ray queries (RayQueryTracer). Free of Vulkan,
// for the render configuration.
#pragma once

#include <cstdint>

#include "common/name_table.h"

namespace hrpp {

// Which device tracer answers a command's queries (--tracer): the project's BVH kernels
// (GpuTracer) or the driver's ray queries (RayQueryTracer).
enum class DeviceTracerKind : std::uint8_t { kCompute, kRayQuery };
inline constexpr NameTable<DeviceTracerKind, 2> kDeviceTracerNames = {
    {{DeviceTracerKind::kCompute, "compute"}, {DeviceTracerKind::kRayQuery, "rayquery"}}};

}  // namespace hrpp
