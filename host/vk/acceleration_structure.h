// The driver's acceleration structures over a triangle soup (VK_KHR_acceleration_structure):
// one bottom-level structure of the triangles, built for fast tracing and compacted, and a
// top-level one holding a single instance of it with the identity transform. This is what a
// kernel's rayQueryEXT traverses (shaders/lib/ray_query_kernel.glsl). Needs a context with ray
// queries on (VulkanOptions::ray_query). Move-only.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

namespace hrpp {

class VulkanContext;

struct AccelerationStructureStats {
  double build_ms = 0.0;               // host wall time: upload, both builds, compaction
  std::uint64_t bytes = 0;             // bottom (compacted) and top level, as kept
  std::uint64_t uncompacted_bytes = 0;  // the bottom level before compaction, and the top
  std::uint64_t scratch_bytes = 0;      // the larger build's scratch (freed after the build)
};

class AccelerationStructure {
 public:
  // `vertices`: three per triangle, triangle i being primitive i of a query's answer; a
  // triangle whose first vertex has a NaN x is inactive (never hit). Throws hrpp::Error when the
  // context has no ray queries or a build fails.
  AccelerationStructure(VulkanContext& ctx, std::span<const glm::vec3> vertices);
  ~AccelerationStructure();
  AccelerationStructure(AccelerationStructure&&) noexcept;
  AccelerationStructure& operator=(AccelerationStructure&&) noexcept;
  AccelerationStructure(const AccelerationStructure&) = delete;
  AccelerationStructure& operator=(const AccelerationStructure&) = delete;

  // The top level: what the kernels bind.
  VkAccelerationStructureKHR top() const;
  const AccelerationStructureStats& stats() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace hrpp
