// How the GPU tracer runs its trace kernels (rays per invocation, step counting, serial mode):
// a plain configuration, free of Vulkan, so render configurations can hold it
// (render/render_config.h).
#pragma once

#include <cstdint>

namespace hrpp {

struct DeviceInfo;

struct GpuTracerConfig {
  // Most rays one kernel invocation traces before it exits (more workgroups are dispatched
  // instead); 0: the device's default, what resolved_for() fills in. Lavapipe's loop limiter
  // (docs/DEVICES.md, "Lavapipe") ends every loop of a subgroup after 65,535 iterations in
  // total, a few hundred rays' worth: on a CPU device the default is 16, which keeps a wide
  // margin and amortises an invocation's start. A GPU has no such limit and hides latency with
  // more invocations in flight: there the default is 1 (NVIDIA H200, bunny, 2^20 rays: 1.5x
  // faster AO and diffuse traces than 16; DECISIONS.md). A dispatch whose
  // rays do not all finish throws hrpp::Error naming the limit.
  std::uint32_t rays_per_invocation = 0;
  static constexpr std::uint32_t kCpuDeviceRaysPerInvocation = 16;
  static constexpr std::uint32_t kGpuRaysPerInvocation = 1;
  // The trace kernels also count the subgroup iterations of their interior-node loop
  // (TraversalCounters::interior_steps), from which lane_use() follows; off, the count is
  // compiled out (a specialization constant). The HRPP stage's trace never counts them.
  bool count_steps = false;
  // One ray per subgroup: the trace kernels visit nodes in the CPU reference's order (HRPP's
  // deterministic runs, serial, set by make_device_tracer from the predictor's
  // configuration, whose stage dispatches the same way). Not for the driver's ray queries.
  bool serial = false;

  // This configuration with the device's default rays per invocation where it asks for one.
  GpuTracerConfig resolved_for(const DeviceInfo& device) const;
};

}  // namespace hrpp
